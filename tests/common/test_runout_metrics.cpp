// Runout measures and the stress quality at rest of docs/method.md §6 on hand-computed
// particle sets.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/physics/runout_metrics.hpp"

namespace slide {
namespace {

TEST(RunoutMetrics, PercentileInterpolatesLinearlyBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 99.0), 4.96);
  EXPECT_DOUBLE_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 50.0), 3.0);
  EXPECT_DOUBLE_EQ(percentile({7.0}, 99.0), 7.0);
  EXPECT_DOUBLE_EQ(percentile({1.0, 2.0}, 100.0), 2.0);
  EXPECT_TRUE(std::isnan(percentile({}, 99.0)));
}

// Bin 0 holds y = 1, 2, 3; bin 1 holds y = 0.5 at x = 3.5; bin 2 is empty; the particle
// in bin 3 is a stray.
const std::vector<Vec2> sample{{0.5, 1.0}, {1.0, 2.0}, {1.9, 3.0}, {3.5, 0.5}, {6.5, 10.0}};

TEST(RunoutMetrics, ProfileAndToeIgnoreParticlesBeyondAnEmptyBin) {
  const SurfaceProfile profile = surface_profile(sample, 2.0, 99.0);
  ASSERT_EQ(profile.height.size(), 2u);
  EXPECT_DOUBLE_EQ(profile.height[0], 2.98);  // rank 1.98 of {1, 2, 3}
  EXPECT_DOUBLE_EQ(profile.height[1], 0.5);
  EXPECT_DOUBLE_EQ(profile.x_toe, 3.5);
  EXPECT_EQ(profile.stray_count, 1u);
}

TEST(RunoutMetrics, RunoutIsMeasuredFromTheInitialLength) {
  const RunoutMeasures m = runout_measures(surface_profile(sample, 2.0, 99.0), 2.0);
  EXPECT_DOUBLE_EQ(m.x_toe, 3.5);
  EXPECT_DOUBLE_EQ(m.runout, 1.5);
  EXPECT_DOUBLE_EQ(m.runout_normalised, 0.75);
  EXPECT_DOUBLE_EQ(m.crest_height, 2.98);
}

// A body of 96 unit masses along x = 0.5 … 19.5 (bins of 1 m, every one filled) and a
// sheet of 4 light particles (0.25 each, area 0.1 m² each) at x = 20.5 … 23.5: 97 kg in all.
// 95 % of it, 92.15 kg, is behind the body's 93rd particle; the sheet beyond it holds the
// body's last 3 particles and the 4 light ones.
TEST(FrontMeasures, TheFrontOfAShareOfTheMassAndTheSheetBeyondIt) {
  std::vector<Vec2> points;
  std::vector<double> masses, volumes;
  for (int i = 0; i < 96; ++i) {
    points.emplace_back(0.5 + 0.2 * i, 1.0);
    masses.push_back(1.0);
    volumes.push_back(0.5);
  }
  for (int i = 0; i < 4; ++i) {
    points.emplace_back(20.5 + i, 0.05);
    masses.push_back(0.25);
    volumes.push_back(0.1);
  }
  const SurfaceProfile profile = surface_profile(points, 1.0, 99.0);
  ASSERT_DOUBLE_EQ(profile.x_toe, 23.5);
  const FrontMeasures f = front_measures(points, masses, volumes, profile, 0.0, 0.95);
  EXPECT_DOUBLE_EQ(f.x_front, 0.5 + 0.2 * 92);  // the 93rd particle
  EXPECT_DOUBLE_EQ(f.sheet_length, 23.5 - (0.5 + 0.2 * 92));
  EXPECT_DOUBLE_EQ(f.sheet_mass_share, (3.0 + 1.0) / 97.0);  // 3 body + 4 × 0.25
  EXPECT_DOUBLE_EQ(f.sheet_thickness, (3 * 0.5 + 4 * 0.1) / f.sheet_length);
  EXPECT_THROW((void)front_measures(points, masses, volumes, profile, 0.0, 1.0), Error);
  // Strays beyond an empty bin are not measured, as for the toe.
  points.emplace_back(40.0, 0.05);
  masses.push_back(50.0);
  volumes.push_back(1.0);
  const FrontMeasures g =
      front_measures(points, masses, volumes, surface_profile(points, 1.0, 99.0), 0.0, 0.95);
  EXPECT_DOUBLE_EQ(g.x_front, f.x_front);
}

