#pragma once
// Inside tactical::ImcLink (imc_link.cpp: the link's life and what it reads;
// imc_link_calls.cpp: the calls it takes and answers): what both halves use.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>

#include "imc/codec.h"
#include "protocol/message.h"

namespace strata::tactical::imc_link_detail {

inline constexpr double kEarthRadiusM = 6378137.0;  // WGS-84 semi-major axis: flat earth near the origin
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// The messages a controller reads (docs/imc.md, "What the link reads");
// everything else a vehicle sends is counted and skipped at its header.
inline bool wanted(std::uint16_t id) {
  switch (id) {
    case imc::Announce::kId:
    case imc::Heartbeat::kId:
    case imc::EstimatedState::kId:
    case imc::VehicleState::kId:
    case imc::GpsFix::kId:
    case imc::PlanControl::kId:
    case imc::PlanControlState::kId:
    case imc::FollowRefState::kId:
    case imc::LogBookEntry::kId:
    case imc::NavigationUncertainty::kId: return true;
    default: return false;
  }
}

inline std::string_view name_of(const protocol::Request& r) { return r.name; }

// Text from the vehicle, for the terminal and the log: control characters
// (an escape sequence) shown as '?', and at most 200 bytes.
inline std::string printable(std::string_view text) {
  std::string out(text.substr(0, 200));
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  }
  return out;
}

inline double wrap_deg(double d) {
  d = std::fmod(d, 360.0);
  return d < 0 ? d + 360.0 : d;
}

inline std::optional<double> number_arg(const protocol::Request& r, std::size_t i) {
  return i < r.args.size() ? r.args[i].number() : std::nullopt;
}

}  // namespace strata::tactical::imc_link_detail
