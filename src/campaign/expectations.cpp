#include "campaign/expectations.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace strata::campaign {

namespace {

Check bound_check(const ExpectationSet& set, const Observation& seen, const BoundProof* proof) {
  Check c{"bound", true, nullptr, nullptr, ""};
  const std::string to = set.bound->text.substr(set.bound->text.find("->") + 2);
  const std::string_view to_words = std::string_view(to).substr(std::min(to.size(), to.find_first_not_of(' ')));
  if (proof != nullptr && proof->worst_s) c.limit = *proof->worst_s;
  if (!seen.fault_at_s) {
    c.note = "no fault in this case";
    return c;
  }
  if (!seen.fault_reached) {
    c.note = fmt::format("the run ended ({:.1f} s) before the fault", seen.sim_time_s);
    return c;
  }
  if (seen.bound_to_at_s) c.figure = std::round((*seen.bound_to_at_s - *seen.fault_at_s) * 1e6) / 1e6;
  if (proof == nullptr || proof->measured_only) {
    c.note = proof != nullptr ? proof->why : "no proof was made";
    return c;
  }
  if (!proof->worst_s) {
    c.pass = false;
    c.note = "no proven bound: " + proof->why;
    return c;
  }
  const double worst = *proof->worst_s;
  if (seen.bound_to_at_s) {
    c.pass = c.figure.get<double>() <= worst + 1e-6;
    if (!c.pass) {
      c.note = fmt::format(
          "{} came {:.1f} s after the fault, past the proven worst case of {:.1f} s: the timing "
          "analysis is unsound",
          to_words, c.figure.get<double>(), worst);
    }
    return c;
  }
  const double ran_after = seen.sim_time_s - *seen.fault_at_s;
  if (seen.bound_to_before_s) {
    c.note = fmt::format("{} came at {:.1f} s, before the fault: the mission was already reacting", to_words,
                         *seen.bound_to_before_s);
  } else if (proof->ends_without) {
    c.note = fmt::format("the run ended without {} after the fault, as the analysis allows", to_words);
  } else if (ran_after <= worst + 1e-6) {
    c.note = fmt::format("the run ended {:.1f} s after the fault, within the proven {:.1f} s", ran_after, worst);
  } else {
    c.pass = false;
    c.note = fmt::format(
        "no {} in the {:.1f} s the run went on after the fault, past the proven worst case of {:.1f} "
        "s: the timing analysis is unsound",
        to_words, ran_after, worst);
  }
  return c;
}

}  // namespace

std::vector<Check> evaluate(const ExpectationSet& set, const Observation& seen, const BoundProof* proof) {
  std::vector<Check> checks;
  const bool ran = seen.outcome != "error" && seen.outcome != "crashed";
  checks.push_back({"ran", ran, seen.outcome, nullptr, ran ? "" : seen.reason});
  if (!ran) return checks;
  if (seen.answers_used) {
    const bool followed = *seen.answers_used == seen.answers_total && seen.answers_diverged.empty();
    std::string note = seen.answers_diverged;
    if (note.empty() && !followed) note = "the run ended before " + seen.answers_first_unused;
    checks.push_back({"answers_followed", followed, *seen.answers_used, seen.answers_total, note});
  }
  if (!set.outcomes.empty()) {
    const bool ok = std::find(set.outcomes.begin(), set.outcomes.end(), seen.outcome) != set.outcomes.end();
    checks.push_back({"outcome", ok, seen.outcome, set.outcomes, ok ? "" : seen.reason});
  }
  if (set.surface_within_s) {
    Check c{"surface_within_s", true, nullptr, *set.surface_within_s, ""};
    if (!seen.fault_at_s) {
      c.note = "no fault in this case";
    } else if (!seen.fault_reached) {
      c.note = fmt::format("the run ended ({:.1f} s) before the fault", seen.sim_time_s);
    } else if (!seen.time_to_surface_s) {
      c.pass = false;
      c.note = "the vehicle was not seen at the surface after the fault";
    } else {
      c.figure = *seen.time_to_surface_s;
      c.pass = *seen.time_to_surface_s <= *set.surface_within_s;
      c.note =
          seen.surface_seen == "final state" ? "at most: seen at the surface only in the vehicle's final state" : "";
    }
    checks.push_back(std::move(c));
  }
  if (set.max_depth_m) {
    Check c{"max_depth_m", true, nullptr, *set.max_depth_m, ""};
    if (seen.max_depth_m) {
      c.figure = *seen.max_depth_m;
      c.pass = *seen.max_depth_m <= *set.max_depth_m;
    } else {
      c.note = "no depth was heard";
    }
    checks.push_back(std::move(c));
  }
  if (set.no_stall) {
    checks.push_back({"no_stall", !seen.stalled, seen.stalled, false, seen.stalled ? seen.reason : ""});
  }
  if (!set.guard.empty()) {
    Check c{"guard", true, nullptr, set.guard_within_s ? nlohmann::ordered_json(*set.guard_within_s) : nullptr, ""};
    if (!seen.fault_at_s) {
      c.note = "no fault in this case";
    } else if (!seen.fault_reached) {
      c.note = fmt::format("the run ended ({:.1f} s) before the fault", seen.sim_time_s);
    } else {
      auto trip = std::find_if(seen.guard_trips.begin(), seen.guard_trips.end(), [&](const auto& g) {
        return g.first == set.guard && g.second >= *seen.fault_at_s - 1e-9;
      });
      if (trip == seen.guard_trips.end()) {
        c.pass = false;
        c.note = seen.guard_trips.empty() ? fmt::format("guard {} never tripped", set.guard)
                                          : fmt::format("guard {} never tripped after the fault ({} did)", set.guard,
                                                        seen.guard_trips.front().first);
      } else {
        const double after = std::max(0.0, trip->second - *seen.fault_at_s);
        c.figure = std::round(after * 1000.0) / 1000.0;
        c.pass = !set.guard_within_s || after <= *set.guard_within_s + 1e-9;
      }
    }
    checks.push_back(std::move(c));
  }
  if (set.bound) checks.push_back(bound_check(set, seen, proof));
  if (set.no_refused_exec) {
    checks.push_back({"no_refused_exec", seen.refused_execs == 0, seen.refused_execs, 0, seen.first_refused});
  }
  return checks;
}

nlohmann::ordered_json to_json(const Check& check) {
  nlohmann::ordered_json j;
  j["name"] = check.name;
  j["pass"] = check.pass;
  j["figure"] = check.figure;
  if (!check.limit.is_null()) j["limit"] = check.limit;
  if (!check.note.empty()) j["note"] = check.note;
  return j;
}

}  // namespace strata::campaign
