// The constitutive library shared by FE Gauss points and material points.
//
// A model maps (stress, state, strain increment) to (stress, state). It knows nothing
// about elements or particles, which is what lets the MPM phase continue exactly the
// model the FE phase used. Plane strain: the strain increment has Δεzz = 0, but the
// model works on the full stress set [σxx, σyy, σzz, σxy] so σzz takes part in yield.
//
// Mohr–Coulomb (tension positive, principal stresses σ1 ≥ σ2 ≥ σ3):
//   f = Nφ σ1 − σ3 − 2c sqrt(Nφ) ≤ 0,  Nφ = (1 + sin φ)/(1 − sin φ)
//   plastic potential g = Nψ σ1 − σ3 (non-associated for ψ < φ)
//   tension cut-off σ1 ≤ T
// The return map works in principal stresses (the in-plane eigenvectors and the z axis
// are kept) and returns to the plane, to either edge (σ1 = σ2 or σ2 = σ3), to the
// tension cut-off and its edges, or to the apex.
//
// Pressure-independent multi-yield (common/physics/multi_yield.hpp): von Mises surfaces whose
// peak strength is frozen at the switch from the point's confinement; the deviatoric
// stress each surface carries is per-point state passed as a span (`surfaces`), empty
// for the other models.
//
// PM4Sand (common/physics/pm4sand.hpp): a bounding-surface model for sands that liquefy;
// its state (back-stress ratios, fabric, the constants fixed at the switch) is the same
// per-point span, pm4sand::records entries.
//
// Residual strength (common/physics/liquefaction.hpp): liquefied particles in MPM,
// Mohr–Coulomb with φ = ψ = 0 and no cut-off whose cohesion is the point's own (one
// record: peak and residual undrained strength, softening from the transfer).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "common/base/pair.hpp"
#include "common/base/types.hpp"
#include "common/physics/material.hpp"
#include "common/physics/material_state.hpp"
#include "common/physics/multi_yield.hpp"
#include "common/physics/pm4sand.hpp"

namespace slide {

/// True when a material's liquefied particles take the residual-strength model (a
/// liquefaction rule whose correlation is not "none").
inline bool has_residual_strength(const Material& m) {
  return m.liquefaction.enabled && m.liquefaction.correlation != ResidualStrengthCorrelation::none;
}

/// The largest number of surfaces any model of `materials` needs in `phase`.
std::size_t surfaces_needed(const MaterialTable& materials, Phase phase);

/// The constants of a Mohr–Coulomb return that depend on the elastic constants and Nφ, Nψ
/// only (constitutive.cpp), computed once per model: the main plane's D b and 1/(aᵀ D b),
/// and for each of its edges (σ2 = σ3, σ1 = σ2) the second plane's D b and the inverse of
/// the 2 × 2 system aᵢᵀ D bⱼ of a return to both planes. The planes' a and b themselves
/// are kept too: read from here, not built in each return (GCC built (Nφ, 0) on the
/// stack with two stores and loaded it as a pair, which the store buffer cannot forward:
/// a stall per return).
struct MohrCoulombReturns {
  struct Edge {
    Eigen::Vector3d stiffness_flow = Eigen::Vector3d::Zero();  // D b of the second plane
    Eigen::Matrix2d inverse = Eigen::Matrix2d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // the second plane's a
    Eigen::Vector3d flow = Eigen::Vector3d::Zero();    // and b
  };
  Vec4 main_plane = Vec4::Zero();
  std::array<Edge, 2> edges{};                            // σ2 = σ3, σ1 = σ2
  Eigen::Vector3d main_normal = Eigen::Vector3d::Zero();  // a = (Nφ, 0, −1)
  Eigen::Vector3d main_flow = Eigen::Vector3d::Zero();    // b = (Nψ, 0, −1)
  double main_flow_trace = 0.0;  // Σ b_i, and sqrt(2/3 dev b : dev b): a main-plane return's
  double main_flow_shear = 0.0;  // Δεᵖ = Δλ b has Δλ times these as its invariants
};

/// One point of advance_mohr_coulomb_pair: its velocity gradient and where its stress,
/// state and accumulated strain live.
struct PointRefs {
  Vec4 velocity_gradient;
  Vec4* stress;
  MaterialState* state;
  Vec4* strain;
};

/// A model with its constants precomputed: a small value type that kernels copy.
class ConstitutiveModel {
 public:
  /// Linear elastic with the material's E and ν (the FE geostatic stage).
  static ConstitutiveModel elastic(const Material& material);
  /// The material's own model of one phase (FE failure stage or MPM phase).
  static ConstitutiveModel from(const Material& material, Phase phase = Phase::fem);
  /// The material's liquefied state (common/physics/liquefaction.hpp): φ = 0 with the
  /// cohesion of each point's record, the reduced G and the undrained ν of its rule.
  static ConstitutiveModel liquefied(const Material& material);

