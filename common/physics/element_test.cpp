#include "common/physics/element_test.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <string_view>

#include "common/base/error.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/pm4sand.hpp"

namespace slide::element_test {
namespace {

/// One point of a simple-shear sample: its model, stress, state and records.
class Specimen {
 public:
  Specimen(const Material& material, const Consolidation& start)
      : model_(ConstitutiveModel::from(material, Phase::fem)),
        records_(static_cast<std::size_t>(std::max(model_.surfaces(), 1)), Vec4::Zero()),
        initial_vertical_(start.vertical_stress) {
    const double v = start.vertical_stress;
    const double h = start.k0 * v;
    stress_ = {-h, -v, -h, 0.0};
    model_.start(stress_, state_, surfaces());
  }

  /// Shears by dγ: constant volume (undrained), or with εyy found so that σ′v stays
  /// (drained; a few iterations on the elastic constrained modulus, each from the
  /// saved state).
  void shear(double d_gamma, Drainage drainage) {
    if (drainage == Drainage::undrained) {
      apply({0.0, 0.0, 0.0, d_gamma});
      return;
    }
    const Specimen saved = *this;
    const double target = saved.stress_[1];
    // Secant iterations on Δεyy, the first step on the elastic constrained modulus. The
    // model's response is not smooth at the scale of 1e-4 σ′v (its elastic–plastic
    // switches and adaptive sub-steps), so the best iterate within 1e-3 σ′v0 is taken
    // when 1e-7 σ′v0 is not reached.
    double x0 = 0.0;
    apply({0.0, x0, 0.0, d_gamma});
    double r0 = stress_[1] - target;
    double best_x = x0;
    double best_r = r0;
    double x1 = -r0 / (3.0 * model_.shear_modulus() + model_.lame_lambda());
    for (int iteration = 0; iteration < 30 && std::abs(best_r) > 1e-7 * initial_vertical_;
         ++iteration) {
      *this = saved;
      apply({0.0, x1, 0.0, d_gamma});
      const double r1 = stress_[1] - target;
      if (std::abs(r1) < std::abs(best_r)) best_x = x1, best_r = r1;
      const double slope = (r1 - r0) / (x1 - x0);
      if (slope == 0.0 || !std::isfinite(slope)) break;
      x0 = x1;
      r0 = r1;
      x1 -= r1 / slope;
    }
    if (std::abs(best_r) > 1e-3 * initial_vertical_) {
      throw Error("element test: drained simple shear: σ′v held only to {:.3g} Pa", best_r);
    }
    *this = saved;
    apply({0.0, best_x, 0.0, d_gamma});
  }

  Sample sample(double cycles) const {
    Sample s{};
    s.cycles = cycles;
    s.shear_strain = strain_[3];
    s.shear_stress = stress_[3];
    s.vertical_stress = -stress_[1];
    s.horizontal_stress = -stress_[0];
    s.mean_stress = 0.5 * (s.vertical_stress + s.horizontal_stress);
    const double radius = std::hypot(0.5 * (stress_[0] - stress_[1]), stress_[3]);
    s.stress_ratio = s.mean_stress > 0.0 ? 2.0 * radius / s.mean_stress : 0.0;
    s.volumetric_strain = -(strain_[0] + strain_[1]);
    s.pore_pressure_ratio = 1.0 - s.vertical_stress / initial_vertical_;
    return s;
  }

  double shear_stress() const { return stress_[3]; }
  double shear_strain() const { return strain_[3]; }

 private:
  std::span<Vec4> surfaces() {
    return std::span<Vec4>(records_).first(static_cast<std::size_t>(model_.surfaces()));
  }
  void apply(const Vec4& increment) {
    model_.update(stress_, state_, increment, surfaces());
    strain_ += increment;
  }