TEST(RunoutMetrics, RmseNormalisesByReferenceHeightPlusParticleSize) {
  SurfaceProfile reference;
  reference.bin_width = 2.0;
  reference.height = {2.0, 1.0, 0.2};
  reference.x_toe = 3.5;  // toe in bin 1: bins 0 and 1 count, bin 2 does not
  SurfaceProfile run;
  run.bin_width = 2.0;
  run.height = {3.0};  // the run stops in bin 0: bin 1 counts as height 0
  run.x_toe = 1.5;
  const double e0 = (3.0 - 2.0) / (2.0 + 0.5), e1 = (0.0 - 1.0) / (1.0 + 0.5);
  EXPECT_DOUBLE_EQ(profile_rmse(run, reference, 0.5), std::sqrt((e0 * e0 + e1 * e1) / 2.0));
  EXPECT_DOUBLE_EQ(profile_rmse(reference, reference, 0.5), 0.0);
}

TEST(RunoutMetrics, FoundationLayerIsLeftOutOfTheProfileAndToe) {
  // A foundation layer (y ≤ 1) reaching x = 9 and debris on it up to x = 3.5.
  std::vector<Vec2> points{{0.5, 3.0}, {1.5, 2.0}, {3.5, 1.5}};
  for (double x = 0.25; x < 9.0; x += 0.5) points.emplace_back(x, 0.75);
  EXPECT_DOUBLE_EQ(surface_profile(points, 2.0).x_toe, 8.75);
  const SurfaceProfile above = surface_profile(points, 2.0, 99.0, 1.0);
  EXPECT_DOUBLE_EQ(above.x_toe, 3.5);
  ASSERT_EQ(above.height.size(), 2u);
  EXPECT_DOUBLE_EQ(above.height[1], 1.5);
}

TEST(RunoutMetrics, ACrestSunkBelowTheFoundationLevelKeepsItsHeightAndTheToe) {
  // Foundation top at y = 1 to x = 9; the crest (bins 0 and 1) has sunk to y = 0.8 and
  // 0.9, and debris above the level lies in bins 2 and 3 (toe 7.5), a stray at 11.5.
  std::vector<Vec2> points{{0.5, 0.8}, {2.5, 0.9}, {4.5, 2.0}, {5.0, 1.6}, {7.5, 1.2}, {11.5, 1.1}};
  for (double x = 0.25; x < 9.0; x += 0.5) points.emplace_back(x, 0.5);
  const SurfaceProfile p = surface_profile(points, 2.0, 50.0, 1.0);
  EXPECT_DOUBLE_EQ(p.x_toe, 7.5);
  EXPECT_EQ(p.stray_count, 1u);
  ASSERT_EQ(p.height.size(), 4u);
  // Bin 0 (x < 2): all its particles, y = 0.8 and 0.5 ×4: median 0.5. Bin 1: the
  // median of 0.9 and 0.5 ×4 is 0.5; with the 99th percentile it is 0.5 + 0.96·0.4.
  EXPECT_DOUBLE_EQ(p.height[0], 0.5);
  EXPECT_DOUBLE_EQ(p.height[2], 1.8);  // median of 2.0 and 1.6 (above the level only)
  EXPECT_DOUBLE_EQ(p.height[3], 1.2);
  EXPECT_NEAR(surface_profile(points, 2.0, 99.0, 1.0).height[1], 0.5 + 0.96 * 0.4, 1e-12);
  const RunoutMeasures m = runout_measures(p, 5.0);
  EXPECT_DOUBLE_EQ(m.runout, 2.5);
  EXPECT_DOUBLE_EQ(m.crest_height, 0.5);
  // Without a foundation level (docs/method.md §6) the run starts at the wall: every bin
  // has particles out to bin 5, and the toe is the stray.
  EXPECT_DOUBLE_EQ(surface_profile(points, 2.0).x_toe, 11.5);
}

// ---- Stress quality at rest

constexpr double g = gravity_acceleration;

