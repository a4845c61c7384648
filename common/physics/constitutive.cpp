// Linear elasticity and Mohr–Coulomb plasticity with a tension cut-off, plane strain,
// tension positive (docs/method.md §2, §3; the equations and the return regions are written
// out in common/physics/constitutive.md).
//
// The Mohr–Coulomb return works in principal stresses, after Clausen, Damkilde &
// Andersen (Int. J. Numer. Meth. Engng 66 (2006) 1036–1059; Computers & Structures 85
// (2007) 1795–1807): every yield function is linear in the sorted principal stresses
// σ1 ≥ σ2 ≥ σ3, so for a set S of active planes the backward-Euler return
//     σ = σ_trial − Σ_j Δλ_j D b_j  with  f_i(σ) = 0 (i ∈ S)
// is one small linear system, Σ_j (a_iᵀ D b_j) Δλ_j = f_i(σ_trial), solved exactly.
// The candidates are tried in order of increasing complexity (plane, edges, corners);
// the first whose multipliers are ≥ 0 and whose stress is admissible under the true
// (re-sorted) yield functions satisfies the Kuhn–Tucker conditions and is the return.
// The Mohr–Coulomb apex, or the tension corners when the cut-off truncates it, close the
// list and are always admissible. The principal directions (the in-plane eigenvectors
// and the z axis) do not change in the return.
#include "common/physics/constitutive.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/base/error.hpp"
#include "common/base/pair.hpp"
#include "common/physics/liquefaction.hpp"
#include "common/physics/multi_yield.hpp"

namespace slide {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double infinity = std::numeric_limits<double>::infinity();

/// Relative tolerance of the yield test and of the candidate checks, against a stress
/// scale of the trial (so a stress that a return left on the surface is admissible).
constexpr double yield_tolerance = 1e-12;

/// The Mohr–Coulomb apex c cot φ in the form that makes f vanish there exactly,
/// 2c sqrt(Nφ)/(Nφ − 1); +∞ for φ = 0 (Tresca has no apex).
double apex_stress(double n_phi, double k) {
  return n_phi > 1.0 ? k / (n_phi - 1.0) : infinity;
}

/// The Mohr–Coulomb constants one return needs, gathered once per call.
struct MohrCoulomb {
  double lambda;                      // Lamé λ
  double shear;                       // G
  double n_phi;                       // Nφ
  double n_psi;                       // Nψ
  double k;                           // 2c sqrt(Nφ)
  double tension;                     // T ≤ apex
  const MohrCoulombReturns& returns;  // the model's return constants