  MaterialModel model() const { return model_; }
  double shear_modulus() const { return shear_; }
  double lame_lambda() const { return lambda_; }
  /// Per-point records the model needs: the multi-yield model's surfaces (a deviatoric
  /// stress each), PM4Sand's state records, 0 for the others.
  int surfaces() const { return surfaces_; }
  /// The pore fluid's stiffness K_f/n of a saturated material whose pore pressure evolves
  /// undrained in MPM (ṗ = −(K_f/n) tr ε̇, docs/method.md §10), Pa; 0: frozen or dry.
  double pore_fluid_stiffness() const { return pore_fluid_stiffness_; }
  void set_pore_fluid_stiffness(double stiffness) { pore_fluid_stiffness_ = stiffness; }
  /// PM4Sand's constants (meaningful only for that model).
  const pm4sand::Constants& pm4sand_constants() const { return pm4sand_; }
  /// Rotates the per-point records that are tensors by a spin increment (the objective
  /// update; the stress is rotated by the caller).
  void rotate_records(std::span<Vec4> surfaces, double spin_increment) const;
  /// Multi-yield: the peak strength q_f = M p′₀ + q₀ frozen from the mean effective
  /// stress p′₀ = max(p, 0) at the switch (common/physics/multi_yield.hpp).
  double frozen_peak_strength(const Vec4& stress) const;

  /// Elastic stress increment D·Δε for plane strain (Δεzz = strain_increment[2]).
  Vec4 elastic_stress_increment(const Vec4& strain_increment) const;

  /// Advances one point by one strain increment: elastic predictor, then the return
  /// map (Mohr–Coulomb), or the update of every yield surface (multi-yield, whose
  /// `surfaces` span holds surfaces() entries). Returns true when the point yielded:
  /// a plastic correction (Mohr–Coulomb), the peak strength reached (multi-yield).
  /// `kept` (optional): the point's multi-yield components from its previous update,
  /// reused when they are for its peak strength and refreshed otherwise.
  bool update(Vec4& stress, MaterialState& state, const Vec4& strain_increment,
              std::span<Vec4> surfaces = {}, multi_yield::KeptComponents* kept = nullptr) const;

  /// The switch to this model from the elastic geostatic state, from the initial K0
  /// stresses of pure MPM or from the other phase's model (docs/method.md §3). Mohr–Coulomb
  /// returns an inadmissible stress to its surface (an update with a zero increment);
  /// multi-yield freezes the peak strength from the point's confinement (unless the
  /// state already holds one) and sets its surfaces as after a monotonic loading to the
  /// current stress. Returns true when the stress had to be brought onto the surface.
  bool start(Vec4& stress, MaterialState& state, std::span<Vec4> surfaces = {}) const;

  /// Largest of the yield functions (Mohr–Coulomb and tension cut-off; multi-yield:
  /// q − q_f of the state's frozen strength), in Pa. ≤ 0 is admissible; always −∞ for
  /// linear elastic.
  double yield_function(const Vec4& stress, const MaterialState& state = {}) const;

 private:
  friend std::array<bool, 2> advance_mohr_coulomb_pair(const ConstitutiveModel& model, double dt,
                                                       bool objective,
                                                       const std::array<PointRefs, 2>& points);
  /// update() of the multi-yield model, out of line: the Mohr–Coulomb path stays small.
  bool update_multi_yield(Vec4& stress, MaterialState& state, const Vec4& strain_increment,
                          std::span<Vec4> surfaces, multi_yield::KeptComponents* kept) const;

