#include "vehicle/seabed.h"

#include <algorithm>
#include <cmath>

namespace strata::vehicle {

std::string_view to_string(SeabedKind kind) {
  switch (kind) {
    case SeabedKind::Flat: return "flat";
    case SeabedKind::Slope: return "slope";
    case SeabedKind::Grid: return "grid";
  }
  return "?";
}

double Seabed::depth_at(double x_m, double y_m) const {
  switch (kind) {
    case SeabedKind::Flat: return depth_m;
    case SeabedKind::Slope: return std::max(0.0, depth_m + slope_x * x_m + slope_y * y_m);
    case SeabedKind::Grid: {
      if (nx == 0 || ny == 0 || depths_m.size() != nx * ny) return depth_m;  // the reader refuses these
      // Fractional node coordinates, clamped to the grid: the edge holds outside.
      const double fi = std::clamp((x_m - x0_m) / spacing_m, 0.0, static_cast<double>(nx - 1));
      const double fj = std::clamp((y_m - y0_m) / spacing_m, 0.0, static_cast<double>(ny - 1));
      const std::size_t i = std::min(static_cast<std::size_t>(fi), nx > 1 ? nx - 2 : 0);
      const std::size_t j = std::min(static_cast<std::size_t>(fj), ny > 1 ? ny - 2 : 0);
      const double u = nx > 1 ? fi - static_cast<double>(i) : 0.0;
      const double v = ny > 1 ? fj - static_cast<double>(j) : 0.0;
      auto at = [&](std::size_t ii, std::size_t jj) {
        return depths_m[std::min(jj, ny - 1) * nx + std::min(ii, nx - 1)];
      };
      const double d0 = at(i, j) * (1.0 - u) + at(i + 1, j) * u;
      const double d1 = at(i, j + 1) * (1.0 - u) + at(i + 1, j + 1) * u;
      return d0 * (1.0 - v) + d1 * v;
    }
  }
  return depth_m;
}

}  // namespace strata::vehicle
