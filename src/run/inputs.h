#pragma once
// The inputs of a run as commands name them: a catalogue file or the built-in
// one, a scenario by name or path, a vehicle address.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include "core/result.h"
#include "tactical/catalogue.h"
#include "vehicle/scenario.h"

namespace strata::run {

// "PORT" or "ADDRESS:PORT" (ADDRESS defaults to 127.0.0.1; IPv4 only).
core::Result<std::pair<std::string, std::uint16_t>> parse_listen(const std::string& text);
// --catalogue: the built-in catalogue when empty, else the file.
core::Result<tactical::Catalogue> load_catalogue_option(const std::string& path);
// --scenario: the mission's scenarios/nominal.toml (else no faults) when
// empty; a path; or NAME in the mission's scenarios/.
core::Result<vehicle::Scenario> load_scenario_option(const std::string& scenario, const std::string& mission);
// The same with every file read through `read` (RunOptions::read_file):
// "" is the mission's scenarios/nominal.toml when `read` finds one (Io: it
// is not there), else the built-in nominal; anything else is a path.
core::Result<vehicle::Scenario> load_scenario_through(
    const std::function<core::Result<std::string>(const std::string&)>& read, const std::string& scenario,
    const std::string& mission);

}  // namespace strata::run
