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
#pragma once

#include <cstdint>
#include <span>

#include "common/material.hpp"
#include "common/types.hpp"

namespace slide {

/// Algorithmic state carried per point (Gauss point or material point).
struct MaterialState {
  /// Accumulated deviatoric plastic strain, Σ sqrt(2/3 Δe^p : Δe^p) (–).
  double plastic_shear_strain = 0.0;
  /// Accumulated volumetric plastic strain, Σ tr Δε^p (–), dilation positive.
  double plastic_volumetric_strain = 0.0;
};

/// A model with its constants precomputed: a small value type that kernels copy.
class ConstitutiveModel {
 public:
  /// Linear elastic with the material's E and ν (the FE geostatic stage).
  static ConstitutiveModel elastic(const Material& material);
  /// The material's own model (failure stage, MPM phase).
  static ConstitutiveModel from(const Material& material);

  MaterialModel model() const { return model_; }
  double shear_modulus() const { return shear_; }
  double lame_lambda() const { return lambda_; }

  /// Elastic stress increment D·Δε for plane strain (Δεzz = strain_increment[2]).
  Vec4 elastic_stress_increment(const Vec4& strain_increment) const;

  /// Advances one point by one strain increment: elastic predictor, then the return
  /// map. With a zero increment it returns an inadmissible stress to the yield surface
  /// (the switch from the elastic geostatic state, METHOD.md §3). Returns true when the
  /// point yielded (plastic correction applied).
  bool update(Vec4& stress, MaterialState& state, const Vec4& strain_increment) const;

  /// Largest of the yield functions (Mohr–Coulomb and tension cut-off), in Pa.
  /// ≤ 0 is admissible; always −∞ for linear elastic.
  double yield_function(const Vec4& stress) const;

 private:
  MaterialModel model_ = MaterialModel::linear_elastic;
  double lambda_ = 0.0;          // Lamé λ
  double shear_ = 0.0;           // G
  double n_phi_ = 1.0;           // Nφ
  double n_psi_ = 1.0;           // Nψ
  double two_c_sqrt_n_phi_ = 0;  // 2c sqrt(Nφ)
  double tension_cutoff_ = 0.0;  // T (already limited to the apex)
};

/// Objective (Jaumann) rotation of the stress by the spin increment
/// ω = ½ (∂v_x/∂y − ∂v_y/∂x) Δt, applied before `update` in updated Lagrangian FE and
/// in MPM: Δσxx = 2ωσxy, Δσyy = −2ωσxy, Δσxy = ω(σyy − σxx).
void rotate_jaumann(Vec4& stress, double spin_increment);

/// Updates a range of points that share one model; `yielded[i]` (optional, may be
/// empty) receives 1 where point i yielded. Returns the number of points that yielded.
std::size_t update_stresses(const ConstitutiveModel& model, std::span<Vec4> stress,
                            std::span<MaterialState> state, std::span<const Vec4> strain_increment,
                            std::span<std::uint8_t> yielded = {});

/// Mean stress p = −(σxx+σyy+σzz)/3 (compression positive) and q = sqrt(3/2 s:s).
double mean_stress(const Vec4& stress);
double deviatoric_stress(const Vec4& stress);
/// Deviatoric strain invariant εq = sqrt(2/3 e:e) of a strain vector with γxy = 2εxy.
double deviatoric_strain(const Vec4& strain);

}  // namespace slide