  MaterialModel model_ = MaterialModel::linear_elastic;
  double lambda_ = 0.0;           // Lamé λ
  double shear_ = 0.0;            // G
  double n_phi_ = 1.0;            // Nφ
  double n_psi_ = 1.0;            // Nψ
  double two_c_sqrt_n_phi_ = 0;   // 2c sqrt(Nφ)
  double tension_cutoff_ = 0.0;   // T (already limited to the apex)
  MohrCoulombReturns returns_{};  // Mohr–Coulomb, residual strength
  // Multi-yield: q_f = strength_slope_ · p′₀ + strength_intercept_, the backbone's γ_peak.
  int surfaces_ = 0;
  double strength_slope_ = 0.0;
  double strength_intercept_ = 0.0;
  double peak_shear_strain_ = 0.0;
  double softening_strain_ = 0.0;      // residual strength: γ_s (NaN: no softening)
  double pore_fluid_stiffness_ = 0.0;  // K_f/n (MPM, undrained pore pressure)
  pm4sand::Constants pm4sand_{};
};

/// The plane-strain elasticity matrix on [εxx, εyy, γxy]: [[λ+2G, λ, 0], [λ, λ+2G, 0],
/// [0, 0, G]] (FE stiffness matrices; ConstitutiveModel applies the same λ and G to the
/// full stress vector).
Eigen::Matrix3d plane_strain_elasticity(const Material& material);

/// The stored elastic energy density ½ σ:C⁻¹:σ of an isotropic material on the full
/// stress [σxx, σyy, σzz, σxy] (σzz counts): ((1 + ν) σ:σ − ν (tr σ)²)/(2E), J/m³. Both
/// solvers' energies (the instability guard, the transfer's report).
double elastic_energy_density(const Material& material, const Vec4& stress);

/// Objective (Jaumann) rotation of the stress by the spin increment
/// ω = ½ (∂v_x/∂y − ∂v_y/∂x) Δt, applied before `update` in updated Lagrangian FE and
/// in MPM: Δσxx = 2ωσxy, Δσyy = −2ωσxy, Δσxy = ω(σyy − σxx).
void rotate_jaumann(Vec4& stress, double spin_increment);

/// advance_point (no per-point records) of two points of one Mohr–Coulomb model at
/// once: the strain increments, the Jaumann rotations (when `objective`), the elastic predictors
/// and the elastic tests side by side in the two lanes of a register pair
/// (common/base/pair.hpp), each lane the scalar operations in their order, so the bits
/// of two calls (where the compiler does not fuse products into FMAs); a point the test
/// rejects returns to the surface alone. Requires `model.model()` Mohr–Coulomb. Returns
/// whether each yielded. (The common case of the MPM kernels and of one-point FE elements:
/// half the predictor's instructions.)
std::array<bool, 2> advance_mohr_coulomb_pair(const ConstitutiveModel& model, double dt,
                                              bool objective,
                                              const std::array<PointRefs, 2>& points);

/// Advances one point, an FE Gauss point or a material point, over a step Δt from its
/// velocity gradient l = [∂vx/∂x, ∂vx/∂y, ∂vy/∂x, ∂vy/∂y] (plane strain): the strain
/// increment Δε = Δt sym(l) as [Δεxx, Δεyy, 0, Δγxy]; when `objective` (updated
/// Lagrangian FE, MPM) the Jaumann rotation of the stress and of the multi-yield surfaces
/// by ω = ½ Δt (∂vx/∂y − ∂vy/∂x); the constitutive update; Δε added to `strain`. The one
/// point update of both solvers. Returns true when the point yielded.
bool advance_point(const ConstitutiveModel& model, const Vec4& velocity_gradient, double dt,
                   bool objective, Vec4& stress, MaterialState& state, std::span<Vec4> surfaces,
                   Vec4& strain, multi_yield::KeptComponents* kept = nullptr);

/// Updates a range of points that share one model; `yielded[i]` (optional, may be
/// empty) receives 1 where point i yielded; `surfaces` holds model.surfaces() entries
/// per point (empty for the models without surface state). Returns the number of
/// points that yielded.
std::size_t update_stresses(const ConstitutiveModel& model, std::span<Vec4> stress,
                            std::span<MaterialState> state, std::span<const Vec4> strain_increment,
                            std::span<std::uint8_t> yielded = {}, std::span<Vec4> surfaces = {});

/// Mean stress p = −(σxx+σyy+σzz)/3 (compression positive).
inline double mean_stress(const Vec4& stress) {
  return -(stress[0] + stress[1] + stress[2]) / 3.0;
}
/// Von Mises equivalent stress q = sqrt(3/2 s:s) = sqrt(3 J2), a scalar invariant of the
/// deviator s (not the deviator itself); q = |σ| in uniaxial stress.
double von_mises_stress(const Vec4& stress);
/// Deviatoric strain invariant εq = sqrt(2/3 e:e) of the strain (εxx, εyy, εzz, γxy = 2εxy),
/// for one point (Real = double) or two side by side (Real = Pair: lane by lane the same
/// bits, common/base/pair.hpp).
template <class Real>
Real deviatoric_strain(Real xx, Real yy, Real zz, Real gamma_xy) {
  const Real mean = (xx + yy + zz) / 3.0;
  const Real exx = xx - mean;
  const Real eyy = yy - mean;
  const Real ezz = zz - mean;
  const Real exy = 0.5 * gamma_xy;
  const Real e_e = exx * exx + eyy * eyy + ezz * ezz + 2.0 * exy * exy;
  if constexpr (std::is_same_v<Real, double>) {
    return std::sqrt(2.0 / 3.0 * e_e);
  } else {
    return sqrt_pair(2.0 / 3.0 * e_e);
  }
}
inline double deviatoric_strain(const Vec4& strain) {
  return deviatoric_strain(strain[0], strain[1], strain[2], strain[3]);
}

}  // namespace slide
