#include "campaign/bound.h"

#include <map>
#include <mutex>
#include <tuple>

#include <fmt/format.h>

#include "run/bound_options.h"
#include "run/coral_load.h"

namespace strata::campaign {
namespace {

constexpr double kDefaultDepthM = 6.0;  // strata verify --depth-max's default

BoundProof prove(const std::string& mission, const coral::BoundQuery& q, double ascent_s) {
  BoundProof proof;
  const tactical::Catalogue& cat = tactical::Catalogue::builtin();
  run::CoralLoad load = run::load_coral_file(mission, cat);
  if (!load.program) {
    proof.why = "the mission does not compile";
    return proof;
  }
  coral::BoundOptions options = run::bound_options(cat);
  options.ascent_s = ascent_s;
  const coral::BoundAnswer a = coral::analyse_bound(*load.program, q, options);
  if (a.verdict == coral::BoundAnswer::Verdict::Bounded) {
    proof.worst_s = a.worst_s;
    proof.ends_without = a.ends_without;
  } else {
    proof.why = std::string(coral::bound_verdict_name(a.verdict)) + (a.message.empty() ? "" : ": " + a.message);
  }
  return proof;
}

}  // namespace

double bound_depth_m(const ExpectationSet& set) { return set.max_depth_m.value_or(kDefaultDepthM); }

BoundProof proven_bound(const Spec& spec, std::size_t mission, const ExpectationSet& set,
                        const vehicle::VehicleParams& params) {
  const Mission& m = spec.missions.at(mission);
  if (m.kind != MissionKind::Coral) {
    BoundProof proof;
    proof.measured_only = true;
    proof.why = "PROLOG rules: no timing analysis, the time is only measured";
    return proof;
  }
  const coral::BoundQuery& q = *set.bound;
  // The ascent changes the answer only for a bound to the surface.
  const double ascent_s =
      q.to == coral::BoundQuery::To::Surface ? run::ascent_estimate_s(params, bound_depth_m(set)) : 0.0;
  static std::mutex mutex;
  static std::map<std::tuple<std::string, std::string, double>, BoundProof> proofs;
  const auto key = std::make_tuple(m.resolved, q.text, ascent_s);
  std::lock_guard lock(mutex);
  auto it = proofs.find(key);
  if (it == proofs.end()) it = proofs.emplace(key, prove(m.resolved, q, ascent_s)).first;
  return it->second;
}

}  // namespace strata::campaign
