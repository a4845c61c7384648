// Material parameters as the user gives them (case file) and as checkpoints store them
// (`/materials/<id>/` attributes). Angles are in degrees here, as users write them; the
// constitutive kernels precompute their trigonometry once (constitutive.hpp).
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slide {

/// A handful of models: an enum and a switch, no factory (common/physics/constitutive.md).
enum class MaterialModel {
  linear_elastic,
  mohr_coulomb,
  pressure_independent_multi_yield,
  pm4sand,
  /// The undrained residual strength of liquefied soil (common/physics/liquefaction.hpp):
  /// the MPM model of a material's liquefied particles, never a case file's `model`.
  residual_strength
};

std::string_view to_string(MaterialModel model);
/// Parses "linear-elastic", "mohr-coulomb", "pressure-independent-multi-yield" or
/// "pm4sand"; throws Error naming `where` otherwise.
MaterialModel parse_material_model(std::string_view text, std::string_view where);
/// True for the models that read φ and c (Mohr–Coulomb and multi-yield).
bool has_strength(MaterialModel model);

/// The two phases that may run different models of one material (docs/method.md §3).
enum class Phase { fem, mpm };

/// Largest number of yield surfaces of the multi-yield model (OpenSees allows 40 too).
inline constexpr int max_yield_surfaces = 40;

/// PM4Sand's parameters (common/physics/pm4sand.hpp) as the user gives them: the three
/// primary ones, then the secondary ones with the report's defaults. NaN: derived (from
/// D_R, or for z_max and A_do from each point's stress at the switch).
struct Pm4SandParameters {
  static constexpr double derived = std::numeric_limits<double>::quiet_NaN();
  double relative_density = derived;           ///< D_R (required)
  double shear_modulus_coefficient = derived;  ///< G₀; default 167 sqrt(46 D_R² + 2.5)
  double contraction_rate = derived;           ///< h_po (or calibrated to a CRR)
  double atmospheric_pressure = 101.3e3;       ///< p_A, Pa
  double h0 = derived;                         ///< default max(0.3, (0.25 + D_R)/2)
  double e_max = 0.8;
  double e_min = 0.5;
  double n_b = 0.5;
  double n_d = 0.1;
  double a_do = derived;
  double z_max = derived;
  double c_z = 250.0;
  double c_e = derived;
  double critical_friction_angle = 33.0;  ///< φ_cv, degrees
  double c_gd = 2.0;
  double c_dr = derived;
  double c_kaf = derived;
  double q = 10.0;
  double r = 1.5;
  double m = 0.01;
  double strain_step = 1e-5;  ///< largest strain component of one sub-increment
  /// When h_po was calibrated (calibrate_to_crr): the target CRR and the cycles to 3 %
  /// strain the calibrated h_po gives; NaN otherwise. Not stored in checkpoints.
  double calibrated_crr = derived;
  double calibrated_cycles = derived;
};

/// How liquefied soil's undrained residual strength S_r/σ′v0 follows from the blow count
/// (common/physics/liquefaction.hpp), or `ratio` (given), or `none`: the liquefied
/// particles keep the material's own MPM model.
enum class ResidualStrengthCorrelation {
  idriss_boulanger_void_redistribution,
  idriss_boulanger,
  olson_stark,
  ratio,
  none
};

std::string_view to_string(ResidualStrengthCorrelation correlation);
/// Parses "idriss-boulanger-void-redistribution", "idriss-boulanger", "olson-stark",
/// "ratio" or "none"; throws Error naming `where` otherwise.
ResidualStrengthCorrelation parse_residual_strength_correlation(std::string_view text,
                                                                std::string_view where);

/// A material that may liquefy (docs/method.md §10): the rule that marks its particles
/// liquefied at the transfer and the strength they have after it ([materials.liquefaction]).
/// NaN: not given (the rule's criterion unused, or the value derived).
struct LiquefactionParameters {
  static constexpr double unset = std::numeric_limits<double>::quiet_NaN();
  bool enabled = false;              ///< the material has a liquefaction rule
  double pore_pressure_ratio = 0.7;  ///< liquefied when r_u,max ≥ this (NaN: not used)
  double shear_strain = unset;       ///< … or when γ = √3 εq ≥ this (NaN: not used)
  ResidualStrengthCorrelation correlation =
      ResidualStrengthCorrelation::idriss_boulanger_void_redistribution;
  double blow_count = unset;      ///< (N1)60cs-Sr; default 46 D_R² for PM4Sand
  double strength_ratio = unset;  ///< S_r/σ′v0 of correlation `ratio`
  double friction_angle = unset;  ///< φ′ of the cap σ′v0 tan φ′, degrees; default φ or φ_cv
  double minimum_strength = 0.0;       ///< floor of S_r, Pa
  double peak_strength_ratio = unset;  ///< S_u,peak/σ′v0 the strength softens from (NaN: none)
  double softening_strain = unset;     ///< engineering shear strain of the softening
  double shear_modulus_ratio = 0.1;    ///< G_liquefied / G of the material's elastic stage
  double poisson_ratio = 0.49;         ///< ν of the liquefied (undrained) soil
};

struct Material {
  std::string name;
  /// Model of the FE failure stage, and of the MPM phase unless `mpm_model` names
  /// another. The FE geostatic stage always uses the linear elastic model with the same
  /// elastic constants (docs/method.md §3).
  MaterialModel model = MaterialModel::mohr_coulomb;
  /// Model of the MPM phase when it differs from the FE one (the reference workflow:
  /// pressure-independent multi-yield in FE, Mohr–Coulomb in MPM).
  std::optional<MaterialModel> mpm_model;
  double density = 0.0;         ///< ρ, kg/m³
  double youngs_modulus = 0.0;  ///< E, Pa
  double poisson_ratio = 0.0;   ///< ν, –
  double friction_angle = 0.0;  ///< φ, degrees
  double cohesion = 0.0;        ///< c, Pa
  double dilation_angle = 0.0;  ///< ψ, degrees
  /// Largest admissible principal stress T (Pa, tension positive), taken literally:
  /// T = 0 is a no-tension material; a value at or above the Mohr–Coulomb apex c·cot φ
  /// (the default, +∞) leaves only the apex.
  double tension_cutoff = std::numeric_limits<double>::infinity();
  /// Pressure-independent multi-yield only: the octahedral shear strain γ_peak at which
  /// the hyperbolic backbone reaches the peak strength, and the number of yield surfaces
  /// (both OpenSees's defaults).
  double peak_shear_strain = 0.1;
  int yield_surfaces = 20;
  /// Saturated soil (docs/method.md §10): porosity n (0: a dry material, the default)
  /// and the hydraulic conductivity k along x and y, m/s. Below the water table the
  /// material is a u–p mixture and `density` is its saturated density ρ_sat; above it the
  /// soil is dry, of density ρ_sat − n ρ_w.
  double porosity = 0.0;
  double conductivity_x = 0.0;  ///< k_x, m/s
  double conductivity_y = 0.0;  ///< k_y, m/s
  /// PM4Sand only. Its elastic stage (the geostatic one) has G = G₀ p_A and ν:
  /// `youngs_modulus` is then 2 (1 + ν) G₀ p_A, set by the case reader.
  Pm4SandParameters pm4sand;
  /// A material that may liquefy: its rule and residual strength (`enabled` false: none).
  LiquefactionParameters liquefaction;

  /// The model of one phase.
  MaterialModel model_of(Phase phase) const {
    return phase == Phase::mpm ? mpm_model.value_or(model) : model;
  }
  /// True when either phase runs `m`.
  bool uses(MaterialModel m) const { return model == m || model_of(Phase::mpm) == m; }

  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  /// Lamé's first parameter λ.
  double lame_lambda() const;
  /// P-wave (constrained) modulus M = E(1−ν)/((1+ν)(1−2ν)).
  double p_wave_modulus() const;
  /// Dilatational wave speed c_p = sqrt(M/ρ), used by both Courant conditions.
  double p_wave_speed() const;
  /// Earth pressure coefficient at rest of the elastic geostatic stage, K0 = ν/(1−ν).
  double k0() const { return poisson_ratio / (1.0 - poisson_ratio); }
  /// True for a material that holds pore water below the water table.
  bool saturable() const { return porosity > 0.0; }
  /// The Mohr–Coulomb apex c·cot φ (infinite for φ = 0).
  double apex_stress() const;

  /// Checks every parameter for physical admissibility; throws Error naming `where`
  /// (e.g. "case.toml: materials[0]") and the offending key otherwise.
  void validate(std::string_view where) const;

 private:
  void validate_pm4sand(std::string_view where) const;
  void validate_liquefaction(std::string_view where) const;
};

using MaterialTable = std::vector<Material>;

}  // namespace slide