  /// c cot φ = k/(Nφ − 1), +∞ for φ = 0 (apex_stress).
  double apex() const;
  /// The cut-off is a separate surface only below the apex; at the apex the
  /// Mohr–Coulomb pyramid already implies σ1 ≤ T.
  bool has_tension_cutoff() const { return tension < apex(); }
  bool has_apex() const { return apex() < infinity && !has_tension_cutoff(); }
};

double MohrCoulomb::apex() const {
  return apex_stress(n_phi, k);
}

/// A plane-strain stress's principal values as the elastic test finds them: the in-plane
/// eigenvalues c ± r of the 2×2 block (with ½(σxx − σyy), which with σxy gives their
/// direction), and σ1 = max(c + r, σzz), σ3 = min(c − r, σzz).
struct PrincipalBounds {
  double centre;
  double half_difference;
  double radius;
  double sigma_1;
  double sigma_3;
};

inline PrincipalBounds principal_bounds(const Vec4& s) {
  const double centre = 0.5 * (s[0] + s[1]);
  const double half_difference = 0.5 * (s[0] - s[1]);
  const double radius = std::sqrt(half_difference * half_difference + s[3] * s[3]);
  return {centre, half_difference, radius, std::max(centre + radius, s[2]),
          std::min(centre - radius, s[2])};
}

/// Largest of the Mohr–Coulomb and tension functions for given σ1, σ3.
inline double yield_value(double n_phi, double k, double tension, double sigma_1, double sigma_3) {
  return std::max(n_phi * sigma_1 - sigma_3 - k, sigma_1 - tension);
}

/// Stress scale for the tolerances: the size of the terms that make up f.
inline double stress_scale(double n_phi, double k, double sigma_1, double sigma_3) {
  return (n_phi + 1.0) * std::max(std::abs(sigma_1), std::abs(sigma_3)) + k;
}

/// The elastic test: f ≤ 0 for both functions, within round-off of the surface (so that a
/// stress a return left on it stays put). A square root and a few comparisons.
inline bool admissible(const PrincipalBounds& p, double n_phi, double k, double tension) {
  return yield_value(n_phi, k, tension, p.sigma_1, p.sigma_3) <=
         yield_tolerance * stress_scale(n_phi, k, p.sigma_1, p.sigma_3);
}

/// The full principal decomposition: the sorted values, where the in-plane major value,
/// the in-plane minor value and σzz went among them, and the in-plane direction of the
/// major axis as (cos 2θ, sin 2θ), which is all a rebuild with the same principal
/// directions needs (no trigonometric function is evaluated).
struct PrincipalStress {
  Vec3 sigma;  // σ1 ≥ σ2 ≥ σ3
  int major_slot;
  int minor_slot;
  int z_slot;
  double cos_2theta;
  double sin_2theta;
};

/// The decomposition of a stress `s` whose bounds `b` the elastic test found.
PrincipalStress principal_stress(const PrincipalBounds& b, const Vec4& s) {
  const double major = b.centre + b.radius;
  const double minor = b.centre - b.radius;
  PrincipalStress p{};
  if (b.radius > 0.0) {
    p.cos_2theta = b.half_difference / b.radius;
    p.sin_2theta = s[3] / b.radius;
  } else {  // in-plane isotropic: every direction is principal, take x
    p.cos_2theta = 1.0;
    p.sin_2theta = 0.0;
  }
  // major ≥ minor, so σzz goes above, between or below them.
  p.z_slot = s[2] >= major ? 0 : (s[2] >= minor ? 1 : 2);
  p.major_slot = p.z_slot == 0 ? 1 : 0;
  p.minor_slot = p.z_slot == 2 ? 1 : 2;
  // By value, not by slot: three stores at computed slots, then the return's loads of
  // them as pairs, stalled (no store forwarding across two stores).
  p.sigma =
      Vec3(p.z_slot == 0 ? s[2] : major, p.z_slot == 1 ? s[2] : (p.z_slot == 0 ? major : minor),
           p.z_slot == 2 ? s[2] : minor);
  return p;
}

/// The stress vector with principal values `sigma` (in the slots of `p`) on the
/// principal directions of `p`.
Vec4 rebuild(const PrincipalStress& p, const Vec3& sigma) {
  const double centre = 0.5 * (sigma[p.major_slot] + sigma[p.minor_slot]);
  const double radius = 0.5 * (sigma[p.major_slot] - sigma[p.minor_slot]);
  return {centre + radius * p.cos_2theta, centre - radius * p.cos_2theta, sigma[p.z_slot],
          radius * p.sin_2theta};
}

/// The yield planes in sorted principal space, f = aᵀσ − level ≤ 0, with the gradient b
/// of the plastic potential. The second and third Mohr–Coulomb planes are the main one
/// with σ2 taking the place of σ1 or of σ3: they become active on the edges σ1 = σ2 and
/// σ2 = σ3, where the sorted order would otherwise be violated.
enum Surface : int { mc, mc_2_major, mc_2_minor, tension_1, tension_2, tension_3 };

struct Plane {
  Vec3 normal;  // a = ∂f/∂σ
  Vec3 flow;    // b = ∂g/∂σ
  double level;
};

using Planes = std::array<Plane, 6>;

Planes yield_planes(double n_phi, double n_psi, double k, double t) {
  return {{
      {{n_phi, 0.0, -1.0}, {n_psi, 0.0, -1.0}, k},
      {{0.0, n_phi, -1.0}, {0.0, n_psi, -1.0}, k},
      {{n_phi, -1.0, 0.0}, {n_psi, -1.0, 0.0}, k},
      {{1.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, t},
      {{0.0, 1.0, 0.0}, {0.0, 1.0, 0.0}, t},
      {{0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}, t},
  }};
}

Planes yield_planes(const MohrCoulomb& m) {
  return yield_planes(m.n_phi, m.n_psi, m.k, m.tension);
}

/// D b for D = λ 11ᵀ + 2G I: the stress a unit multiplier of flow b takes off.
Vec3 stiffness_times(double lambda, double shear, const Vec3& b) {
  return (lambda * b.sum()) * Vec3::Ones() + (2.0 * shear) * b;
}

/// The edges of the main plane, in MohrCoulombReturns::edges, with their second plane.
enum Edge : int { edge_2_3, edge_1_2 };
constexpr std::array<Surface, 2> second_plane{mc_2_minor, mc_2_major};

/// The constants of a return that depend on the elastic constants and Nφ, Nψ only
/// (MohrCoulombReturns); a model computes them once, return_to the same numbers for the
/// other sets of planes in every return.
MohrCoulombReturns return_constants(double lambda, double shear, double n_phi, double n_psi) {
  const Planes planes = yield_planes(n_phi, n_psi, 0.0, 0.0);
  const Vec3 main_flow = stiffness_times(lambda, shear, planes[mc].flow);
  MohrCoulombReturns r;
  // head<3>() rather than a comma initializer: with AVX, GCC 12 warns (-Warray-bounds)
  // on the initializer's dynamic-size copy path, which a 3-vector never takes.
  r.main_plane.head<3>() = main_flow;
  r.main_plane[3] = 1.0 / planes[mc].normal.dot(main_flow);
  r.main_normal = planes[mc].normal;
  r.main_flow = planes[mc].flow;
  r.main_flow_trace = r.main_flow.sum();
  const Vec3 deviatoric_flow = r.main_flow - (r.main_flow_trace / 3.0) * Vec3::Ones();
  r.main_flow_shear = std::sqrt(2.0 / 3.0 * deviatoric_flow.squaredNorm());
  for (const Edge edge : {edge_2_3, edge_1_2}) {
    const Plane& second = planes[second_plane[edge]];
    const Vec3 flow = stiffness_times(lambda, shear, second.flow);
    Eigen::Matrix2d a_d_b;
    a_d_b << planes[mc].normal.dot(main_flow), planes[mc].normal.dot(flow),
        second.normal.dot(main_flow), second.normal.dot(flow);
    r.edges[edge] = {flow, a_d_b.inverse(), second.normal, second.flow};
  }
  return r;
}

/// One candidate return: the stress, the plastic strain (principal), and how well it
/// meets the Kuhn–Tucker conditions.
struct Candidate {
  Vec3 sigma;
  Vec3 plastic_strain;
  double smallest_multiplier;  // min_j Δλ_j / Σ|Δλ_j|
  double violation;            // max of the true yield functions at sigma, Pa
};

/// True yield functions at principal values in any order (re-sorted).
inline double violation_of(const MohrCoulomb& m, const Vec3& sigma) {
  return yield_value(m.n_phi, m.k, m.tension, sigma.maxCoeff(), sigma.minCoeff());
}

/// Solves the return onto the intersection of the planes in `set`: the exact
/// backward-Euler step, since every function is linear in the principal stresses.
template <std::size_t Count>
Candidate return_to(const MohrCoulomb& m, const std::array<Surface, Count>& set,
                    const Vec3& trial) {
  const Planes planes = yield_planes(m);
  constexpr int Size = static_cast<int>(Count);
  using Matrix = Eigen::Matrix<double, Size, Size>;
  using Vector = Eigen::Matrix<double, Size, 1>;
  std::array<Vec3, Count> stiffness_flow;  // D b_j, D = λ 11ᵀ + 2G I
  Matrix a_d_b;
  Vector residual;
  for (int j = 0; j < Size; ++j) {
    const Vec3& b = planes[set[j]].flow;
    stiffness_flow[j] = stiffness_times(m.lambda, m.shear, b);
  }
  for (int i = 0; i < Size; ++i) {
    const Plane& plane = planes[set[i]];
    residual[i] = plane.normal.dot(trial) - plane.level;
    for (int j = 0; j < Size; ++j) a_d_b(i, j) = plane.normal.dot(stiffness_flow[j]);
  }
  const Vector multiplier = a_d_b.inverse() * residual;  // closed form for Size ≤ 3
  Candidate c{trial, Vec3::Zero(), 0.0, 0.0};
  for (int j = 0; j < Size; ++j) {
    c.sigma -= multiplier[j] * stiffness_flow[j];
    c.plastic_strain += multiplier[j] * planes[set[j]].flow;
  }
  const double total = multiplier.cwiseAbs().sum();
  c.smallest_multiplier = total > 0.0 ? multiplier.minCoeff() / total : 0.0;
  c.violation = violation_of(m, c.sigma);
  return c;
}

/// The main plane's multiplier Δλ = (aᵀσ − k) / (aᵀ D b), from the model's constants.
double main_plane_multiplier(const MohrCoulomb& m, const Vec3& trial) {
  return m.returns.main_plane[3] * (m.returns.main_normal.dot(trial) - m.k);
}

/// return_to for the main plane alone, with the model's constants: the same numbers, the
/// plane's constants computed once per model instead of in every return.
Candidate return_to_main_plane(const MohrCoulomb& m, const Vec3& trial, double multiplier) {
  const Vec4& main_plane = m.returns.main_plane;
  Candidate c{trial - multiplier * main_plane.head<3>(), multiplier * m.returns.main_flow, 0.0,
              0.0};
  c.smallest_multiplier = std::abs(multiplier) > 0.0 ? multiplier / std::abs(multiplier) : 0.0;
  c.violation = violation_of(m, c.sigma);
  return c;
}

/// return_to for an edge of the main plane, with the model's constants: the same numbers,
/// the system's inverse computed once per model instead of in every return, and the two
/// planes' normals and flows (yield_planes' rows mc and second_plane[edge]) read from
/// the model: building the six planes cost more than the rest of this return.
Candidate return_to_edge(const MohrCoulomb& m, Edge edge, const Vec3& trial) {
  const MohrCoulombReturns::Edge& constants = m.returns.edges[edge];
  const Eigen::Vector2d residual(m.returns.main_normal.dot(trial) - m.k,
                                 constants.normal.dot(trial) - m.k);
  const Eigen::Vector2d multiplier = constants.inverse * residual;
  Candidate c{trial, Vec3::Zero(), 0.0, 0.0};
  c.sigma -= multiplier[0] * m.returns.main_plane.head<3>();
  c.sigma -= multiplier[1] * constants.stiffness_flow;
  c.plastic_strain += multiplier[0] * m.returns.main_flow;
  c.plastic_strain += multiplier[1] * constants.flow;
  const double total = multiplier.cwiseAbs().sum();
  c.smallest_multiplier = total > 0.0 ? multiplier.minCoeff() / total : 0.0;
  c.violation = violation_of(m, c.sigma);
  return c;
}

/// The return to the Mohr–Coulomb apex σ1 = σ2 = σ3 = c cot φ. Its plastic strain is
/// D⁻¹(σ_trial − σ_apex); it is admissible whatever the trial.
Candidate return_to_apex(const MohrCoulomb& m, const Vec3& trial) {
  const Vec3 sigma = Vec3::Constant(m.apex());
  const Vec3 difference = trial - sigma;
  const double bulk_3 = 3.0 * m.lambda + 2.0 * m.shear;  // 3K
  const Vec3 plastic =
      (difference - (m.lambda / bulk_3 * difference.sum()) * Vec3::Ones()) / (2.0 * m.shear);
  return {sigma, plastic, 1.0, 0.0};
}

/// The Kuhn–Tucker test of a candidate: multipliers ≥ 0 and admissible, within the
/// tolerance `tolerance` (Pa) of the yield functions.
bool meets_kuhn_tucker(const Candidate& c, double tolerance) {
  return c.violation <= tolerance && c.smallest_multiplier >= -yield_tolerance;
}

/// return_to_surface's search beyond the main plane, which `main_plane` (its candidate) failed:
/// out of line, so that the common return stays small.
[[gnu::noinline]] Candidate search_returns(const MohrCoulomb& m, const Vec3& trial,
                                           double tolerance, const Candidate& main_plane) {
  Candidate result = main_plane;
  auto closer = [tolerance](const Candidate& c, const Candidate& than) {
    const bool admissible = c.violation <= tolerance;
    if (admissible != (than.violation <= tolerance)) return admissible;
    return admissible ? c.smallest_multiplier > than.smallest_multiplier
                      : c.violation < than.violation;
  };
  auto solves = [&](const Candidate& c) {
    const bool found = meets_kuhn_tucker(c, tolerance);
    if (found || closer(c, result)) result = c;
    return found;
  };
  auto to = [&](const auto&... planes) { return return_to(m, std::array{planes...}, trial); };
  const bool cutoff = m.has_tension_cutoff();
  const bool found =
      (cutoff && solves(to(tension_1))) ||           // tension plane
      solves(return_to_edge(m, edge_2_3, trial)) ||  // edge σ2 = σ3
      solves(return_to_edge(m, edge_1_2, trial)) ||  // edge σ1 = σ2
      (cutoff &&
       (solves(to(mc, tension_1)) ||              // edge f = 0, σ1 = T
        solves(to(tension_1, tension_2)) ||       // edge σ1 = σ2 = T
        solves(to(mc, mc_2_minor, tension_1)) ||  // corner (T, σ, σ)
        // corner (T, T, σ): four planes meet there, so the cone of their flow
        // directions is the union of the cones of its four 3-subsets
        solves(to(mc, mc_2_major, tension_1)) || solves(to(mc, tension_1, tension_2)) ||
        solves(to(mc_2_major, tension_1, tension_2)) || solves(to(mc, mc_2_major, tension_2)) ||
        solves(to(tension_1, tension_2, tension_3))));  // corner (T, T, T)
  if (!found && m.has_apex()) return return_to_apex(m, trial);
  return result;
}

/// The plastic strain increment's share of the state: its trace, and its deviatoric
/// invariant sqrt(2/3 Δeᵖ:Δeᵖ) from the principal components (principal directions are
/// kept, so they are the tensor's).
void add_plastic_strain(MaterialState& state, const Vec3& plastic_strain) {
  const double volumetric = plastic_strain.sum();
  const Vec3 deviatoric = plastic_strain - (volumetric / 3.0) * Vec3::Ones();
  state.plastic_volumetric_strain += volumetric;
  state.plastic_shear_strain += std::sqrt(2.0 / 3.0 * deviatoric.squaredNorm());
}

/// Backward-Euler return of an inadmissible stress (principal bounds `trial`) to the
/// surface, advancing the state. Tries the candidates in order of increasing complexity
/// and takes the first that satisfies the Kuhn–Tucker conditions (multipliers ≥ 0,
/// admissible): the main plane, then (search_returns) its edges from the model's
/// constants (where the cut-off is a plane of its own, it is tried before the edges),
/// then the cut-off's edges and corners. Should round-off reject every one (a trial on a
/// region boundary), it takes the admissible candidate that comes closest to them; the
/// corners are always admissible. Kept out of line so that the elastic path stays small
/// enough to inline into the update loops.
[[gnu::noinline]] void return_to_surface(const MohrCoulomb& m, const PrincipalBounds& trial,
                                         Vec4& stress, MaterialState& state) {
  const PrincipalStress principal = principal_stress(trial, stress);
  const Vec3& sigma = principal.sigma;
  const double tolerance = yield_tolerance * stress_scale(m.n_phi, m.k, sigma[0], sigma[2]);
  const double multiplier = main_plane_multiplier(m, sigma);
  const Candidate main_plane = return_to_main_plane(m, sigma, multiplier);
  if (meets_kuhn_tucker(main_plane, tolerance)) {
    stress = rebuild(principal, main_plane.sigma);
    // Δεᵖ = Δλ b with Δλ ≥ 0 and b the plane's: its invariants are Δλ times b's (no
    // square root on the common path).
    state.plastic_volumetric_strain += multiplier * m.returns.main_flow_trace;
    state.plastic_shear_strain += multiplier * m.returns.main_flow_shear;
    return;
  }
  const Candidate c = search_returns(m, sigma, tolerance, main_plane);
  stress = rebuild(principal, c.sigma);
  add_plastic_strain(state, c.plastic_strain);
}

}  // namespace

ConstitutiveModel ConstitutiveModel::elastic(const Material& material) {
  ConstitutiveModel model;
  model.model_ = MaterialModel::linear_elastic;
  model.lambda_ = material.lame_lambda();
  model.shear_ = material.shear_modulus();
  return model;
}

ConstitutiveModel ConstitutiveModel::from(const Material& material, Phase phase) {
  ConstitutiveModel model = elastic(material);
  constexpr double degree = std::numbers::pi / 180.0;
  const double sin_phi = std::sin(material.friction_angle * degree);
  switch (material.model_of(phase)) {
    case MaterialModel::linear_elastic:
      return model;
    case MaterialModel::pressure_independent_multi_yield:
      // OpenSees's calibration to Mohr–Coulomb (multi_yield.hpp): the failure surface
      // q_f = M (p′₀ + p_r), p_r = 3c/(√2 M), i.e. M p′₀ + 3c/√2; q_f = 2c for φ = 0.
      model.model_ = MaterialModel::pressure_independent_multi_yield;
      model.surfaces_ = material.yield_surfaces;
      model.peak_shear_strain_ = material.peak_shear_strain;
      model.strength_slope_ = 6.0 * sin_phi / (3.0 - sin_phi);
      model.strength_intercept_ =
          sin_phi > 0.0 ? 3.0 * material.cohesion / std::numbers::sqrt2 : 2.0 * material.cohesion;
      return model;
    case MaterialModel::pm4sand:
      model.model_ = MaterialModel::pm4sand;
      model.surfaces_ = pm4sand::records;
      model.pm4sand_ = pm4sand::Constants::of(material);
      return model;
    case MaterialModel::residual_strength:
      return liquefied(material);
    case MaterialModel::mohr_coulomb:
      break;
  }
  const double sin_psi = std::sin(material.dilation_angle * degree);
  model.model_ = MaterialModel::mohr_coulomb;
  model.n_phi_ = (1.0 + sin_phi) / (1.0 - sin_phi);
  model.n_psi_ = (1.0 + sin_psi) / (1.0 - sin_psi);
  model.two_c_sqrt_n_phi_ = 2.0 * material.cohesion * std::sqrt(model.n_phi_);
  // T = min(tension_cutoff, apex), taken literally: 0 is a no-tension material, and a
  // value at or above the apex (the case reader's default c cot φ, or +∞) leaves the
  // pyramid alone. The apex is computed from the same constants as f, so the pyramid's
  // tip and T coincide exactly; a cut-off within round-off of it is snapped to it.
  const double apex = apex_stress(model.n_phi_, model.two_c_sqrt_n_phi_);
  model.tension_cutoff_ =
      material.tension_cutoff >= apex * (1.0 - 1e-12) ? apex : material.tension_cutoff;
  model.returns_ = return_constants(model.lambda_, model.shear_, model.n_phi_, model.n_psi_);
  return model;
}

ConstitutiveModel ConstitutiveModel::liquefied(const Material& material) {
  const LiquefactionParameters& rule = material.liquefaction;
  ConstitutiveModel model;
  model.model_ = MaterialModel::residual_strength;
  model.shear_ = rule.shear_modulus_ratio * material.shear_modulus();
  model.lambda_ = 2.0 * model.shear_ * rule.poisson_ratio / (1.0 - 2.0 * rule.poisson_ratio);
  model.surfaces_ = 1;
  model.softening_strain_ = rule.softening_strain;
  model.tension_cutoff_ = 0.0;
  model.returns_ = return_constants(model.lambda_, model.shear_, 1.0, 1.0);
  return model;
}

Vec4 ConstitutiveModel::elastic_stress_increment(const Vec4& strain_increment) const {
  const double volumetric =
      lambda_ * (strain_increment[0] + strain_increment[1] + strain_increment[2]);
  const double two_g = 2.0 * shear_;
  return {volumetric + two_g * strain_increment[0], volumetric + two_g * strain_increment[1],
          volumetric + two_g * strain_increment[2], shear_ * strain_increment[3]};
}

double ConstitutiveModel::frozen_peak_strength(const Vec4& stress) const {
  return strength_slope_ * std::max(mean_stress(stress), 0.0) + strength_intercept_;
}

[[gnu::noinline]] bool ConstitutiveModel::update_multi_yield(
    Vec4& stress, MaterialState& state, const Vec4& strain_increment, std::span<Vec4> surfaces,
    multi_yield::KeptComponents* kept) const {
  // Without kept components, fresh ones: their NaN tag matches no strength.
  multi_yield::KeptComponents fresh;
  multi_yield::KeptComponents& own = kept != nullptr ? *kept : fresh;
  if (!(own.peak_strength == state.peak_strength)) {
    own.components =
        multi_yield::components(shear_, state.peak_strength, peak_shear_strain_, surfaces_);
    own.peak_strength = state.peak_strength;
  }
  return multi_yield::update(own.components, lambda_ + 2.0 / 3.0 * shear_, shear_, stress, state,
                             strain_increment, surfaces.first(static_cast<std::size_t>(surfaces_)));
}

bool ConstitutiveModel::update(Vec4& stress, MaterialState& state, const Vec4& strain_increment,
                               std::span<Vec4> surfaces, multi_yield::KeptComponents* kept) const {
  if (model_ == MaterialModel::pm4sand) {
    return pm4sand::update(pm4sand_, stress, state, strain_increment, surfaces);
  }
  if (model_ == MaterialModel::pressure_independent_multi_yield) {
    return update_multi_yield(stress, state, strain_increment, surfaces, kept);
  }
  stress += elastic_stress_increment(strain_increment);
  if (model_ == MaterialModel::linear_elastic) return false;
  if (model_ == MaterialModel::residual_strength) {
    // Tresca on the full stress (σzz takes part): σ1 − σ3 ≤ 2c(εq^p), and no tension
    // (σ1 ≤ T = 0: the grains of a liquefied sand hold none).
    const double k =
        2.0 * liquefaction::cohesion(surfaces[0], state.plastic_shear_strain, softening_strain_);
    const PrincipalBounds trial = principal_bounds(stress);
    if (admissible(trial, 1.0, k, tension_cutoff_)) return false;
    return_to_surface({lambda_, shear_, 1.0, 1.0, k, tension_cutoff_, returns_}, trial, stress,
                      state);
    return true;
  }
  const PrincipalBounds trial = principal_bounds(stress);
  if (admissible(trial, n_phi_, two_c_sqrt_n_phi_, tension_cutoff_)) return false;
  return_to_surface({lambda_, shear_, n_phi_, n_psi_, two_c_sqrt_n_phi_, tension_cutoff_, returns_},
                    trial, stress, state);
  return true;
}

bool ConstitutiveModel::start(Vec4& stress, MaterialState& state, std::span<Vec4> surfaces) const {
  switch (model_) {
    case MaterialModel::linear_elastic:
      return false;
    case MaterialModel::mohr_coulomb:
      return update(stress, state, Vec4::Zero());
    case MaterialModel::residual_strength:
      return update(stress, state, Vec4::Zero(), surfaces);
    case MaterialModel::pm4sand:
      return pm4sand::start(pm4sand_, stress, surfaces);
    case MaterialModel::pressure_independent_multi_yield:
      break;
  }
  const auto own = surfaces.first(static_cast<std::size_t>(surfaces_));
  if (state.peak_strength >= 0.0) {
    const auto c =
        multi_yield::components(shear_, state.peak_strength, peak_shear_strain_, surfaces_);
    return multi_yield::reconcile(c, stress, own);
  }
  state.peak_strength = frozen_peak_strength(stress);
  const auto c =
      multi_yield::components(shear_, state.peak_strength, peak_shear_strain_, surfaces_);
  return multi_yield::load_monotonically(c, stress, own);
}

double ConstitutiveModel::yield_function(const Vec4& stress, const MaterialState& state) const {
  // Residual strength: the cohesion is each point's (its record), not the model's.
  if (model_ == MaterialModel::linear_elastic || model_ == MaterialModel::residual_strength) {
    return -infinity;
  }
  if (model_ == MaterialModel::pm4sand) {  // q − M_b p at the initial D_R
    const double p = std::max(mean_stress(stress), 0.0);
    const double m_b = pm4sand::ratios(pm4sand_, p, pm4sand_.relative_density).bounding;
    return pm4sand::stress_ratio(stress) * p - m_b * p;
  }
  if (model_ == MaterialModel::pressure_independent_multi_yield) {
    return von_mises_stress(stress) - state.peak_strength;
  }
  const PrincipalBounds bounds = principal_bounds(stress);
  return yield_value(n_phi_, two_c_sqrt_n_phi_, tension_cutoff_, bounds.sigma_1, bounds.sigma_3);
}

Eigen::Matrix3d plane_strain_elasticity(const Material& material) {
  const double lambda = material.lame_lambda();
  const double g = material.shear_modulus();
  Eigen::Matrix3d c;
  c << lambda + 2.0 * g, lambda, 0.0,  //
      lambda, lambda + 2.0 * g, 0.0,   //
      0.0, 0.0, g;
  return c;
}

double elastic_energy_density(const Material& material, const Vec4& s) {
  const double trace = s[0] + s[1] + s[2];
  const double contracted = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * s[3] * s[3];
  return ((1.0 + material.poisson_ratio) * contracted - material.poisson_ratio * trace * trace) /
         (2.0 * material.youngs_modulus);
}

void rotate_jaumann(Vec4& stress, double spin_increment) {
  const double sxx = stress[0];
  const double syy = stress[1];
  const double sxy = stress[3];
  // One store of the whole tensor: the update that follows loads it whole, and a load
  // that spans several narrower stores waits until they are written (no store forwarding).
  stress = Vec4(sxx + 2.0 * spin_increment * sxy, syy - 2.0 * spin_increment * sxy, stress[2],
                sxy + spin_increment * (syy - sxx));
}

void ConstitutiveModel::rotate_records(std::span<Vec4> surfaces, double spin_increment) const {
  if (model_ == MaterialModel::pm4sand) {
    pm4sand::rotate(surfaces, spin_increment);
    return;
  }
  if (model_ == MaterialModel::residual_strength) return;  // its record holds scalars
  for (Vec4& s : surfaces) rotate_jaumann(s, spin_increment);
}

bool advance_point(const ConstitutiveModel& model, const Vec4& velocity_gradient, double dt,
                   bool objective, Vec4& stress, MaterialState& state, std::span<Vec4> surfaces,
                   Vec4& strain, multi_yield::KeptComponents* kept) {
  const Vec4& l = velocity_gradient;
  const Vec4 increment(dt * l[0], dt * l[3], 0.0, dt * (l[1] + l[2]));
  if (objective) {
    const double spin = 0.5 * dt * (l[1] - l[2]);
    rotate_jaumann(stress, spin);
    if (!surfaces.empty()) model.rotate_records(surfaces, spin);
  }
  const bool yielded = model.update(stress, state, increment, surfaces, kept);
  strain += increment;
  return yielded;
}

namespace {

/// advance_mohr_coulomb_pair's predictor, both points lane by lane (advance_point's
/// operations in its order): the strain increments Δε = (Δt l0, Δt l3, 0, Δt (l1 + l2)),
/// the Jaumann rotations (rotate_jaumann), the elastic trial stresses
/// (elastic_stress_increment with Δεzz = 0) and their principal bounds.
struct PairTrial {
  Pair e0, e1, e3;                                         ///< Δεxx, Δεyy, Δγxy
  Pair s0, s1, s2, s3;                                     ///< the trial stresses
  Pair centre, half_difference, radius, sigma_1, sigma_3;  ///< principal_bounds'
};

PairTrial predict_pair(double lambda, double shear, double dt, bool objective,
                       const std::array<PointRefs, 2>& points) {
  const auto component = [&](auto field, int i) {
    return Pair{field(points[0])[i], field(points[1])[i]};
  };
  const auto gradient = [](const PointRefs& r) -> const Vec4& { return r.velocity_gradient; };
  const auto stress = [](const PointRefs& r) -> const Vec4& { return *r.stress; };
  const Pair l0 = component(gradient, 0), l1 = component(gradient, 1), l2 = component(gradient, 2),
             l3 = component(gradient, 3);
  const Pair zero{};
  PairTrial t;
  t.e0 = dt * l0;
  t.e1 = dt * l3;
  t.e3 = dt * (l1 + l2);
  const Pair spin = 0.5 * dt * (l1 - l2);
  const Pair sxx = component(stress, 0), syy = component(stress, 1), szz = component(stress, 2),
             sxy = component(stress, 3);
  Pair rxx = sxx, ryy = syy, rxy = sxy;
  if (objective) {
    rxx = sxx + 2.0 * spin * sxy;
    ryy = syy - 2.0 * spin * sxy;
    rxy = sxy + spin * (syy - sxx);
  }
  const Pair volumetric = lambda * (t.e0 + t.e1 + zero);
  const double two_g = 2.0 * shear;
  t.s0 = rxx + (volumetric + two_g * t.e0);
  t.s1 = ryy + (volumetric + two_g * t.e1);
  t.s2 = szz + (volumetric + two_g * zero);
  t.s3 = rxy + shear * t.e3;
  t.centre = 0.5 * (t.s0 + t.s1);
  t.half_difference = 0.5 * (t.s0 - t.s1);
  t.radius = sqrt_pair(t.half_difference * t.half_difference + t.s3 * t.s3);
  t.sigma_1 = lanes::max(t.centre + t.radius, t.s2);
  t.sigma_3 = lanes::min(t.centre - t.radius, t.s2);
  return t;
}

}  // namespace

std::array<bool, 2> advance_mohr_coulomb_pair(const ConstitutiveModel& model, double dt,
                                              bool objective,
                                              const std::array<PointRefs, 2>& points) {
  const PairTrial t = predict_pair(model.lambda_, model.shear_, dt, objective, points);
  // admissible, lane by lane.
  const double n_phi = model.n_phi_, k = model.two_c_sqrt_n_phi_;
  const Pair value =
      lanes::max(n_phi * t.sigma_1 - t.sigma_3 - k, t.sigma_1 - model.tension_cutoff_);
  const Pair scale = (n_phi + 1.0) * lanes::max(lanes::abs(t.sigma_1), lanes::abs(t.sigma_3)) + k;
  std::array<bool, 2> yielded{};
  for (std::size_t i = 0; i < 2; ++i) {
    const PointRefs& point = points[i];
    *point.stress = Vec4(t.s0[i], t.s1[i], t.s2[i], t.s3[i]);
    yielded[i] = !(value[i] <= yield_tolerance * scale[i]);
    if (yielded[i]) {
      return_to_surface(
          {model.lambda_, model.shear_, n_phi, model.n_psi_, k, model.tension_cutoff_,
           model.returns_},
          {t.centre[i], t.half_difference[i], t.radius[i], t.sigma_1[i], t.sigma_3[i]},
          *point.stress, *point.state);
    }
    *point.strain += Vec4(t.e0[i], t.e1[i], 0.0, t.e3[i]);
  }
  return yielded;
}

std::size_t update_stresses(const ConstitutiveModel& model, std::span<Vec4> stress,
                            std::span<MaterialState> state, std::span<const Vec4> strain_increment,
                            std::span<std::uint8_t> yielded, std::span<Vec4> surfaces) {
  const std::size_t n = stress.size();
  const auto per_point = static_cast<std::size_t>(model.surfaces());
  if (state.size() != n || strain_increment.size() != n ||
      (!yielded.empty() && yielded.size() != n) || surfaces.size() != n * per_point) {
    throw Error(
        "update_stresses: {} stresses, {} states, {} strain increments, {} flags, {} surface "
        "stresses ({} per point)",
        n, state.size(), strain_increment.size(), yielded.size(), surfaces.size(), per_point);
  }
  std::size_t count = 0;
  switch (model.model()) {
    case MaterialModel::linear_elastic:
      for (std::size_t i = 0; i < n; ++i) {
        stress[i] += model.elastic_stress_increment(strain_increment[i]);
      }
      std::fill(yielded.begin(), yielded.end(), std::uint8_t{0});
      break;
    case MaterialModel::mohr_coulomb:
    case MaterialModel::pressure_independent_multi_yield:
    case MaterialModel::pm4sand:
    case MaterialModel::residual_strength:
      for (std::size_t i = 0; i < n; ++i) {
        const auto own =
            per_point > 0 ? surfaces.subspan(i * per_point, per_point) : std::span<Vec4>{};
        const bool yield = model.update(stress[i], state[i], strain_increment[i], own);
        if (!yielded.empty()) yielded[i] = yield ? 1 : 0;
        count += yield ? 1 : 0;
      }
      break;
  }
  return count;
}

std::size_t surfaces_needed(const MaterialTable& materials, Phase phase) {
  std::size_t n = 0;
  for (const Material& m : materials) {
    if (m.model_of(phase) == MaterialModel::pressure_independent_multi_yield) {
      n = std::max(n, static_cast<std::size_t>(m.yield_surfaces));
    }
    if (m.model_of(phase) == MaterialModel::pm4sand) {
      n = std::max(n, static_cast<std::size_t>(pm4sand::records));
    }
    // A liquefied particle's residual strength: one record.
    if (phase == Phase::mpm && has_residual_strength(m)) n = std::max<std::size_t>(n, 1);
  }
  return n;
}

double von_mises_stress(const Vec4& stress) {
  const double p = mean_stress(stress);
  const double sxx = stress[0] + p;
  const double syy = stress[1] + p;
  const double szz = stress[2] + p;
  const double s_s = sxx * sxx + syy * syy + szz * szz + 2.0 * stress[3] * stress[3];
  return std::sqrt(1.5 * s_s);
}

}  // namespace slide
