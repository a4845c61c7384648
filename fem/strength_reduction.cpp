#include "fem/strength_reduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "common/io/atomic_file.hpp"
#include "fem/fem_solver.hpp"

namespace slide::fem {

namespace {

constexpr double degrees = std::numbers::pi / 180.0;
constexpr double smallest_factor = 0.05;
constexpr double largest_factor = 20.0;
constexpr double bracket_step = 1.5;  ///< F grows or shrinks by this until it brackets

}  // namespace

Case reduced_case(const Case& c, double factor, double duration) {
  Case reduced = c;
  for (Material& m : reduced.materials) {
    if (m.model == MaterialModel::linear_elastic) continue;
    m.model = MaterialModel::mohr_coulomb;
    const double phi = std::atan(std::tan(m.friction_angle * degrees) / factor) / degrees;
    m.friction_angle = phi;
    m.cohesion /= factor;
    m.dilation_angle = std::min(m.dilation_angle, phi);
    if (std::isfinite(m.tension_cutoff)) m.tension_cutoff /= factor;
  }
  FemSpec& fem = reduced.fem;
  fem.friction_coefficient /= factor;
  fem.failure_stage = true;
  fem.end_time = duration;
  fem.checkpoint_times.clear();
  fem.checkpoint_every = 0.0;
  fem.output_every = std::min(fem.output_every > 0.0 ? fem.output_every : 0.1, duration / 20.0);
  fem.vtk_every.reset();
  fem.damping = DampingSpec{};
  fem.damping.local = strength_reduction_damping;
  // A shaken stage's base is rock, rigid or compliant, which the soil does not slide on:
  // the static equivalent is a fixed base, not the roller its motion drives (a roller
  // would let the whole body slide on a frictionless base at any factor).
  if (fem.motion) fem.failure_boundaries["base"] = BoundaryCondition::fixed;
  fem.motion.reset();
  fem.recorders.clear();
  return reduced;
}

ElementType strength_reduction_element(const Case& c, const FemOptions& options) {
  if (options.element) return *options.element;
  return c.mesh.element_type == ElementType::quad4_1gp ? ElementType::quad4_2x2
                                                       : c.mesh.element_type;
}

bool in_equilibrium(double ke_end_over_peak, double max_displacement, double height) {
  return ke_end_over_peak < equilibrium_energy_ratio &&
         max_displacement <= equilibrium_displacement_ratio * height;
}

double mesh_height(const Mesh& mesh) {
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (const Vec2& x : mesh.nodes) {
    low = std::min(low, x.y());
    high = std::max(high, x.y());
  }
  return high - low;
}

double strength_trial_duration(const Case& c, const Mesh& mesh) {
  double shear_wave_speed = std::numeric_limits<double>::infinity();
  for (const Material& m : c.materials) {
    shear_wave_speed = std::min(shear_wave_speed, std::sqrt(m.shear_modulus() / m.density));
  }
  const double period = 4.0 * mesh_height(mesh) / shear_wave_speed;
  return 20.0 * period;
}

namespace {

/// One trial: the reduced model from its geostatic state for `duration` seconds. A run
/// that the instability guard stops has not reached equilibrium either.
StrengthTrial run_trial(const Case& c, const FemOptions& options, double factor, double duration,
                        double height) {
  StrengthTrial trial;
  trial.factor = factor;
  FemOptions trial_options = options;
  trial_options.element = strength_reduction_element(c, options);
  trial_options.output_dir = options.output_dir / fmt::format("F{:.4f}", factor);
  trial_options.write_vtk = false;
  trial_options.until.reset();
  trial.folder = trial_options.output_dir;
  const Logger muted("fem-solve", true, true);
  const FemPlan plan = plan_fem(reduced_case(c, factor, duration), trial_options, muted);
  try {
    const FemRunSummary summary = run_fem(plan, muted);
    trial.ke_end_over_peak =
        summary.ke_over_pe0_max > 0.0 ? summary.ke_over_pe0_end / summary.ke_over_pe0_max : 0.0;
    trial.max_displacement = summary.max_displacement;
    trial.stable = in_equilibrium(trial.ke_end_over_peak, trial.max_displacement, height);
  } catch (const Error&) {
    trial.ke_end_over_peak = std::numeric_limits<double>::infinity();
    trial.stable = false;  // the guard stopped it: far from equilibrium
  }
  return trial;
}

std::string report_text(const Case& c, const StrengthReduction& r) {
  std::string text = fmt::format(
      "# fem-solve --strength-reduction of case {} (docs/method.md §3, \"Factor of safety\")\n"
      "factor_of_safety = {:.4f}\nfailing_factor = {:.4f}\ntrial_duration = {:.4g}\n"
      "criterion = Mohr-Coulomb with tan(phi)/F and c/F, Cundall local damping {}; "
      "equilibrium when KE at the end is below {:g} of its peak and no node moved more "
      "than {:g} of the model height ({:.4g} m)\n"
      "# factor, stable, ke_end_over_peak, max_displacement_m, folder\n",
      c.name, r.factor_of_safety, r.failing_factor, r.duration, strength_reduction_damping,
      equilibrium_energy_ratio, equilibrium_displacement_ratio, r.height);
  for (const auto& t : r.trials) {
    text += fmt::format("{:.4f}, {}, {:.3e}, {:.4g}, {}\n", t.factor, t.stable ? "yes" : "no",
                        t.ke_end_over_peak, t.max_displacement, t.folder.filename().string());
  }
  return text;
}

/// Grows F from 1 by bracket_step away from the side the first trial is on, until a
/// stable and a failing factor bracket the failure (`trial` records both); Error outside
/// smallest_factor … largest_factor.
template <typename Trial>
void bracket(const Trial& trial, const double& stable, const double& failing) {
  double factor = 1.0;
  if (trial(factor)) {
    while (failing == 0.0) {
      factor *= bracket_step;
      if (factor > largest_factor) {
        throw Error(
            "strength reduction: the model is still in equilibrium at F = {:.3g}: "
            "it does not fail by strength (is every material elastic?)",
            largest_factor);
      }
      trial(factor);
    }
    return;
  }
  while (stable == 0.0) {
    factor /= bracket_step;
    if (factor < smallest_factor) {
      throw Error(
          "strength reduction: the model does not reach equilibrium even at F = "
          "{:.3g}: it fails for another reason than its strength",
          smallest_factor);
    }
    trial(factor);
  }
}

}  // namespace

StrengthReduction run_strength_reduction(const Case& c, const FemOptions& options,
                                         const Logger& log) {
  if (options.restart || options.until) {
    throw Error(
        "--strength-reduction runs from the case's geostatic state: it takes no "
        "--restart or --until");
  }
  StrengthReduction result;
  {
    const Logger muted("fem-solve", true, true);
    const FemPlan plan = plan_fem(reduced_case(c, 1.0, 1.0), options, muted);
    result.duration = strength_trial_duration(c, plan.mesh);
    result.height = mesh_height(plan.mesh);
  }
  log.info(
      "strength reduction: {} elements, trials of {:.3g} s (20 periods of the first shear "
      "mode), Cundall α = {}; equilibrium when KE ends below {:g} of its peak and no node "
      "moved more than {:.3g} m ({:g} of the model height)",
      to_string(strength_reduction_element(c, options)), result.duration,
      strength_reduction_damping, equilibrium_energy_ratio,
      equilibrium_displacement_ratio * result.height, equilibrium_displacement_ratio);

  double stable = 0.0, failing = 0.0;  // 0: not found yet
  const auto trial = [&](double factor) {
    StrengthTrial t = run_trial(c, options, factor, result.duration, result.height);
    log.info("F = {:.4f}: {} (KE end/peak {:.2e}, largest |u| {:.3g} m)", factor,
             t.stable ? "equilibrium" : "fails", t.ke_end_over_peak, t.max_displacement);
    // Monotone in every phase below: the bracket grows from 1 away from the known side,
    // the bisection narrows it.
    (t.stable ? stable : failing) = factor;
    result.trials.push_back(t);
    return t.stable;
  };

  bracket(trial, stable, failing);
  while ((failing - stable) / stable > strength_reduction_tolerance) {
    trial(0.5 * (stable + failing));
  }
  result.factor_of_safety = stable;
  result.failing_factor = failing;
  write_text_atomically(options.output_dir / "strength_reduction.txt", report_text(c, result));
  return result;
}

}  // namespace slide::fem
