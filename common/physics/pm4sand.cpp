// PM4Sand version 3.1 (Boulanger & Ziotopoulou 2017, "PM4Sand (Version 3.1): a sand
// plasticity model for earthquake engineering applications", report UCD/CGM-17/01),
// integrated as the open-source implementation integrates it (Chen & Arduino, OpenSees:
// sub-increments of at most 1e-5 strain, modified Euler with error control, a drift
// correction, the small-p′ rules). The equations, their sources and the places where
// this code departs from the reference implementation are in
// common/physics/constitutive.md ("PM4Sand"), whose headings the comments below name.
//
// Internally: compression positive, in-plane tensors [xx, yy, xy] with the double
// contraction a:b = axx bxx + ayy byy + 2 axy bxy, strains as tensors (εxy = γxy/2).
#include "common/physics/pm4sand.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/base/error.hpp"
#include "common/physics/constitutive.hpp"

namespace slide::pm4sand {
namespace {

constexpr double sqrt2 = std::numbers::sqrt2;
constexpr double tiny = 1e-10;

/// A symmetric in-plane tensor.
struct Tensor {
  double xx = 0.0;
  double yy = 0.0;
  double xy = 0.0;

  Tensor& operator+=(const Tensor& b) {
    xx += b.xx, yy += b.yy, xy += b.xy;
    return *this;
  }
  Tensor& operator-=(const Tensor& b) {
    xx -= b.xx, yy -= b.yy, xy -= b.xy;
    return *this;
  }
  Tensor& operator*=(double a) {
    xx *= a, yy *= a, xy *= a;
    return *this;
  }
  friend Tensor operator+(Tensor a, const Tensor& b) { return a += b; }
  friend Tensor operator-(Tensor a, const Tensor& b) { return a -= b; }
  friend Tensor operator*(double a, Tensor b) { return b *= a; }
};

constexpr Tensor identity{1.0, 1.0, 0.0};

double dot(const Tensor& a, const Tensor& b) {
  return a.xx * b.xx + a.yy * b.yy + 2.0 * a.xy * b.xy;
}
double norm(const Tensor& a) {
  return std::sqrt(dot(a, a));
}
double trace_mean(const Tensor& a) {
  return 0.5 * (a.xx + a.yy);
}
Tensor deviator(const Tensor& a) {
  const double p = trace_mean(a);
  return {a.xx - p, a.yy - p, a.xy};
}
double macaulay(double x) {
  return x > 0.0 ? x : 0.0;
}

Tensor tensor(const Vec4& r) {
  return {r[0], r[1], r[3]};
}
Vec4 record(const Tensor& t) {
  return {t.xx, t.yy, 0.0, t.xy};
}

/// The unpacked records of a point.
struct Point {
  Tensor alpha, alpha_in, alpha_in_p, alpha_in_true, alpha_in_max, alpha_in_min, z, z_in;
  double z_cum, z_peak, p_zp, z_xp;
  double z_max, a_do, p_min, volumetric_strain;
};

Point unpack(std::span<const Vec4> r) {
  Point p;
  p.alpha = tensor(r[back_stress]);
  p.alpha_in = tensor(r[apparent_reversal]);
  p.alpha_in_p = tensor(r[previous_reversal]);
  p.alpha_in_true = tensor(r[true_reversal]);
  p.alpha_in_max = tensor(r[reversal_maximum]);
  p.alpha_in_min = tensor(r[reversal_minimum]);
  p.z = tensor(r[fabric]);
  p.z_in = tensor(r[fabric_at_reversal]);
  const Vec4& f = r[fabric_measures];
  p.z_cum = f[0], p.z_peak = f[1], p.p_zp = f[2], p.z_xp = f[3];
  const Vec4& s = r[switch_constants];
  p.z_max = s[0], p.a_do = s[1], p.p_min = s[2], p.volumetric_strain = s[3];
  return p;
}

void pack(const Point& p, std::span<Vec4> r) {
  r[back_stress] = record(p.alpha);
  r[apparent_reversal] = record(p.alpha_in);
  r[previous_reversal] = record(p.alpha_in_p);
  r[true_reversal] = record(p.alpha_in_true);
  r[reversal_maximum] = record(p.alpha_in_max);
  r[reversal_minimum] = record(p.alpha_in_min);
  r[fabric] = record(p.z);
  r[fabric_at_reversal] = record(p.z_in);
  r[fabric_measures] = {p.z_cum, p.z_peak, p.p_zp, p.z_xp};
  r[switch_constants] = {p.z_max, p.a_do, p.p_min, p.volumetric_strain};
}

/// D_R after the volumetric strain εv since the switch (compression positive): the void
/// ratio e = e₀ − (1 + e₀) εv.
double density_after(const Constants& c, double volumetric_strain) {
  const double e = c.e0 - (1.0 + c.e0) * volumetric_strain;
  return (c.e_max - e) / (c.e_max - c.e_min);
}
double density_now(const Constants& c, const Point& pt) {
  return density_after(c, pt.volumetric_strain);
}

/// The in-plane stress, compression positive, and back.
Tensor compression(const Vec4& stress) {
  return {-stress[0], -stress[1], -stress[3]};
}
void store(const Tensor& sigma, Vec4& stress) {
  stress = {-sigma.xx, -sigma.yy, -trace_mean(sigma), -sigma.xy};
}

/// The yield function f = |s − pα| − m p/√2.
double yield(const Constants& c, const Tensor& sigma, const Tensor& alpha) {
  const double p = trace_mean(sigma);
  return norm(deviator(sigma) - p * alpha) - c.m * p / sqrt2;
}

/// The unit normal n = (r − α)/|r − α|; at p ≈ 0, the simple-shear direction.
Tensor normal(const Tensor& sigma, const Tensor& alpha) {
  const double p = trace_mean(sigma);
  if (std::abs(p) < tiny) return {0.0, 0.0, 1.0 / sqrt2};
  Tensor n = deviator(sigma) - p * alpha;
  const double size = norm(n);
  return (1.0 / (size < tiny ? 1.0 : size)) * n;
}

/// The stress ratio q/p of an in-plane stress (q = σ1 − σ3), with p floored.
double ratio_of(const Tensor& sigma, double p_floor) {
  const double p = std::max(trace_mean(sigma), p_floor);
  const double q = 2.0 * std::hypot(0.5 * (sigma.xx - sigma.yy), sigma.xy);
  return q / p;
}

struct Moduli {
  double shear;
  double bulk;
};

/// G = G₀ p_A sqrt(p/p_A) C_SR (1 + z_cum/z_max)/(1 + C_GD z_cum/z_max), K from ν
/// ("Elasticity"); the stress-ratio factor C_SR = 1 − 0.5 min(1, (q/(p M_b))⁴).
Moduli moduli(const Constants& c, const Tensor& sigma, const Point& pt, double bounding) {
  const double p = std::max(trace_mean(sigma), pt.p_min);
  const double stress_ratio = ratio_of(sigma, pt.p_min);
  const double c_sr = 1.0 - 0.5 * std::min(1.0, std::pow(stress_ratio / bounding, 4));
  const double fabric = pt.z_cum / pt.z_max;
  const double shear =
      c.g0 * c.p_a * std::sqrt(p / c.p_a) * c_sr * (1.0 + fabric) / (1.0 + c.c_gd * fabric);
  return {shear, c.bulk_ratio() * shear};
}

/// The moduli at a point's stress, with M_b of its p and D_R.
Moduli moduli_at(const Constants& c, const Tensor& sigma, const Point& pt,
                 double relative_density) {
  return moduli(c, sigma, pt, ratios(c, trace_mean(sigma), relative_density).bounding);
}

/// The deviatoric part of a strain tensor, Δe = Δε − Δεv/3 I (plane strain: Δεzz = 0).
Tensor strain_deviator(const Tensor& eps) {
  const double volumetric = eps.xx + eps.yy;
  return {eps.xx - volumetric / 3.0, eps.yy - volumetric / 3.0, eps.xy};
}

/// The elastic stress increment 2G Δe + K Δεv I.
Tensor elastic_increment(const Moduli& g, const Tensor& eps) {
  return 2.0 * g.shear * strain_deviator(eps) + (g.bulk * (eps.xx + eps.yy)) * identity;
}

/// The stress ratio brought back to `limit` at the same p, and α to (limit − m)/limit of
/// the new ratio (the reference implementation's rule at the switch and after each step).
void scale_ratio(const Constants& c, Tensor& sigma, Tensor& alpha, double p, double now,
                 double limit) {
  const Tensor r = (limit / now / p) * deviator(sigma);
  sigma = p * identity + p * r;
  alpha = ((limit - c.m) / limit) * r;
}

/// What the flow rule needs at one state ("Bounding and dilatancy surfaces",
/// "Plastic modulus", "Dilatancy").
struct Flow {
  Tensor n;        // loading direction
  Tensor b;        // α_b − α
  double h;        // hardening ratio
  double k_p;      // plastic modulus
  double d;        // dilatancy (positive: contraction)
  Tensor alpha_d;  // dilatancy back-stress ratio
};

/// The fabric's cumulative factors C_zpk1, C_zpk2 (plastic modulus, contraction).
double peak_factor_1(const Point& pt) {
  return pt.z_peak / (pt.z_cum + pt.z_max / 5.0);
}
double peak_factor_2(const Point& pt) {
  return std::min(pt.z_peak / (pt.z_cum + pt.z_max / 100.0), 1.0 - tiny);
}

/// The hardening ratio h and the plastic modulus K_p ("Plastic modulus").
void plastic_modulus(const Constants& c, Flow& f, const Tensor& alpha, const Point& pt, double p,
                     double shear) {
  const Tensor& n = f.n;
  const double b_n = dot(f.b, n);
  const double c_pzp2 = macaulay(pt.p_zp - p) / (macaulay(pt.p_zp - p) + pt.p_min);
  const double c_gamma1 = c.h0 / 200.0;
  constexpr double c_kp = 2.0;
  const double from_apparent = macaulay(dot(alpha - pt.alpha_in, n));
  const double from_true = macaulay(dot(alpha - pt.alpha_in_true, n));
  const double c_ka =
      1.0 + c.c_kaf / (1.0 + std::pow(2.5 * from_true, 2)) * c_pzp2 * peak_factor_1(pt);
  if (std::abs(b_n) < tiny) {
    f.h = 1e10;
  } else {
    f.h = 1.5 * shear * c.h0 / p / (std::exp(from_apparent) - 1.0 + c_gamma1) /
          std::sqrt(std::abs(b_n)) * c_ka /
          (1.0 + c_kp * pt.z_peak / pt.z_max * macaulay(b_n) * std::sqrt(1.0 - peak_factor_2(pt)));
    if (dot(alpha - pt.alpha_in_p, n) <= 0.0) {
      f.h *= (from_apparent + c_gamma1) / (from_true + c_gamma1);
    }
  }
  f.k_p = 2.0 / 3.0 * f.h * p * b_n;
}

/// D when dilating past the rotated dilatancy surface ("Dilatancy", first case).
double dilation(const Constants& c, const Tensor& sigma, const Point& pt, double p,
                const Ratios& bd, double z_n, double c_zin1, double to_d, double to_dr) {
  const double c_pzp = pt.p_zp == 0.0 ? 1.0 : 1.0 / (1.0 + std::pow(2.5 * p / pt.p_zp, 5));
  const double c_pmin = 1.0 / (1.0 + std::pow(10.0 * pt.p_min / p, 2));
  const double excess = c_zin1 * (pt.z_cum - pt.z_peak) / (3.0 * pt.z_max);
  const double c_zin2 = (1.0 + excess) / (1.0 + 3.0 * excess);
  const double erased = std::pow(1.0 - macaulay(-z_n) / sqrt2 / pt.z_peak, 3);
  const double a_d =
      pt.a_do * c_zin2 /
      (pt.z_cum * pt.z_cum / pt.z_max * erased * c.c_e * c.c_e * c_pzp * c_pmin * c_zin1 + 1.0);
  double d = a_d * to_d;
  const double d_rot = a_d * macaulay(-z_n) / (sqrt2 * pt.z_max) * to_dr / c.c_dr;
  if (d > d_rot) {
    const double below = macaulay(bd.bounding - ratio_of(sigma, pt.p_min));
    d += (d_rot - d) * below / (below + 0.01);
  }
  if (pt.p_min <= p && p <= 2.0 * pt.p_min) {
    d = std::min(
        d, -3.5 * pt.a_do * macaulay(bd.bounding - bd.dilatancy) * (2.0 * pt.p_min - p) / pt.p_min);
  }
  return d;
}

/// D when contracting ("Dilatancy", second case).
double contraction(const Constants& c, const Tensor& alpha, const Point& pt, double p,
                   const Ratios& bd, const Tensor& n, double z_n, double to_d) {
  const double h_p =
      c.h_po * std::exp(-0.7 + 7.0 * std::pow(macaulay(0.5 - bd.state_parameter), 2));
  const double c_rot2 = 1.0 - peak_factor_2(pt);
  const double c_dz = std::max(
      (1.0 - c_rot2 * sqrt2 * pt.z_peak / pt.z_max) * (pt.z_max / (pt.z_max + c_rot2 * pt.z_cum)),
      1.0 / (1.0 + pt.z_max / 2.0));
  const double a_dc = pt.a_do * (1.0 + macaulay(z_n)) / h_p / c_dz;
  const double c_in = 2.0 * macaulay(z_n) / sqrt2 / pt.z_max;
  const double d = std::min(a_dc * std::pow(dot(alpha - pt.alpha_in, n) + c_in, 2), 1.5 * pt.a_do) *
                   to_d / (to_d + 0.16);
  // No contraction near p_min, full contraction above 18 p_min (the small-p′ rule).
  return d * std::clamp((p - 2.0 * pt.p_min) / (16.0 * pt.p_min), 0.0, 1.0);
}

Flow flow(const Constants& c, const Tensor& sigma, const Tensor& alpha, const Tensor& z,
          const Point& pt, double relative_density, double shear) {
  Flow f;
  const double p = std::max(trace_mean(sigma), pt.p_min);
  const Ratios bd = ratios(c, p, relative_density);
  f.n = normal(sigma, alpha);
  const Tensor& n = f.n;
  f.alpha_d = ((bd.dilatancy - c.m) / sqrt2) * n;
  f.b = ((bd.bounding - c.m) / sqrt2) * n - alpha;
  plastic_modulus(c, f, alpha, pt, p, shear);

  // Dilatancy: the rotated dilatancy surface decides between dilation and contraction.
  const double z_n = dot(z, n);
  const double c_zin1 =
      macaulay(1.0 - std::exp(-2.0 * std::abs((dot(pt.z_in, n) - z_n) / pt.z_max)));
  const double c_rot1 =
      std::max(1.0 + 2.0 * macaulay(-z_n) / (sqrt2 * pt.z_max) * (1.0 - c_zin1), 1.0);
  const Tensor alpha_dr = ((bd.dilatancy / c_rot1 - c.m) / sqrt2) * n;
  const double to_d = dot(f.alpha_d - alpha, n);
  const double to_dr = dot(alpha_dr - alpha, n);
  if (to_dr <= 0.0) {
    f.d = dilation(c, sigma, pt, p, bd, z_n, c_zin1, to_d, to_dr);
  } else {
    f.k_p = std::max(0.0, f.k_p);
    f.d = contraction(c, alpha, pt, p, bd, n, z_n, to_d);
  }
  return f;
}

/// The change of one explicit stage.
struct Change {
  Tensor sigma;
  Tensor alpha;
  Tensor z;
  double loading = 0.0;  // L ≥ 0
  double dilatancy = 0.0;
};

/// One forward stage over the strain increment `eps` (tensor, compression positive):
/// dσ = 2G de + K dεv I − ⟨L⟩(2G n + K D I), dα = ⅔ L h b, the fabric's growth when
/// dilating past the dilatancy surface ("Flow rule", "Fabric").
Change stage(const Constants& c, const Tensor& sigma, const Tensor& alpha, const Tensor& z,
             const Point& pt, double relative_density, const Moduli& g, const Tensor& eps) {
  const double volumetric = eps.xx + eps.yy;
  const Tensor de = strain_deviator(eps);
  Change change;
  const Tensor elastic = elastic_increment(g, eps);
  const Flow f = flow(c, sigma, alpha, z, pt, relative_density, g.shear);
  const double p = trace_mean(sigma);
  const Tensor r = (1.0 / p) * deviator(sigma);
  const double n_r = dot(f.n, r);
  const double denominator = f.k_p + 2.0 * g.shear - g.bulk * f.d * n_r;
  if (std::abs(denominator) < tiny) return change;  // neutral loading
  const double loading = (2.0 * g.shear * dot(f.n, de) - n_r * g.bulk * volumetric) / denominator;
  if (loading < 0.0) {
    change.sigma = elastic;
    return change;
  }
  change.loading = loading;
  change.dilatancy = f.d;
  change.sigma = elastic - loading * (2.0 * g.shear * f.n + (g.bulk * f.d) * identity);
  // dα = ⅔ L h b drives α toward α_b; at the bounding surface (b·n → 0, h → ∞) a tiny L
  // times a huge h would throw α past α_b in one stage (departure from the reference
  // implementation: the move is capped at α_b itself).
  change.alpha = std::min(2.0 / 3.0 * loading * f.h, 1.0) * f.b;
  if (dot(f.alpha_d - alpha, f.n) < 0.0 && f.d < 0.0) {
    const double growth = c.c_z / (1.0 + macaulay(pt.z_cum / (2.0 * pt.z_max) - 1.0));
    change.z = (-growth * loading) * (pt.z_max * f.n + z);
  }
  return change;
}

/// The floor on p′ (the reference implementation's rule): below p_min/5 a stress inside
/// the yield surface is lifted to p_min/5, one outside is replaced by a simple-shear state
/// at p_min/5 with q/p = 0.8 M_c. Returns true when it acted.
bool apply_floor(const Constants& c, Tensor& sigma, Tensor& alpha, const Point& pt,
                 double tolerance) {
  const double floor = pt.p_min / 5.0;
  if (trace_mean(sigma) >= floor) return false;
  if (yield(c, sigma, alpha) < tolerance) {
    sigma += (floor - trace_mean(sigma)) * identity;
  } else {
    sigma = {floor, floor, 0.8 * c.m_c * floor};
    alpha = {0.0, 0.0, 0.8 * c.m_c};
  }
  return true;
}

/// Brings a stress that drifted outside the yield surface back onto it (Potts & Gens
/// 1985 consistent correction along the plastic direction, with α moving by its own
/// hardening), unless it is below the floor on p′.
void correct_drift(const Constants& c, Tensor& sigma, Tensor& alpha, const Tensor& z,
                   const Point& pt, double relative_density, double tolerance) {
  if (apply_floor(c, sigma, alpha, pt, tolerance)) return;
  double f = yield(c, sigma, alpha);
  for (int iteration = 0; iteration < 25 && f > tolerance; ++iteration) {
    const Moduli g = moduli_at(c, sigma, pt, relative_density);
    const Flow fl = flow(c, sigma, alpha, z, pt, relative_density, g.shear);
    const double p = std::max(trace_mean(sigma), pt.p_min);
    const Tensor r = (1.0 / p) * deviator(sigma);
    const Tensor df_dsigma = fl.n - (0.5 * dot(fl.n, r)) * identity;
    const Tensor plastic = 2.0 * g.shear * fl.n + (g.bulk * fl.d) * identity;
    const Tensor hardening = (2.0 / 3.0 * fl.h) * fl.b;
    const double slope = dot(df_dsigma, plastic) + p * dot(fl.n, hardening);
    const double lambda = f / slope;
    const Tensor sigma_try = sigma - lambda * plastic;
    const Tensor alpha_try = alpha + lambda * hardening;
    // A guard the reference implementation lacks: where the dilatancy term cancels most
    // of the elastic one (2G − K D n:r → 0) the slope is flat and the correction would
    // throw the stress far; a correction longer than ten times the distance to the
    // surface gives way to the closest point.
    const double step_size = std::abs(lambda) * norm(plastic);
    const double distance = std::abs(f) / norm(df_dsigma);
    if (slope > 0.0 && step_size < 10.0 * distance &&
        std::abs(yield(c, sigma_try, alpha_try)) < std::abs(f)) {
      sigma = sigma_try;
      alpha = alpha_try;
    } else {  // fall back on the closest point along ∂f/∂σ
      sigma -= (f / dot(df_dsigma, df_dsigma)) * df_dsigma;
    }
    f = yield(c, sigma, alpha);
  }
}

/// Modified Euler with error control over one plastic sub-increment `eps` (relative error 1e-5, the
/// step fraction between 1e-4 and 1).
void integrate_plastic(const Constants& c, Tensor& sigma, Point& pt, const Tensor& eps,
                       MaterialState& state, double tolerance) {
  constexpr double error_tolerance = 1e-5;
  constexpr double smallest = 1e-4;
  double done = 0.0;
  double step = 1.0;
  const double stress_floor = 0.005 * c.p_a;
  while (done < 1.0) {
    const double dr = density_now(c, pt);
    const Tensor part = step * eps;
    const Moduli g = moduli_at(c, sigma, pt, dr);
    const Change one = stage(c, sigma, pt.alpha, pt.z, pt, dr, g, part);
    const Tensor sigma_one = sigma + one.sigma;
    const bool last_chance = step <= smallest;
    if (trace_mean(sigma_one) < 0.0 && !last_chance) {
      step = std::max(0.1 * step, smallest);
      continue;
    }
    const Change two = stage(c, sigma_one, pt.alpha + one.alpha, pt.z + one.z, pt, dr, g, part);
    const Tensor sigma_next = sigma + 0.5 * (one.sigma + two.sigma);
    if (trace_mean(sigma_next) < 0.0 && !last_chance) {
      step = std::max(0.1 * step, smallest);
      continue;
    }
    const double size = norm(sigma);
    const double error =
        norm(two.sigma - one.sigma) / (size < stress_floor ? stress_floor : 2.0 * size);
    if (error > error_tolerance && !last_chance) {
      step = std::max(std::max(0.8 * std::sqrt(error_tolerance / error), 0.1) * step, smallest);
      continue;
    }
    sigma = sigma_next;
    pt.alpha += 0.5 * (one.alpha + two.alpha);
    pt.z += 0.5 * (one.z + two.z);
    const double loading = 0.5 * (one.loading + two.loading);
    const double volumetric = 0.5 * (one.loading * one.dilatancy + two.loading * two.dilatancy);
    const Tensor n = normal(sigma, pt.alpha);
    // Plastic strains, tension positive: εᵖv = −L D; deviatoric |Δeᵖ| = L |n| = L.
    state.plastic_volumetric_strain -= volumetric;
    state.plastic_shear_strain += std::sqrt(2.0 / 3.0) * loading * norm(n);
    correct_drift(c, sigma, pt.alpha, pt.z, pt, dr, tolerance);
    pt.volumetric_strain += step * (eps.xx + eps.yy);
    done += step;
    const double grow = error > 0.0 ? std::max(0.8 * std::sqrt(error_tolerance / error), 0.5) : 2.0;
    step = std::min(std::max(grow * step, smallest), 1.0 - done);
  }
}

/// The fraction a ∈ [lo, hi] of the elastic increment `elastic` at which the yield
/// function crosses zero (Pegasus iterations).
double crossing(const Constants& c, const Tensor& sigma, const Tensor& alpha, const Tensor& elastic,
                double lo, double hi, double tolerance) {
  double f_lo = yield(c, sigma + lo * elastic, alpha);
  double f_hi = yield(c, sigma + hi * elastic, alpha);
  double a = lo;
  for (int i = 0; i < 30; ++i) {
    a = hi - f_hi * (hi - lo) / (f_hi - f_lo);
    const double f = yield(c, sigma + a * elastic, alpha);
    if (std::abs(f) < tolerance) break;
    if (f * f_lo < 0.0) {
      hi = a, f_hi = f;
    } else {
      f_hi = f_hi * f_lo / (f_lo + f);
      lo = a, f_lo = f;
    }
  }
  return std::isfinite(a) ? std::clamp(a, 0.0, 1.0) : 0.0;
}

/// One sub-increment: elastic, or elastic up to the yield surface then plastic.
bool sub_increment(const Constants& c, Tensor& sigma, Point& pt, const Tensor& eps,
                   MaterialState& state, double tolerance) {
  const double dr = density_now(c, pt);
  const Moduli g = moduli_at(c, sigma, pt, dr);
  const double volumetric = eps.xx + eps.yy;
  const Tensor elastic = elastic_increment(g, eps);
  const double f_trial = yield(c, sigma + elastic, pt.alpha);
  if (f_trial <= tolerance) {
    sigma += elastic;
    pt.volumetric_strain += volumetric;
    apply_floor(c, sigma, pt.alpha, pt, tolerance);
    return false;
  }
  const double f_now = yield(c, sigma, pt.alpha);
  double fraction = 0.0;
  if (f_now < -tolerance) {
    fraction = crossing(c, sigma, pt.alpha, elastic, 0.0, 1.0, tolerance);
  } else {
    const double size = norm(elastic);
    const double direction = dot(normal(sigma, pt.alpha), elastic) / (size > 0.0 ? size : 1.0);
    if (direction < -std::sqrt(tolerance / c.p_a)) {
      // Unloads into the surface, then reloads out of it: find where it leaves again.
      constexpr int samples = 20;
      double inside = 0.0;
      for (int k = 1; k <= samples; ++k) {
        const double a = static_cast<double>(k) / samples;
        if (yield(c, sigma + a * elastic, pt.alpha) > tolerance) {
          fraction = crossing(c, sigma, pt.alpha, elastic, inside, a, tolerance);
          break;
        }
        inside = a;
      }
    }
  }
  sigma += fraction * elastic;
  pt.volumetric_strain += fraction * volumetric;
  integrate_plastic(c, sigma, pt, (1.0 - fraction) * eps, state, tolerance);
  return true;
}

/// A loading reversal (the back-stress ratio moving away from α_in,true against the new
/// loading direction): the reversal history and the apparent α_in ("Reversals").
void detect_reversal(const Constants& c, const Tensor& sigma, Point& pt, const Tensor& eps) {
  const Moduli g = moduli_at(c, sigma, pt, density_now(c, pt));
  const Tensor n = normal(sigma + elastic_increment(g, eps), pt.alpha);
  if (dot(pt.alpha - pt.alpha_in_true, n) >= 0.0) return;
  pt.alpha_in_p = pt.alpha_in;
  pt.alpha_in_true = pt.alpha;
  pt.z_in = pt.z;
  const double p = std::max(trace_mean(sigma), pt.p_min);
  const double z_p = norm(pt.z) * p;
  if ((z_p > pt.z_xp && p > pt.p_zp) || pt.z_xp < 0.0) {
    pt.z_xp = z_p;
    pt.p_zp = p;
  }
  auto track = [](double in, double alpha, double& minimum, double& maximum) {
    if (in > 0.0) {
      minimum = std::min(minimum, alpha);
    } else {
      maximum = std::max(maximum, alpha);
    }
  };
  track(pt.alpha_in.xx, pt.alpha.xx, pt.alpha_in_min.xx, pt.alpha_in_max.xx);
  track(pt.alpha_in.yy, pt.alpha.yy, pt.alpha_in_min.yy, pt.alpha_in_max.yy);
  track(pt.alpha_in.xy, pt.alpha.xy, pt.alpha_in_min.xy, pt.alpha_in_max.xy);
  if (pt.alpha.xy * pt.alpha_in_p.xy > 0.0) {
    auto pick = [](double direction, double minimum, double maximum) {
      return direction > 0.0 ? std::max(0.0, minimum) : std::min(0.0, maximum);
    };
    pt.alpha_in = {pick(n.xx, pt.alpha_in_min.xx, pt.alpha_in_max.xx),
                   pick(n.yy, pt.alpha_in_min.yy, pt.alpha_in_max.yy),
                   pick(n.xy, pt.alpha_in_min.xy, pt.alpha_in_max.xy)};
  } else {
    pt.alpha_in = pt.alpha;
  }
}

}  // namespace

double default_shear_modulus_coefficient(double relative_density) {
  return 167.0 * std::sqrt(blow_count(relative_density) + 2.5);
}

namespace {

/// G₀: the given one, else the field default from D_R.
double shear_modulus_coefficient(const Pm4SandParameters& p) {
  return std::isnan(p.shear_modulus_coefficient)
             ? default_shear_modulus_coefficient(p.relative_density)
             : p.shear_modulus_coefficient;
}

}  // namespace

double elastic_stage_youngs_modulus(const Material& material) {
  const Pm4SandParameters& p = material.pm4sand;
  return 2.0 * (1.0 + material.poisson_ratio) * shear_modulus_coefficient(p) *
         p.atmospheric_pressure;
}

Constants Constants::of(const Material& material) {
  const Pm4SandParameters& in = material.pm4sand;
  auto or_default = [](double value, double fallback) {
    return std::isnan(value) ? fallback : value;
  };
  Constants c{};
  const double dr = in.relative_density;
  c.relative_density = dr;
  c.g0 = shear_modulus_coefficient(in);
  c.h_po = in.contraction_rate;
  c.p_a = in.atmospheric_pressure;
  c.h0 = or_default(in.h0, std::max(0.3, (0.25 + dr) / 2.0));
  c.e_max = in.e_max;
  c.e_min = in.e_min;
  c.e0 = c.e_max - (c.e_max - c.e_min) * dr;
  c.n_b = in.n_b;
  c.n_d = in.n_d;
  c.a_do = in.a_do;
  c.z_max = in.z_max;
  c.c_z = in.c_z;
  // The reference implementation's default (it matches FLAC's, not the report's).
  c.c_e = or_default(in.c_e, dr > 0.75 ? 0.2 : (dr < 0.55 ? 0.5 : 0.5 - (dr - 0.55) * 1.5));
  c.m_c = 2.0 * std::sin(in.critical_friction_angle * std::numbers::pi / 180.0);
  c.nu = material.poisson_ratio;
  c.c_gd = in.c_gd;
  c.c_dr = or_default(in.c_dr, std::min(5.0 + 25.0 * (dr - 0.35), 10.0));
  c.c_kaf = or_default(in.c_kaf, std::clamp(5.0 + 220.0 * std::pow(dr - 0.26, 3), 4.0, 35.0));
  c.q = in.q;
  c.r = in.r;
  c.m = in.m;
  c.strain_step = in.strain_step;
  return c;
}

Ratios ratios(const Constants& c, double mean_stress, double relative_density) {
  Ratios out{};
  const double p = std::max(mean_stress, c.p_a / 200.0);
  out.state_parameter = c.r / (c.q - std::log(100.0 * p / c.p_a)) - relative_density;
  const double xi = out.state_parameter;
  // Loose of critical the exponents are a quarter (bounding) and four times
  // (dilatancy) the dense ones.
  out.bounding = c.m_c * std::exp(-(xi <= 0.0 ? c.n_b : c.n_b / 4.0) * xi);
  out.dilatancy = c.m_c * std::exp((xi <= 0.0 ? c.n_d : 4.0 * c.n_d) * xi);
  return out;
}

double relative_density(const Constants& c, std::span<const Vec4> point) {
  return density_after(c, point.empty() ? 0.0 : point[switch_constants][3]);
}

double stress_ratio(const Vec4& stress) {
  return ratio_of(compression(stress), std::numeric_limits<double>::min());
}

double shear_modulus(const Constants& c, const Vec4& stress, std::span<const Vec4> point) {
  const Tensor sigma = compression(stress);
  if (point.empty() || point[switch_constants][2] <= 0.0) {
    return c.g0 * c.p_a * std::sqrt(std::max(trace_mean(sigma), c.p_a / 200.0) / c.p_a);
  }
  const Point pt = unpack(point);
  return moduli_at(c, sigma, pt, density_now(c, pt)).shear;
}

bool start(const Constants& c, Vec4& stress, std::span<Vec4> point) {
  if (point.size() < static_cast<std::size_t>(records)) {
    throw Error("pm4sand: a point needs {} state records, got {}", records, point.size());
  }
  if (point[switch_constants][2] > 0.0) {  // already switched: keep σzz on the rule
    stress[2] = 0.5 * (stress[0] + stress[1]);
    return false;
  }
  const Vec4 before = stress;
  Tensor sigma = compression(stress);
  double p0 = trace_mean(sigma);
  Point pt{};
  pt.p_min = std::max(p0 / 200.0, c.p_a / 200.0);
  if (p0 < pt.p_min) {  // (nearly) unconfined: isotropic at p_min
    sigma = {pt.p_min, pt.p_min, 0.0};
    p0 = pt.p_min;
  }
  pt.alpha = (1.0 / p0) * deviator(sigma);
  const Ratios bd = ratios(c, p0, c.relative_density);
  pt.z_max =
      std::isnan(c.z_max) ? std::min(0.7 * std::exp(-6.1 * bd.state_parameter), 20.0) : c.z_max;
  if (!std::isnan(c.a_do)) {
    pt.a_do = c.a_do;
  } else if (bd.state_parameter < 0.0 && bd.bounding <= 2.0) {
    // The peak friction angle of dense sand in simple shear from Bolton's
    // relation, φ_pk − φ_cv, over M_b − M_d.
    pt.a_do = 2.5 * (std::asin(bd.bounding / 2.0) - std::asin(c.m_c / 2.0)) /
              (bd.bounding - bd.dilatancy);
  } else {
    pt.a_do = bd.bounding > 2.0 ? 1.5 : 1.24;
  }
  // A stress ratio beyond both the bounding and the dilatancy ratio is scaled back.
  const double limit = std::max(bd.bounding, bd.dilatancy);
  const double now = sqrt2 * norm(deviator(sigma)) / p0;
  if (now > limit) scale_ratio(c, sigma, pt.alpha, p0, now, limit);
  pt.alpha_in_true = pt.alpha_in_max = pt.alpha_in_min = pt.alpha;
  pt.z_peak = pt.z_max / 1e5;
  pt.p_zp = std::max(p0, pt.p_min) / 100.0;
  pt.z_xp = -1.0;  // no reversal yet: the first one sets p_zp
  pack(pt, point);
  store(sigma, stress);
  // σzz moving onto its rule is not a return: only an in-plane change counts.
  const double moved = std::max({std::abs(stress[0] - before[0]), std::abs(stress[1] - before[1]),
                                 std::abs(stress[3] - before[3])});
  return moved > 1e-9 * c.p_a;
}

bool update(const Constants& c, Vec4& stress, MaterialState& state, const Vec4& strain_increment,
            std::span<Vec4> point) {
  Point pt = unpack(point);
  Tensor sigma = compression(stress);
  const Tensor eps{-strain_increment[0], -strain_increment[1], -0.5 * strain_increment[3]};
  const Tensor z_before = pt.z;
  const double tolerance = 1e-10 * c.p_a;
  detect_reversal(c, sigma, pt, eps);
  const double largest = std::max({std::abs(eps.xx), std::abs(eps.yy), 2.0 * std::abs(eps.xy)});
  const int parts = largest > c.strain_step ? static_cast<int>(largest / c.strain_step) + 1 : 1;
  const Tensor part = (1.0 / parts) * eps;
  bool plastic = false;
  for (int k = 0; k < parts; ++k)
    plastic = sub_increment(c, sigma, pt, part, state, tolerance) || plastic;

  // The cumulative fabric measures and the bound on the stress ratio, once per increment
  // as the reference implementation commits them.
  pt.z_cum += norm(pt.z - z_before) / sqrt2;
  pt.z_peak = std::max(norm(pt.z) / sqrt2, pt.z_peak);
  const double p = trace_mean(sigma);
  const double dr = density_now(c, pt);
  const double bounding = ratios(c, p, dr).bounding;
  const double now = ratio_of(sigma, pt.p_min);
  if (p > 0.0 && now > bounding) scale_ratio(c, sigma, pt.alpha, p, now, bounding);
  pack(pt, point);
  store(sigma, stress);
  return plastic;
}

void rotate(std::span<Vec4> point, double spin_increment) {
  for (int k = back_stress; k <= fabric_at_reversal; ++k) {
    rotate_jaumann(point[static_cast<std::size_t>(k)], spin_increment);
  }
}

}  // namespace slide::pm4sand
