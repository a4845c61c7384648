// Pressure-independent multi-yield plasticity: the backbone as elastic–perfectly-plastic
// components, their update and their initialisation (the formulas: multi_yield.hpp and
// common/physics/constitutive.md).
#include "common/physics/multi_yield.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace slide::multi_yield {

namespace {

/// The deviatoric part [sxx, syy, szz, sxy] of a stress, and its mean σm = tr σ / 3.
Vec4 deviator(const Vec4& stress, double& mean) {
  mean = (stress[0] + stress[1] + stress[2]) / 3.0;
  return {stress[0] - mean, stress[1] - mean, stress[2] - mean, stress[3]};
}

Vec4 with_mean(const Vec4& deviatoric, double mean) {
  return {deviatoric[0] + mean, deviatoric[1] + mean, deviatoric[2] + mean, deviatoric[3]};
}

/// Components of the hyperbolic backbone in units of τ_f (stress) and τ_f/G (strain):
/// vertices at τ̂_i = i/N, strains γ̂_i = τ̂_i γ̂_r / (γ̂_r − τ̂_i) on the hyperbola with
/// γ̂_r = G γ_r / τ_f = 1/(1 − ρ), ρ = τ_f/(G γ_peak). The secant slope between vertices
/// i and i+1 is (1/N)/(γ̂_{i+1} − γ̂_i) = (γ̂_r − τ̂_i)(γ̂_r − τ̂_{i+1})/γ̂_r² (no division
/// per segment). Writes Ĝ_i and the τ̂ at each component's limit. This runs at every
/// update of every point (the components depend on the point's frozen strength), so it
/// is one pass without temporaries.
void normalised_components(double rho, int n, std::array<double, max_yield_surfaces>& modulus,
                           std::array<double, max_yield_surfaces>& limit) {
  const double reference = 1.0 / (1.0 - rho);  // γ̂_r
  const double inverse_square = 1.0 / (reference * reference);
  const double step = 1.0 / n;
  const double first_strain = step * reference / (reference - step);  // γ̂_1
  double slope_before = 1.0;                                          // elastic up to τ̂_1
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double tau = (i + 1) * step;
    const double strain = tau * reference / (reference - tau);
    const double slope_after =
        i < n - 1 ? (reference - tau) * (reference - tau - step) * inverse_square : 0.0;
    // Vertex i sits at γ̃ = τ̂_1 + γ̂_i − γ̂_1 (elastic to τ̂_1, the secants after).
    modulus[k] = slope_before - slope_after;
    limit[k] = modulus[k] * (step + strain - first_strain);
    slope_before = slope_after;
  }
}

}  // namespace

Components components(double shear_modulus, double peak_strength, double peak_shear_strain,
                      int count) {
  Components c;
  c.count = std::clamp(count, 1, max_yield_surfaces);
  const auto last = static_cast<std::size_t>(c.count - 1);
  const double tau_f = std::numbers::sqrt2 / 3.0 * std::max(peak_strength, 0.0);  // octahedral
  const double rho = tau_f / (shear_modulus * peak_shear_strain);
  if (!(tau_f > 0.0) || rho >= 1.0 || c.count == 1) {
    // One elastic–perfectly-plastic component carries all of G (or no strength at all).
    std::fill_n(c.two_shear.begin(), last, 0.0);
    std::fill_n(c.limit.begin(), last, 0.0);
    c.two_shear[last] = 2.0 * shear_modulus;
    c.limit[last] = std::max(peak_strength, 0.0);
    std::fill_n(c.limit_squared.begin(), last, 0.0);
    c.limit_squared[last] = c.limit[last] * c.limit[last];
    return c;
  }
  std::array<double, max_yield_surfaces> modulus, limit;  // the first `count` are set
  normalised_components(rho, c.count, modulus, limit);
  // τ̂ in units of τ_f is k_i in units of q_f (both scale by 3/√2 to q).
  for (std::size_t k = 0; k <= last; ++k) {
    c.two_shear[k] = 2.0 * shear_modulus * modulus[k];
    c.limit[k] = peak_strength * limit[k];
    c.limit_squared[k] = c.limit[k] * c.limit[k];
  }
  return c;
}