/// A stepped block of particles at rest on a 0.25 m lattice: 2 m bins of 8 columns each,
/// bin b filled up to its top row at y = 9.875 − 1.5 b (40, 34, 28, ... rows), every
/// particle carrying the lithostatic σyy = −ρ g (h_b − y) under its bin's top row, ρ =
/// 1700 kg/m³ in bins 0–2 and 2100 kg/m³ in bins 3–4. The 99th-percentile profile height
/// is then exactly the top row's y: a bin of n particles has 8 in its top row, and the
/// rank 0.99 (n − 1) lies among the top 8 whenever 8 > 0.01 n + 0.99 (n ≤ 701; here
/// n ≤ 320). So the expected e follows in closed form, not from the profile estimate.
struct Block {
  std::vector<Vec2> x, v;
  std::vector<double> sigma_yy, density, top;  // top: h_b of each bin
};

Block stepped_block() {
  Block b;
  for (int bin = 0; bin < 5; ++bin) {
    const double h = 9.875 - 1.5 * bin;
    b.top.push_back(h);
    const double rho = bin < 3 ? 1700.0 : 2100.0;
    for (int column = 0; column < 8; ++column) {
      for (double y = 0.125; y <= h + 1e-9; y += 0.25) {
        b.x.emplace_back(2.0 * bin + 0.125 + 0.25 * column, y);
        b.v.emplace_back(0.0, 0.0);
        b.sigma_yy.push_back(-rho * g * (h - y));
        b.density.push_back(rho);
      }
    }
  }
  return b;
}

TEST(StressQuality, ALithostaticDepositHasNoError) {
  const Block b = stepped_block();
  const SurfaceProfile profile = surface_profile(b.x, 2.0, 99.0);
  ASSERT_EQ(profile.height.size(), 5u);
  for (std::size_t bin = 0; bin < 5; ++bin) EXPECT_DOUBLE_EQ(profile.height[bin], b.top[bin]);
  const StressQuality q = stress_quality_at_rest(b.x, b.v, b.sigma_yy, b.density, profile, 10.0);
  EXPECT_EQ(q.deposit_count, b.x.size());
  // Zero to round-off: the lithostatic stress is recomputed from the same h_b and y. The
  // neighbouring bin's h_b (1.5 m off) would give e = 0.15, the other material's density
  // up to 0.12 at the base.
  EXPECT_NEAR(q.p50, 0.0, 1e-14);
  EXPECT_NEAR(q.max, 0.0, 1e-14);
}

TEST(StressQuality, AUniformOffsetIsItsOwnErrorAtEveryPercentile) {
  Block b = stepped_block();
  // Δσ_p = −0.05 ρ_p g H0 (5 % of the column's weight, more compression): e = |Δσ|/(ρ g
  // H0) = 0.05 for every particle, whatever its material.
  const double h0 = 10.0;
  for (std::size_t i = 0; i < b.x.size(); ++i) b.sigma_yy[i] += -0.05 * b.density[i] * g * h0;
  const SurfaceProfile profile = surface_profile(b.x, 2.0, 99.0);
  const StressQuality q = stress_quality_at_rest(b.x, b.v, b.sigma_yy, b.density, profile, h0);
  EXPECT_EQ(q.deposit_count, b.x.size());
  for (double e : {q.p50, q.p90, q.p99, q.max}) EXPECT_NEAR(e, 0.05, 1e-12);
  // One material, a fixed offset in Pa: Δσ = 20 kPa, e = 20e3/(2100 g H0) in bins 3–4.
  Block one = stepped_block();
  for (std::size_t i = 0; i < one.x.size(); ++i) one.sigma_yy[i] += 20e3;
  const std::vector<double> e =
      stress_errors_at_rest(one.x, one.v, one.sigma_yy, one.density, profile, h0);
  ASSERT_EQ(e.size(), one.x.size());
  for (std::size_t i = 0; i < e.size(); ++i) {
    EXPECT_NEAR(e[i], 20e3 / (one.density[i] * g * h0), 1e-12);
  }
}