  ConstitutiveModel model_;
  std::vector<Vec4> records_;
  Vec4 stress_ = Vec4::Zero();
  Vec4 strain_ = Vec4::Zero();
  MaterialState state_;
  double initial_vertical_;
};

/// The phase (in cycles) of a sinusoidal stress history τ = τ_c sin 2πN at stress τ in
/// loading segment `segment` (0: the first quarter, k ≥ 1: the k-th half cycle) heading
/// for sign(direction) τ_c.
double phase(int segment, double direction, double tau, double amplitude) {
  const double s = std::asin(std::clamp(direction * tau / amplitude, -1.0, 1.0));
  const double pi = std::numbers::pi;
  const double theta = segment == 0 ? s : pi / 2.0 + (segment - 1) * pi + s + pi / 2.0;
  return theta / (2.0 * pi);
}

/// Refuses a non-positive (or NaN) argument of a test, naming them all.
void require_positive(std::initializer_list<double> values, std::string_view names) {
  for (double v : values) {
    if (!(v > 0.0)) {
      std::string list;
      for (double w : values) list += fmt::format("{}{}", list.empty() ? "" : ", ", w);
      throw Error("element test: {} = {} must all be > 0", names, list);
    }
  }
}

/// The single-amplitude strain peak of each half cycle, for the cycles at which their
/// envelope crosses a strain limit.
class PeakEnvelope {
 public:
  void observe(double strain, double cycles) {
    if (strain > current_.strain) current_ = {strain, cycles};
  }
  void next_half_cycle() {
    previous_ = current_;
    current_ = {};
  }
  /// Where the envelope crosses `limit` between the last two peaks: log-linear in strain,
  /// linear from the unsheared start.
  double crossing(double limit) const {
    const bool from_start = previous_.strain <= 0.0;
    const double a = from_start ? 0.0 : std::log(previous_.strain);
    const double b = from_start ? current_.strain : std::log(current_.strain);
    const double x = from_start ? limit : std::log(limit);
    const double share = b > a ? std::clamp((x - a) / (b - a), 0.0, 1.0) : 1.0;
    return previous_.cycles + share * (current_.cycles - previous_.cycles);
  }

