// Single-point (element) tests of a constitutive model: simple shear after K0
// consolidation, drained (σ′v held) or undrained (constant volume), monotonic or cyclic
// with reversals at a target shear stress; and the calibration of PM4Sand's contraction
// rate h_po to a cyclic resistance ratio. The program slide-element prints them; the
// tests and the case reader (calibrate_to_crr) call them.
//
// Geometry: x horizontal, y vertical; the sample is sheared by γxy with εxx = 0. The
// vertical stress σv = −σyy and the shear stress τ = σxy. "Undrained" is the constant-
// volume test of the laboratory (εyy = 0 too): the fall of σ′v is the excess pore
// pressure a sealed sample with incompressible water would carry, r_u = 1 − σ′v/σ′v0.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "common/base/types.hpp"
#include "common/physics/material.hpp"

namespace slide::element_test {

/// The consolidated state before shearing.
struct Consolidation {
  double vertical_stress = 101.3e3;  ///< σ′v0, Pa (compression positive)
  double k0 = 0.5;                   ///< σ′h0 = K0 σ′v0 (σzz too)
};

enum class Drainage { drained, undrained };

/// One recorded state.
struct Sample {
  double cycles;               ///< loading phase in cycles (stress-controlled tests), else 0
  double shear_strain;         ///< γxy
  double shear_stress;         ///< τ = σxy, Pa
  double vertical_stress;      ///< σ′v, Pa
  double horizontal_stress;    ///< σ′h = −σxx, Pa
  double mean_stress;          ///< p = (σ′v + σ′h)/2, Pa (the model's in-plane mean)
  double stress_ratio;         ///< q/p of the in-plane stress
  double volumetric_strain;    ///< εv, compression positive
  double pore_pressure_ratio;  ///< r_u = 1 − σ′v/σ′v0 (undrained)
};

/// Monotonic simple shear to γ_max in steps of dγ.
std::vector<Sample> monotonic(const Material& material, const Consolidation& start,
                              Drainage drainage, double gamma_max, double d_gamma);

/// Undrained (constant-volume) cyclic simple shear with τ reversed at ±CSR σ′v0,
/// uniform cycles, until the single-amplitude shear strain reaches `strain_limit` or
/// `max_cycles` pass. The phase counts cycles as a sinusoidal stress history would
/// (τ = CSR σ′v0 sin 2πN): the test is rate independent, so N follows from τ and the
/// number of reversals. The cycles to the strain limit are where the envelope of the
/// single-amplitude peaks (one per half cycle) crosses it, log-linear between the last
/// peak below and the first at or above: continuous in the parameters, where the first
/// instant |γ| reaches the limit jumps by half a cycle when a peak grazes it.
struct CyclicResult {
  double cycles_to_strain = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not reached
  double max_pore_pressure_ratio = 0.0;
  std::vector<Sample> history;  ///< every `keep_every`-th step and every reversal
};
CyclicResult cyclic(const Material& material, const Consolidation& start, double csr,
                    double max_cycles, double strain_limit = 0.03, double d_gamma = 1e-5,
                    std::size_t keep_every = 1);

/// Undrained (constant-volume) strain-controlled cyclic simple shear: γ reversed at
/// ±`amplitude` for `cycles` uniform cycles (the phase is γ's: a cycle is 4 amplitudes).
std::vector<Sample> cyclic_strain(const Material& material, const Consolidation& start,
                                  double amplitude, double cycles, double d_gamma = 1e-5);

/// The Idriss & Boulanger (2008) SPT triggering curve for M = 7.5 and σ′v = 1 atm:
/// CRR = exp(N/14.1 + (N/126)² − (N/23.6)³ + (N/25.4)⁴ − 2.8), N = (N1)60cs.
double idriss_boulanger_crr(double n160cs);
/// The default calibration target of a sand of relative density D_R: the curve above at
/// (N1)60cs = 46 D_R² (pm4sand::blow_count).
double default_target_crr(double relative_density);

/// h_po such that undrained cyclic simple shear at σ′v = 1 atm, K0 = 0.5 and CSR =
/// `target_crr` reaches 3 % single-amplitude shear strain in `cycles` uniform cycles;
/// bisection on ln h_po within [0.005, 50]. Throws Error when the bracket holds no root.
struct Calibration {
  double contraction_rate;
  double cycles;  ///< N at the calibrated h_po
  int iterations;
};
Calibration calibrate_contraction_rate(Material material, double target_crr, double cycles = 15.0);

}  // namespace slide::element_test
