#include "common/physics/runout_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/base/error.hpp"

namespace slide {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(rank));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double fraction = rank - static_cast<double>(below);
  return values[below] + fraction * (values[above] - values[below]);
}

SurfaceProfile surface_profile(std::span<const Vec2> points, double bin_width, double percentile_p,
                               double foundation_level) {
  SurfaceProfile profile;
  profile.bin_width = bin_width;
  // Heights of the measured particles (above the foundation level) and of all of them.
  std::vector<std::vector<double>> bins, all_bins;
  auto bin_of = [bin_width](const Vec2& x) { return static_cast<std::size_t>(x.x() / bin_width); };
  auto measured = [foundation_level](const Vec2& x) {
    return x.x() >= 0.0 && x.y() > foundation_level;
  };
  for (const Vec2& x : points) {
    if (x.x() < 0.0) continue;
    const std::size_t b = bin_of(x);
    if (b >= all_bins.size()) all_bins.resize(b + 1);
    all_bins[b].push_back(x.y());
    if (!measured(x)) continue;
    if (b >= bins.size()) bins.resize(b + 1);
    bins[b].push_back(x.y());
  }
  // The contiguous run starts at the wall; over a foundation it starts at the first bin
  // with material above the foundation level, and the bins before it (a crest that has
  // sunk below that level) get the height of all their particles.
  std::size_t first = 0;
  if (foundation_level > 0.0) {
    while (first < bins.size() && bins[first].empty()) ++first;
  }
  profile.first_above_level = first;
  std::size_t end = first;
  while (end < bins.size() && !bins[end].empty()) ++end;
  profile.height.reserve(end);
  for (std::size_t b = 0; b < end; ++b) {
    const std::vector<double>& heights = b < first ? all_bins[b] : bins[b];
    profile.height.push_back(heights.empty() ? 0.0 : percentile(heights, percentile_p));
  }
  const double limit = static_cast<double>(end) * bin_width;
  profile.x_toe = 0.0;
  for (const Vec2& x : points) {
    if (!measured(x)) continue;
    if (x.x() < limit) {
      profile.x_toe = std::max(profile.x_toe, x.x());
    } else {
      ++profile.stray_count;
    }
  }
  return profile;
}

RunoutMeasures runout_measures(const SurfaceProfile& profile, double initial_length) {
  RunoutMeasures m;
  m.x_toe = profile.x_toe;
  m.runout = profile.x_toe - initial_length;
  m.runout_normalised = m.runout / initial_length;
  m.crest_height = profile.height.empty() ? 0.0 : profile.height.front();
  return m;
}

FrontMeasures front_measures(std::span<const Vec2> points, std::span<const double> masses,
                             std::span<const double> volumes, const SurfaceProfile& profile,
                             double foundation_level, double share) {
  if (masses.size() != points.size() || volumes.size() != points.size()) {
    throw Error("front measures: {} points but {} masses, {} volumes", points.size(), masses.size(),
                volumes.size());
  }
  if (!(share > 0.0 && share < 1.0)) throw Error("front measures: share {} not in (0, 1)", share);
  std::vector<std::size_t> measured;
  double total = 0.0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (!measured_by_profile(points[p], profile, foundation_level)) continue;
    measured.push_back(p);
    total += masses[p];
  }
  FrontMeasures f;
  f.share = share;
  if (measured.empty()) return f;
  std::ranges::sort(measured,
                    [&](std::size_t a, std::size_t b) { return points[a].x() < points[b].x(); });
  // x_s: the first particle (in x) at which the mass behind, itself included, reaches s.
  double behind = 0.0;
  std::size_t k = 0;
  for (; k < measured.size(); ++k) {
    behind += masses[measured[k]];
    if (behind >= share * total) break;
  }
  f.x_front = points[measured[std::min(k, measured.size() - 1)]].x();
  double sheet_mass = 0.0, sheet_area = 0.0;
  for (std::size_t j = k + 1; j < measured.size(); ++j) {
    sheet_mass += masses[measured[j]];
    sheet_area += volumes[measured[j]];
  }
  f.sheet_length = std::max(profile.x_toe - f.x_front, 0.0);
  f.sheet_mass_share = sheet_mass / total;
  f.sheet_thickness = f.sheet_length > 0.0 ? sheet_area / f.sheet_length : 0.0;
  return f;
}

double profile_rmse(const SurfaceProfile& run, const SurfaceProfile& reference,
                    double particle_size) {
  const auto bins = std::min(reference.height.size(),
                             static_cast<std::size_t>(reference.x_toe / reference.bin_width) + 1);
  if (bins == 0) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (std::size_t b = 0; b < bins; ++b) {
    const double y_ref = reference.height[b];
    const double y = b < run.height.size() ? run.height[b] : 0.0;
    const double e = (y - y_ref) / (y_ref + particle_size);
    sum += e * e;
  }
  return std::sqrt(sum / static_cast<double>(bins));
}

bool measured_by_profile(const Vec2& x, const SurfaceProfile& profile, double foundation_level) {
  if (x.x() < 0.0) return false;
  const auto b = static_cast<std::size_t>(x.x() / profile.bin_width);
  if (b >= profile.height.size()) return false;  // beyond the toe's bin: a stray
  return b < profile.first_above_level || x.y() > foundation_level;
}

std::vector<double> stress_errors_at_rest(std::span<const Vec2> coordinates,
                                          std::span<const Vec2> velocities,
                                          std::span<const double> sigma_yy,
                                          std::span<const double> densities,
                                          const SurfaceProfile& profile, double initial_height,
                                          double foundation_level) {
  const std::size_t n = coordinates.size();
  if (velocities.size() != n || sigma_yy.size() != n || densities.size() != n) {
    throw Error("stress quality: {} coordinates but {} velocities, {} stresses, {} densities", n,
                velocities.size(), sigma_yy.size(), densities.size());
  }
  std::vector<double> errors;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& x = coordinates[i];
    if (!(velocities[i].norm() < rest_speed) ||
        !measured_by_profile(x, profile, foundation_level)) {
      continue;
    }
    // The weight of the column of deposit between the particle and the surface above it.
    const double h_b = profile.height[static_cast<std::size_t>(x.x() / profile.bin_width)];
    const double rho_g = densities[i] * gravity_acceleration;
    const double lithostatic = -rho_g * (h_b - x.y());
    errors.push_back(std::abs(sigma_yy[i] - lithostatic) / (rho_g * initial_height));
  }
  return errors;
}

StressQuality stress_quality_at_rest(std::span<const Vec2> coordinates,
                                     std::span<const Vec2> velocities,
                                     std::span<const double> sigma_yy,
                                     std::span<const double> densities,
                                     const SurfaceProfile& profile, double initial_height,
                                     double foundation_level) {
  const std::vector<double> errors = stress_errors_at_rest(
      coordinates, velocities, sigma_yy, densities, profile, initial_height, foundation_level);
  StressQuality q;
  q.deposit_count = errors.size();
  if (errors.empty()) return q;
  q.p50 = percentile(errors, 50.0);
  q.p90 = percentile(errors, 90.0);
  q.p99 = percentile(errors, 99.0);
  q.max = *std::max_element(errors.begin(), errors.end());
  return q;
}

}  // namespace slide
