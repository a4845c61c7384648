// Particle layouts: every rule is a positive, interior quadrature rule that integrates
// the polynomials of its stated degree exactly over the reference element.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "transfer/particle_layout.hpp"

namespace slide::transfer {
namespace {

double factorial(int n) {
  return n <= 1 ? 1.0 : n * factorial(n - 1);
}

/// Mean of ξ^a η^b over the reference triangle: 2 a! b! / (a + b + 2)!.
double triangle_mean(int a, int b) {
  return 2.0 * factorial(a) * factorial(b) / factorial(a + b + 2);
}

/// Mean of ξ^a over [−1, 1].
double interval_mean(int a) {
  return a % 2 == 1 ? 0.0 : 1.0 / (a + 1);
}

double rule_mean(const ParticleLayout& layout, int a, int b) {
  double sum = 0.0;
  for (const auto& p : layout.points)
    sum += p.weight * std::pow(p.xi.x(), a) * std::pow(p.xi.y(), b);
  return sum;
}

void expect_positive_inside_normalised(const ParticleLayout& layout) {
  double total = 0.0;
  for (const auto& p : layout.points) {
    EXPECT_GT(p.weight, 0.0) << layout.rule;
    total += p.weight;
    if (layout.shape == ElementShape::quad4) {
      EXPECT_LT(std::abs(p.xi.x()), 1.0) << layout.rule;
      EXPECT_LT(std::abs(p.xi.y()), 1.0) << layout.rule;
    } else {
      EXPECT_GT(p.xi.x(), 0.0) << layout.rule;
      EXPECT_GT(p.xi.y(), 0.0) << layout.rule;
      EXPECT_LT(p.xi.x() + p.xi.y(), 1.0) << layout.rule;
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-14) << layout.rule;
}

TEST(ParticleLayout, QuadGaussLegendreIntegratesItsTensorDegreeExactly) {
  for (int nx = 1; nx <= 12; ++nx) {
    for (int ny : {1, 2, 5, nx}) {
      const ParticleLayout layout = quad_layout(nx, ny);
      ASSERT_EQ(layout.count(), nx * ny);
      EXPECT_EQ(layout.label, std::to_string(nx) + "x" + std::to_string(ny));
      expect_positive_inside_normalised(layout);
      for (int a = 0; a <= 2 * nx - 1; ++a) {
        for (int b = 0; b <= 2 * ny - 1; ++b) {
          EXPECT_NEAR(rule_mean(layout, a, b), interval_mean(a) * interval_mean(b), 1e-14)
              << nx << "x" << ny << " ξ^" << a << " η^" << b;
        }
      }
    }
  }
}

TEST(ParticleLayout, TriangleRulesArePositiveInteriorSymmetricAndExactToTheirDegree) {
  const std::vector<std::pair<int, int>> count_degree{{1, 1}, {3, 2},  {4, 1},  {6, 4},  {7, 5},
                                                      {9, 1}, {12, 6}, {13, 6}, {16, 1}, {25, 1}};
  for (const auto& [count, degree] : count_degree) {
    const ParticleLayout layout = triangle_layout(count);
    ASSERT_EQ(layout.count(), count) << layout.rule;
    EXPECT_EQ(layout.degree, degree) << layout.rule;
    EXPECT_EQ(layout.label, std::to_string(count));
    expect_positive_inside_normalised(layout);
    for (int a = 0; a <= degree; ++a) {
      for (int b = 0; a + b <= degree; ++b) {
        EXPECT_NEAR(rule_mean(layout, a, b), triangle_mean(a, b), 2e-15)
            << layout.rule << ": ξ^" << a << " η^" << b;
      }
    }
    // Full symmetry: the barycentric permutations of every point are points of the rule
    // with the same weight.
    for (const auto& p : layout.points) {
      const std::array<double, 3> l{1.0 - p.xi.x() - p.xi.y(), p.xi.x(), p.xi.y()};
      for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 1}, {1, 2}, {2, 0}}) {
        std::array<double, 3> m = l;
        std::swap(m[static_cast<std::size_t>(i)], m[static_cast<std::size_t>(j)]);
        bool found = false;
        for (const auto& q : layout.points) {
          if ((q.xi - Vec2(m[1], m[2])).norm() < 1e-14 && std::abs(q.weight - p.weight) < 1e-15) {
            found = true;
          }
        }
        EXPECT_TRUE(found) << layout.rule;
      }
    }
  }
}

TEST(ParticleLayout, SubdivisionCentroidsGiveEqualSharesOfTheirSubTriangles) {
  const ParticleLayout layout = triangle_layout(16);
  for (const auto& p : layout.points) EXPECT_DOUBLE_EQ(p.weight, 1.0 / 16.0);
}

