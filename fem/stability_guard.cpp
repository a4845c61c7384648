#include "fem/stability_guard.hpp"

#include <cmath>

#include <fmt/format.h>

namespace slide::fem {

namespace {

bool finite(const Vec2& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y());
}
bool finite(const Vec4& v) {
  return v.allFinite();
}

std::string check_finite(const FemModel& model, const FemState& state,
                         std::span<const Vec2> coordinates) {
  const auto when = fmt::format("t = {:.4f} s (step {})", state.time, state.step);
  for (std::size_t n = 0; n < state.velocity.size(); ++n) {
    if (!finite(state.velocity[n]) || !finite(state.displacement[n])) {
      return fmt::format(
          "non-finite velocity or displacement at node {} (X = {:.3f}, {:.3f}) at {}", n,
          model.mesh.nodes[n].x(), model.mesh.nodes[n].y(), when);
    }
  }
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
    if (!finite(state.stress[gp])) {
      const auto e = static_cast<Index>(gp / n_gauss);
      const Vec2 x = map_to_physical(model.mesh.shape(), model.mesh.element_nodes(e, coordinates),
                                     model.rule.local[gp % n_gauss]);
      return fmt::format(
          "non-finite stress at Gauss point {} of element {} (x = {:.3f}, {:.3f}) at {}", gp, e,
          x.x(), x.y(), when);
    }
  }
  for (std::size_t e = 0; e < state.hourglass_force.size(); ++e) {
    if (!finite(state.hourglass_force[e])) {
      return fmt::format("non-finite hourglass force in element {} at {}", e, when);
    }
  }
  return {};
}

}  // namespace

std::string check_stability(const FemModel& model, const FemState& state,
                            std::span<const Vec2> coordinates, double total_energy,
                            const GuardLimits& limits) {
  std::string finite_problem = check_finite(model, state, coordinates);
  if (!finite_problem.empty()) return "instability: " + finite_problem;
  for (std::size_t n = 0; n < state.velocity.size(); ++n) {
    const double speed = state.velocity[n].norm();
    if (speed > limits.speed_limit) {
      return fmt::format(
          "instability: node {} at x = ({:.3f}, {:.3f}) moves at {:.4g} m/s, above the speed "
          "limit {:.4g} m/s (fem.speed_limit_factor × sqrt(2 g H)) at t = {:.4f} s (step {})",
          n, coordinates[n].x(), coordinates[n].y(), speed, limits.speed_limit, state.time,
          state.step);
    }
  }
  if (const auto growth = run::energy_growth(total_energy, limits.energy)) {
    return fmt::format("instability: {} at t = {:.4f} s (step {})", *growth, state.time,
                       state.step);
  }
  return {};
}

}  // namespace slide::fem
