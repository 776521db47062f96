#include "coral/witness.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "coral/verify_report.h"

namespace strata::coral {

std::vector<TraceStep> trace_of(const Program& program, const AnalysisNet& an,
                                const std::vector<petri::TransitionId>& path) {
  std::vector<TraceStep> steps;
  steps.reserve(path.size());
  for (petri::TransitionId t : path) steps.push_back(trace_step(program, an, t));
  return steps;
}

std::size_t answer_count(const std::vector<TraceStep>& steps) {
  return static_cast<std::size_t>(
      std::count_if(steps.begin(), steps.end(), [](const TraceStep& s) { return s.kind == TraceStep::Kind::Answer; }));
}

nlohmann::ordered_json witness_answers_json(const std::string& mission, const std::string& net, const std::string& from,
                                            const std::vector<TraceStep>& steps) {
  // Which firing issued each answered action: per (transition, action), the
  // firings not yet answered, earliest first.
  std::map<std::string, std::vector<std::size_t>> fired;                // transition -> its firing steps
  std::map<std::pair<std::string, std::string>, std::size_t> answered;  // (transition, action) -> answers so far
  struct Entry {
    std::size_t issued = 0, action = 0, step = 0;
  };
  std::vector<Entry> order;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const TraceStep& s = steps[i];
    if (s.kind == TraceStep::Kind::Fire) {
      fired[s.transition].push_back(i);
      continue;
    }
    const auto& firings = fired[s.transition];
    std::size_t& n = answered[{s.transition, s.action}];
    // A path answers only what a firing issued, so a firing is there.
    const std::size_t issued = n < firings.size() ? firings[n] : i;
    ++n;
    const TraceStep& issuer = steps[issued];
    const auto at = std::find(issuer.actions.begin(), issuer.actions.end(), s.action);
    order.push_back({issued, static_cast<std::size_t>(at - issuer.actions.begin()), i});
  }
  std::stable_sort(order.begin(), order.end(), [](const Entry& a, const Entry& b) {
    return std::tie(a.issued, a.action) < std::tie(b.issued, b.action);
  });
  nlohmann::ordered_json answers = nlohmann::ordered_json::array();
  for (const Entry& e : order) {
    const TraceStep& s = steps[e.step];
    nlohmann::ordered_json a;
    a["step"] = e.step + 1;
    a["net"] = net;
    a["transition"] = s.transition;
    a["action"] = s.tactic;
    a["primitive"] = s.primitive;
    if (s.tactic == "phase") {
      a["answer"] = s.answer;
    } else {
      a["answer"] = s.answer == "1" ? 1 : 0;
    }
    answers.push_back(std::move(a));
  }
  nlohmann::ordered_json path = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < steps.size(); ++i) path.push_back(std::to_string(i + 1) + ". " + step_text(steps[i]));
  nlohmann::ordered_json j;
  j["strata_answers"] = kAnswersFormatVersion;
  j["mission"] = mission;
  j["net"] = net;
  j["from"] = from;
  j["answers"] = std::move(answers);
  j["path"] = std::move(path);
  return j;
}

}  // namespace strata::coral
