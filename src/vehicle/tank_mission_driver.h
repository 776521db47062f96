#pragma once
// Test support, not part of the library: drives a Simulation through the
// tank mission (missions/tank/*.coral, paper §4) the way the Strategic and
// Tactical levels will, so the model's figures (when each phase runs, how it
// ends) can be checked and the scenario files' fault times chosen.
//
// Cost model (docs/protocol.md §8, lockstep time): every primitive call is made,
// then costs one cycle; sleep(n) advances n seconds; reports cost nothing.
// The real run may differ by a cycle here and there; the figures this gives
// are estimates with that resolution.
#include <string>
#include <vector>

#include "vehicle/simulation.h"

namespace strata::vehicle::testing {

struct PhaseRun {
  int phase = 0;
  double start_s = 0.0;
  double end_s = 0.0;
  bool completed = false;  // false: aborted
  std::string why;         // "depth reached", "time out", "system problem", ...
};

struct MissionRun {
  std::vector<PhaseRun> phases;
  bool completed = false;
  double end_s = 0.0;
};

class TankMissionDriver {
 public:
  struct Setpoint {
    double depth_m;
    double timeout_s;
  };
  // The setpoints of missions/tank/setpoints.toml.
  static constexpr Setpoint kSetpoints[] = {{0.6, 30.0}, {1.5, 45.0}, {0.0, 60.0}};

  explicit TankMissionDriver(Simulation& sim) : sim_(sim) {}

  MissionRun run() {
    MissionRun m;
    const auto finish = [&](bool completed) {
      (void)call([&] { return sim_.shutdown_network().ok(); });
      m.completed = completed;
      m.end_s = sim_.time_s();
      return m;
    };
    // Phase 1: initialise.
    PhaseRun p1{1, sim_.time_s(), 0.0, false, ""};
    (void)call([&] { return sim_.start_network().ok(); });
    p1.completed = !call([&] { return sim_.system_problem(); });
    p1.why = p1.completed ? "healthy" : "system problem";
    p1.end_s = sim_.time_s();
    m.phases.push_back(p1);
    if (!p1.completed) return finish(false);
    // Phases 2 and 3: dive to a setpoint.
    for (int phase = 2; phase <= 3; ++phase) {
      m.phases.push_back(dive(phase, kSetpoints[phase - 2], phase == 2));
      if (!m.phases.back().completed) return finish(false);
    }
    m.phases.push_back(return_to_surface());
    return finish(m.phases.back().completed);
  }

 private:
  template <typename F>
  bool call(F f) {
    const bool r = f();
    sim_.step();
    return r;
  }
  void sleep(double s) { sim_.advance(s); }

  PhaseRun dive(int phase, Setpoint sp, bool check_filter) {
    PhaseRun p{phase, sim_.time_s(), 0.0, false, ""};
    (void)call([&] { return sim_.set_setpoint(sp.depth_m, sp.timeout_s).ok(); });
    if (check_filter && call([&] { return sim_.depth_filter_off(); })) {
      (void)call([&] { return sim_.start_depth_filter().ok(); });
      sleep(1.0);
    }
    (void)call([&] { return sim_.submerge().ok(); });
    (void)call([&] { return sim_.start_timer().ok(); });
    for (int guard = 0; guard < 10000; ++guard) {
      sleep(1.0);
      if (call([&] { return sim_.depth_reached(); })) {
        p.completed = true;
        p.why = "depth reached";
        break;
      }
      if (call([&] { return sim_.time_out(); })) {
        p.why = "time out";
        break;
      }
      if (call([&] { return sim_.system_problem(); })) {
        p.why = "system problem";
        break;
      }
    }
    if (!p.completed) {
      (void)call([&] { return sim_.surface().ok(); });
      for (int guard = 0; guard < 10000 && !call([&] { return sim_.surface_reached(); }); ++guard) {}
    }
    p.end_s = sim_.time_s();
    return p;
  }

  PhaseRun return_to_surface() {
    PhaseRun p{4, sim_.time_s(), 0.0, false, ""};
    const Setpoint sp = kSetpoints[2];
    (void)call([&] { return sim_.set_setpoint(sp.depth_m, sp.timeout_s).ok(); });
    (void)call([&] { return sim_.surface().ok(); });
    (void)call([&] { return sim_.start_timer().ok(); });
    for (int guard = 0; guard < 10000; ++guard) {
      sleep(1.0);
      if (call([&] { return sim_.surface_reached(); })) {
        p.completed = true;
        p.why = "surface reached";
        break;
      }
      if (call([&] { return sim_.time_out(); })) {
        p.why = "time out";
        break;
      }
    }
    p.end_s = sim_.time_s();
    return p;
  }

  Simulation& sim_;
};

}  // namespace strata::vehicle::testing