TEST(ParticleLayout, RejectsCountsWithoutAPositiveInteriorRule) {
  for (int count : {0, 2, 5, 8, 10, 11, 14, 15, 17}) {
    EXPECT_THROW(triangle_layout(count), Error) << count;
  }
  try {
    triangle_layout(5);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("supported: 1, 3, 6, 7, 12, 13"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(quad_layout(0, 4), Error);
  EXPECT_THROW(quad_layout(4, max_particle_order + 1), Error);
}

TEST(ParticleLayout, ParsesParticlesPerElement) {
  const auto four = parse_particles_per_element("4", "--particles-per-element");
  EXPECT_EQ(four.nx, 4);
  EXPECT_EQ(four.ny, 4);
  EXPECT_EQ(four.triangle, 4);
  const auto three_by_two = parse_particles_per_element("3x2", "--particles-per-element");
  EXPECT_EQ(three_by_two.nx, 3);
  EXPECT_EQ(three_by_two.ny, 2);
  EXPECT_EQ(three_by_two.triangle, 6);
  for (const char* bad : {"", "0", "x", "3x", "x3", "a", "3x2x1", "-1", "2.5"}) {
    EXPECT_THROW(parse_particles_per_element(bad, "--particles-per-element"), Error) << bad;
  }
  const ParticleLayout tri =
      make_layout(ElementShape::tri3, parse_particles_per_element("4x4", "-"));
  EXPECT_EQ(tri.count(), 16);
}

/// The text of cases/geostatic-4x4/case.toml, which the layout tests below edit.
std::string geostatic_case_text() {
  std::ifstream in(std::filesystem::path(SLIDE_SOURCE_DIR) / "cases" / "geostatic-4x4" /
                   "case.toml");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// One rule for the particles of a triangle (common/geometry/triangle_rules.hpp): a case file's
// particles_per_triangle takes every count fem2mpm's --particles-per-element takes (9
// used to work on the command line and be refused in case.toml), and refuses the same.
TEST(ParticleLayout, CaseFileAcceptsTheTriangleCountsOfTheCommandLine) {
  const std::string base = geostatic_case_text();
  const std::string table = "[transfer]\n";
  const auto at = base.find(table);
  ASSERT_NE(at, std::string::npos);
  const auto accepted_by_case_file = [&](int count) {
    std::string edited = base;
    edited.insert(at + table.size(), fmt::format("particles_per_triangle = {}\n", count));
    try {
      return parse_case(edited, "case.toml").transfer.particles_triangle == count;
    } catch (const Error&) {
      return false;
    }
  };
  const auto accepted_by_command_line = [](int count) {
    try {
      const auto request =
          parse_particles_per_element(std::to_string(count), "--particles-per-element");
      return make_layout(ElementShape::tri3, request).count() == count;
    } catch (const Error&) {
      return false;
    }
  };
  EXPECT_TRUE(accepted_by_case_file(9));
  EXPECT_FALSE(accepted_by_case_file(5));
  EXPECT_FALSE(accepted_by_command_line(5));
  std::vector<int> counts;
  for (int count = 1; count <= 40; ++count) counts.push_back(count);
  for (int count : {1023, 1024, 1025, 1089}) counts.push_back(count);
  for (int count : counts) {
    EXPECT_EQ(accepted_by_case_file(count), accepted_by_command_line(count)) << count;
  }
}

// The same for quads: particles_per_element takes the n of fem2mpm's NxM (1 to 32 per
// direction; the case file used to stop at 10).
TEST(ParticleLayout, CaseFileAcceptsTheQuadLayoutsOfTheCommandLine) {
  const std::string base = geostatic_case_text();
  const std::string line = "particles_per_element = [4, 4]\n";
  const auto at = base.find(line);
  ASSERT_NE(at, std::string::npos);
  const auto accepted_by_case_file = [&](int n) {
    std::string edited = base;
    edited.replace(at, line.size(), fmt::format("particles_per_element = [{}, 2]\n", n));
    try {
      return parse_case(edited, "case.toml").transfer.particles_x == n;
    } catch (const Error&) {
      return false;
    }
  };
  const auto accepted_by_command_line = [](int n) {
    try {
      const auto request =
          parse_particles_per_element(fmt::format("{}x2", n), "--particles-per-element");
      return make_layout(ElementShape::quad4, request).count() == 2 * n;
    } catch (const Error&) {
      return false;
    }
  };
  EXPECT_TRUE(accepted_by_case_file(12));
  EXPECT_FALSE(accepted_by_case_file(33));
  for (int n = 0; n <= 34; ++n) {
    EXPECT_EQ(accepted_by_case_file(n), accepted_by_command_line(n)) << n;
  }
}

}  // namespace
}  // namespace slide::transfer