bool update(const Components& c, double bulk_modulus, double shear_modulus, Vec4& stress,
            MaterialState& state, const Vec4& strain_increment, std::span<Vec4> surfaces) {
  const double volumetric = strain_increment[0] + strain_increment[1] + strain_increment[2];
  // Deviatoric strain increment, tensor components (Δexy = Δγxy/2).
  const Vec4 de(strain_increment[0] - volumetric / 3.0, strain_increment[1] - volumetric / 3.0,
                strain_increment[2] - volumetric / 3.0, 0.5 * strain_increment[3]);
  double mean = 0.0;
  const Vec4 previous = deviator(stress, mean);
  Vec4 sum = Vec4::Zero();
  bool at_peak = false;
  const int count = c.count;  // a local: the stores to `surfaces` could otherwise alias it
  for (int i = 0; i < count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    Vec4 s = surfaces[k] + c.two_shear[k] * de;
    // q² = 3/2 s:s, the squares taken two at a time: (sxx², syy²) and (szz², 2 sxy²).
    const Eigen::Array2d squares = s.head<2>().array().square();
    const Eigen::Array2d rest =
        s.tail<2>().array() * (s.tail<2>().array() * Eigen::Array2d(1.0, 2.0));
    const double q2 = 1.5 * (squares[0] + squares[1] + rest[0] + rest[1]);
    if (q2 > c.limit_squared[k]) {
      s *= c.limit[k] / std::sqrt(q2);
      at_peak = i == count - 1;
    }
    surfaces[k] = s;
    sum += s;
  }
  stress = with_mean(sum, mean + bulk_modulus * volumetric);
  // Δeᵖ = Δe − Δs/(2G), εq-type measure sqrt(2/3 Δeᵖ:Δeᵖ).
  const Vec4 plastic = de - (sum - previous) / (2.0 * shear_modulus);
  const double pp = plastic[0] * plastic[0] + plastic[1] * plastic[1] + plastic[2] * plastic[2] +
                    2.0 * plastic[3] * plastic[3];
  state.plastic_shear_strain += std::sqrt(2.0 / 3.0 * pp);
  return at_peak;
}

bool load_monotonically(const Components& c, Vec4& stress, std::span<Vec4> surfaces) {
  double mean = 0.0;
  const Vec4 s = deviator(stress, mean);
  const double q = von_mises(s);
  double peak = 0.0;
  for (int i = 0; i < c.count; ++i) peak += c.limit[static_cast<std::size_t>(i)];
  if (!(q > 0.0)) {
    for (int i = 0; i < c.count; ++i) surfaces[static_cast<std::size_t>(i)].setZero();
    return false;
  }
  // The equivalent strain εq at which the backbone reaches q: components yield in order
  // of their vertices, so walk along them until the stress is passed.
  double carried = 0.0;    // Σ k_j of the components at their limit
  double stiffness = 0.0;  // Σ 3 G_j of those still elastic
  for (int i = 0; i < c.count; ++i) stiffness += 1.5 * c.two_shear[static_cast<std::size_t>(i)];
  double eps = std::numeric_limits<double>::infinity();
  for (int i = 0; i < c.count && q < peak; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!(c.two_shear[k] > 0.0)) continue;
    const double vertex = c.limit[k] / (1.5 * c.two_shear[k]);
    if (carried + stiffness * vertex >= q) {
      eps = (q - carried) / stiffness;
      break;
    }
    carried += c.limit[k];
    stiffness -= 1.5 * c.two_shear[k];
  }
  const double scale = q < peak ? 1.0 : peak / q;
  for (int i = 0; i < c.count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double carried_k =
        c.two_shear[k] > 0.0 ? std::min(1.5 * c.two_shear[k] * eps, c.limit[k]) : 0.0;
    surfaces[k] = (carried_k / q) * s;
  }
  if (q < peak) {
    // Σ s_i is s up to round-off; keep the stress exactly as it was.
    return false;
  }
  stress = with_mean(scale * s, mean);
  return true;
}

bool reconcile(const Components& c, Vec4& stress, std::span<Vec4> surfaces) {
  double mean = 0.0;
  const Vec4 s = deviator(stress, mean);
  Vec4 sum = Vec4::Zero();
  for (int i = 0; i < c.count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double q = von_mises(surfaces[k]);
    if (q > c.limit[k]) surfaces[k] *= c.limit[k] / q;
    sum += surfaces[k];
  }
  const double scale = std::max(von_mises(s), std::abs(mean));
  const bool changed = (sum - s).cwiseAbs().maxCoeff() > 1e-9 * scale;
  stress = with_mean(sum, mean);
  return changed;
}

}  // namespace slide::multi_yield