TEST(StressQuality, MovingParticlesAreNotPartOfTheDeposit) {
  Block b = stepped_block();
  // Every third particle moves at exactly 1 cm/s (or faster) with a wrong stress; the
  // others creep at just under 1 cm/s and are at rest.
  std::size_t moving = 0;
  for (std::size_t i = 0; i < b.x.size(); ++i) {
    if (i % 3 == 0) {
      b.v[i] = i % 2 == 0 ? Vec2(rest_speed, 0.0) : Vec2(0.0, -0.5);
      b.sigma_yy[i] = 1e6;
      ++moving;
    } else {
      b.v[i] = Vec2(0.0, 0.0099);
    }
  }
  const SurfaceProfile profile = surface_profile(b.x, 2.0, 99.0);
  const StressQuality q = stress_quality_at_rest(b.x, b.v, b.sigma_yy, b.density, profile, 10.0);
  EXPECT_EQ(q.deposit_count, b.x.size() - moving);
  EXPECT_NEAR(q.max, 0.0, 1e-14);
  // All moving: no deposit, nothing to report.
  for (auto& v : b.v) v = Vec2(0.3, 0.0);
  const StressQuality none = stress_quality_at_rest(b.x, b.v, b.sigma_yy, b.density, profile, 10.0);
  EXPECT_EQ(none.deposit_count, 0u);
  EXPECT_TRUE(std::isnan(none.p50) && std::isnan(none.p90) && std::isnan(none.p99) &&
              std::isnan(none.max));
}

TEST(StressQuality, OverAFoundationTheParticlesOfTheProfileAreMeasured) {
  // The sunk-crest set above, stress-free (σyy = 0), ρ 1700, H0 = 1 m, median profile
  // over a foundation at y = 1 m: heights 0.5, 0.5, 1.8, 1.2, first bin above the level
  // 2. e_p = |0 + ρ g (h_b − y)| / (ρ g H0) = |h_b − y|.
  //  - bins 0 and 1 (sunk crest): all their particles: 0.8 and 0.5 ×4 → 0.3, 0 ×4;
  //    0.9 and 0.5 ×4 → 0.4, 0 ×4;
  //  - bin 2: 2.0 and 1.6 → 0.2, 0.2 (its foundation particles at y = 0.5, e = 1.3,
  //    are the layer, not the deposit); bin 3: 1.2 → 0;
  //  - the stray (11.5, 1.1) and the foundation beyond the toe's bin have no h_b.
  // 13 errors, sorted 0 ×9, 0.2, 0.2, 0.3, 0.4: median (rank 6) 0, p90 (rank 10.8)
  // 0.2 + 0.8·0.1 = 0.28, p99 (rank 11.88) 0.3 + 0.88·0.1 = 0.388, max 0.4.
  std::vector<Vec2> points{{0.5, 0.8}, {2.5, 0.9}, {4.5, 2.0}, {5.0, 1.6}, {7.5, 1.2}, {11.5, 1.1}};
  for (double x = 0.25; x < 9.0; x += 0.5) points.emplace_back(x, 0.5);
  const SurfaceProfile p = surface_profile(points, 2.0, 50.0, 1.0);
  EXPECT_EQ(p.first_above_level, 2u);
  const std::vector<Vec2> at_rest(points.size(), Vec2(0.0, 0.0));
  const std::vector<double> zero(points.size(), 0.0), rho(points.size(), 1700.0);
  const StressQuality q = stress_quality_at_rest(points, at_rest, zero, rho, p, 1.0, 1.0);
  EXPECT_EQ(q.deposit_count, 13u);
  EXPECT_NEAR(q.p50, 0.0, 1e-12);
  EXPECT_NEAR(q.p90, 0.28, 1e-12);
  EXPECT_NEAR(q.p99, 0.388, 1e-12);
  EXPECT_NEAR(q.max, 0.4, 1e-12);
  EXPECT_FALSE(measured_by_profile({11.5, 1.1}, p, 1.0));  // stray
  EXPECT_FALSE(measured_by_profile({4.25, 0.5}, p, 1.0));  // foundation under debris
  EXPECT_TRUE(measured_by_profile({0.25, 0.5}, p, 1.0));   // sunk crest
  EXPECT_FALSE(measured_by_profile({-0.1, 0.5}, p, 1.0));  // behind the wall
}

TEST(StressQuality, FieldsOfDifferentLengthsAreAnError) {
  const std::vector<Vec2> x{{0.5, 1.0}, {1.0, 2.0}}, v{{0.0, 0.0}};
  const std::vector<double> s{0.0, 0.0}, rho{1700.0, 1700.0};
  EXPECT_THROW(stress_quality_at_rest(x, v, s, rho, surface_profile(x, 2.0), 1.0), Error);
}

}  // namespace
}  // namespace slide
