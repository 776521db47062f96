#pragma once
// Stable text forms of nets and markings, for tests and `strata dump`.
#include <string>

#include "petri/net.h"

namespace strata::petri {

// One line per place ("place NAME = N"), then one per transition
// ("transition NAME [priority K]: in{a, b*2} out{c}"), in declaration order.
std::string dump_net(const Net& net);

// Non-empty places in declaration order: "start:1 diving:2"; "(empty)" if none.
std::string dump_marking(const Net& net, const Marking& m);

// The incidence matrix C = Post - Pre, one row per place, for small nets.
std::string dump_incidence(const Net& net);

}  // namespace strata::petri
