#include "common/run/stability_guard.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace slide::run {

std::optional<std::string> energy_growth(double total_energy, const EnergyReference& reference,
                                         const std::string& parts) {
  const double growth = total_energy - reference.initial_energy;
  const double scale = std::max(reference.energy_scale, 1e-300);
  if (std::isfinite(total_energy) && growth <= energy_growth_tolerance * scale) return std::nullopt;
  return fmt::format(
      "total energy{} grew by {:.4g} J/m ({:.3g} % of the releasable energy {:.4g} J/m, "
      "tolerance {:.3g} %)",
      parts.empty() ? "" : " (" + parts + ")", growth, 100.0 * growth / scale,
      reference.energy_scale, 100.0 * energy_growth_tolerance);
}

}  // namespace slide::run