 private:
  struct Peak {
    double strain = 0.0;
    double cycles = 0.0;
  };
  Peak current_;
  Peak previous_;
};

}  // namespace

std::vector<Sample> monotonic(const Material& material, const Consolidation& start,
                              Drainage drainage, double gamma_max, double d_gamma) {
  require_positive({gamma_max, d_gamma}, "γ_max, dγ");
  Specimen specimen(material, start);
  std::vector<Sample> history{specimen.sample(0.0)};
  const auto steps = static_cast<std::size_t>(std::ceil(gamma_max / d_gamma));
  for (std::size_t i = 0; i < steps; ++i) {
    specimen.shear(d_gamma, drainage);
    history.push_back(specimen.sample(0.0));
  }
  return history;
}

CyclicResult cyclic(const Material& material, const Consolidation& start, double csr,
                    double max_cycles, double strain_limit, double d_gamma,
                    std::size_t keep_every) {
  require_positive({csr, d_gamma, strain_limit, max_cycles}, "CSR, dγ, strain limit, cycles");
  constexpr double reach = 1e-3;  // a reversal within 0.1 % of the target stress
  const double amplitude = csr * start.vertical_stress;
  Specimen specimen(material, start);
  CyclicResult result{.history = {specimen.sample(0.0)}};
  int segment = 0;
  double direction = 1.0;
  double step = d_gamma;
  std::size_t count = 0;
  PeakEnvelope peaks;
  bool crossed = false;
  // A bound on the work: every half cycle is at most a few strain limits long.
  const double budget = (2.0 * max_cycles + 2.0) * (4.0 * strain_limit / d_gamma + 1e4);
  for (double taken = 0.0; taken < budget; taken += 1.0) {
    const Specimen saved = specimen;
    specimen.shear(direction * step, Drainage::undrained);
    const double tau = direction * specimen.shear_stress();
    if (tau > amplitude * (1.0 + reach) && step > 1e-9 * d_gamma) {
      specimen = saved;  // overshot the reversal: a shorter step
      step *= 0.5;
      continue;
    }
    const double cycles = phase(segment, direction, specimen.shear_stress(), amplitude);
    const Sample now = specimen.sample(cycles);
    result.max_pore_pressure_ratio =
        std::max(result.max_pore_pressure_ratio, now.pore_pressure_ratio);
    if (++count % keep_every == 0) result.history.push_back(now);
    const double strain = std::abs(specimen.shear_strain());
    peaks.observe(strain, cycles);
    crossed = crossed || strain >= strain_limit;
    const bool reversal = tau >= amplitude * (1.0 - reach);
    if (crossed && (reversal || strain >= 10.0 * strain_limit)) {
      result.cycles_to_strain = peaks.crossing(strain_limit);
      result.history.push_back(now);
      return result;
    }
    if (cycles >= max_cycles) return result;
    if (reversal) {
      result.history.push_back(now);
      direction = -direction;
      ++segment;
      step = d_gamma;
      peaks.next_half_cycle();
    }
  }
  throw Error("element test: cyclic simple shear did not finish within {} steps", budget);
}

std::vector<Sample> cyclic_strain(const Material& material, const Consolidation& start,
                                  double amplitude, double cycles, double d_gamma) {
  if (!(amplitude > 0.0) || !(cycles > 0.0) || !(d_gamma > 0.0) || d_gamma > amplitude) {
    throw Error("element test: strain amplitude {}, cycles {}, dγ {}: expected 0 < dγ ≤ amplitude",
                amplitude, cycles, d_gamma);
  }
  Specimen specimen(material, start);
  std::vector<Sample> history{specimen.sample(0.0)};
  // γ follows a triangle wave 0 → a → −a → 0 …, each quarter cycle in equal steps.
  const auto per_quarter = static_cast<std::size_t>(std::ceil(amplitude / d_gamma));
  const double step = amplitude / static_cast<double>(per_quarter);
  const auto quarters = static_cast<std::size_t>(std::ceil(4.0 * cycles));
  for (std::size_t q = 0; q < quarters; ++q) {
    const double direction = (q % 4 == 0 || q % 4 == 3) ? 1.0 : -1.0;
    for (std::size_t k = 1; k <= per_quarter; ++k) {
      specimen.shear(direction * step, Drainage::undrained);
      const double phase =
          (static_cast<double>(q) + static_cast<double>(k) / static_cast<double>(per_quarter)) /
          4.0;
      history.push_back(specimen.sample(phase));
    }
  }
  return history;
}

double idriss_boulanger_crr(double n) {
  return std::exp(n / 14.1 + std::pow(n / 126.0, 2) - std::pow(n / 23.6, 3) +
                  std::pow(n / 25.4, 4) - 2.8);
}

double default_target_crr(double relative_density) {
  return idriss_boulanger_crr(pm4sand::blow_count(relative_density));
}

Calibration calibrate_contraction_rate(Material material, double target_crr, double cycles) {
  if (!(target_crr > 0.0 && target_crr < 2.0)) {
    throw Error("calibration: target CRR = {} (expected 0 < CRR < 2)", target_crr);
  }
  const Consolidation atmosphere{material.pm4sand.atmospheric_pressure, 0.5};
  // Cycles to 3 % strain at h_po, counting "never" as beyond the bracket.
  auto cycles_at = [&](double h_po) {
    material.pm4sand.contraction_rate = h_po;
    const CyclicResult r =
        cyclic(material, atmosphere, target_crr, 4.0 * cycles, 0.03, 1e-5, 1u << 30);
    return std::isnan(r.cycles_to_strain) ? 4.0 * cycles : r.cycles_to_strain;
  };
  double lo = std::log(0.005);
  double hi = std::log(50.0);
  const double n_lo = cycles_at(std::exp(lo));
  const double n_hi = cycles_at(std::exp(hi));
  if (n_lo > cycles || n_hi < cycles) {
    throw Error(
        "calibration: D_R = {} reaches 3 % strain at CSR = {} in {:.1f} to {:.1f} cycles for h_po "
        "from 0.005 to 50, not in {} (change G₀ or the target CRR)",
        material.pm4sand.relative_density, target_crr, n_lo, n_hi, cycles);
  }
  Calibration out{std::exp(hi), n_hi, 0};
  for (out.iterations = 1; out.iterations <= 40; ++out.iterations) {
    const double mid = 0.5 * (lo + hi);
    const double n = cycles_at(std::exp(mid));
    out = {std::exp(mid), n, out.iterations};
    if (std::abs(n - cycles) < 0.01 * cycles) break;
    (n < cycles ? lo : hi) = mid;
  }
  return out;
}

}  // namespace slide::element_test
