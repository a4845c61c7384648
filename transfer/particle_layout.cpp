#include "transfer/particle_layout.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "common/base/error.hpp"

namespace slide::transfer {

namespace {

int parse_positive(std::string_view text, std::string_view what, std::string_view where) {
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 1) {
    throw Error("{}: \"{}\" is not a particle count (expected {} as a whole number ≥ 1)", where,
                text, what);
  }
  return value;
}

// Triangle rules are written in barycentric coordinates (λ1, λ2, λ3); the reference
// coordinates of tri3 are (ξ, η) = (λ2, λ3) since N = (1 − ξ − η, ξ, η).
class TriangleRuleBuilder {
 public:
  void centroid(double weight) { add(1.0 / 3.0, 1.0 / 3.0, weight); }
  /// The three points of the orbit (a, a, 1 − 2a), each with `weight`.
  void orbit3(double a, double weight) {
    const double b = 1.0 - 2.0 * a;
    add(a, a, weight);
    add(b, a, weight);
    add(a, b, weight);
  }
  /// The six points of the orbit (a, b, 1 − a − b), each with `weight`.
  void orbit6(double a, double b, double weight) {
    const double c = 1.0 - a - b;
    add(a, b, weight);
    add(b, a, weight);
    add(b, c, weight);
    add(c, b, weight);
    add(c, a, weight);
    add(a, c, weight);
  }
  void add(double lambda2, double lambda3, double weight) {
    points_.push_back({Vec2(lambda2, lambda3), weight});
  }
  std::vector<QuadraturePoint> take() { return std::move(points_); }

 private:
  std::vector<QuadraturePoint> points_;
};

/// Centroids of the n² congruent triangles of the regular subdivision (each edge cut
/// into n): n(n+1)/2 upright and n(n−1)/2 inverted sub-triangles, each of area 1/(2n²)
/// of the reference triangle, hence equal shares 1/n². Exact for linear fields (the
/// centroid rule is exact for linear fields on every sub-triangle).
std::vector<QuadraturePoint> subdivision_centroids(int n) {
  std::vector<QuadraturePoint> points;
  const double h = 1.0 / n;
  const double weight = 1.0 / (static_cast<double>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i + j < n; ++i) {
      // Upright triangle (i, j), (i+1, j), (i, j+1) in units of h.
      points.push_back({Vec2((i + 1.0 / 3.0) * h, (j + 1.0 / 3.0) * h), weight});
      // Inverted triangle (i+1, j), (i+1, j+1), (i, j+1), when it exists.
      if (i + j < n - 1) points.push_back({Vec2((i + 2.0 / 3.0) * h, (j + 2.0 / 3.0) * h), weight});
    }
  }
  return points;
}

int perfect_square_root(int count) {
  const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(count))));
  return n * n == count ? n : 0;
}

}  // namespace

ParticlesPerElement parse_particles_per_element(std::string_view text, std::string_view where) {
  ParticlesPerElement request;
  const auto x = text.find_first_of("xX");
  if (x == std::string_view::npos) {
    const int n = parse_positive(text, "N or NxM", where);
    request.nx = request.ny = n;
    request.triangle = n;
    return request;
  }
  const std::string_view first = text.substr(0, x);
  const std::string_view second = text.substr(x + 1);
  request.nx = parse_positive(first, "N of NxM", where);
  request.ny = parse_positive(second, "M of NxM", where);
  request.triangle = request.nx * request.ny;
  return request;
}

ParticleLayout quad_layout(int nx, int ny) {
  if (nx < 1 || ny < 1 || nx > max_particle_order || ny > max_particle_order) {
    throw Error("{}x{} particles per element is not admissible (expected 1 to {} per direction)",
                nx, ny, max_particle_order);
  }
  ParticleLayout layout;
  layout.shape = ElementShape::quad4;
  layout.points = tensor_gauss_legendre(nx, ny);
  // Gauss–Legendre weights sum to 2 per direction: the share of point (i, j) is w_i w_j / 4.
  for (auto& point : layout.points) point.weight /= 4.0;
  // A tensor rule of orders (nx, ny) integrates ξ^a η^b exactly for a ≤ 2nx − 1 and
  // b ≤ 2ny − 1, hence every polynomial of total degree min(2nx, 2ny) − 1.
  layout.degree = 2 * std::min(nx, ny) - 1;
  layout.label = fmt::format("{}x{}", nx, ny);
  layout.rule = fmt::format("{}x{} Gauss–Legendre", nx, ny);
  return layout;
}

ParticleLayout triangle_layout(int count) {
  if (!has_triangle_rule(count)) {
    throw Error(
        "{} particles per triangle is not supported (no symmetric rule with positive "
        "weights and interior points; supported: {})",
        count, supported_triangle_counts());
  }
  ParticleLayout layout;
  layout.shape = ElementShape::tri3;
  layout.label = fmt::format("{}", count);
  TriangleRuleBuilder rule;
  switch (count) {
    case 1:
      rule.centroid(1.0);
      layout.degree = 1;
      layout.rule = "1-point centroid rule";
      break;
    case 3:
      rule.orbit3(1.0 / 6.0, 1.0 / 3.0);
      layout.degree = 2;
      layout.rule = "3-point Strang–Fix interior rule";
      break;
    case 6:
      // Dunavant (1985), degree 4; values refined to double precision.
      rule.orbit3(0.4459484909159648863, 0.2233815896780114657);
      rule.orbit3(0.09157621350977074346, 0.1099517436553218676);
      layout.degree = 4;
      layout.rule = "6-point Dunavant rule";
      break;
    case 7: {
      // Radon (1948), degree 5, in closed form.
      const double s = std::sqrt(15.0);
      rule.centroid(9.0 / 40.0);
      rule.orbit3((6.0 - s) / 21.0, (155.0 - s) / 1200.0);
      rule.orbit3((6.0 + s) / 21.0, (155.0 + s) / 1200.0);
      layout.degree = 5;
      layout.rule = "7-point Radon rule";
      break;
    }
    case 12:
      // Dunavant (1985), degree 6; values refined to double precision.
      rule.orbit3(0.06308901449150222834, 0.05084490637020681692);
      rule.orbit3(0.2492867451709104213, 0.1167862757263793660);
      rule.orbit6(0.05314504984481694735, 0.3103524510337844054, 0.08285107561837357519);
      layout.degree = 6;
      layout.rule = "12-point Dunavant rule";
      break;
    case 13:
      // The degree-7 13-point rule has a negative centroid weight. Dropping the degree-7
      // condition leaves a one-parameter family of degree-6 rules of the same 1+3+3+6
      // structure; this is its member with centroid weight 1/13 (moment equations of the
      // invariants e2^a e3^b, 2a + 3b ≤ 6, solved to 40 digits): all weights positive.
      rule.centroid(1.0 / 13.0);
      rule.orbit3(0.2393765464638772996, 0.08458707938615261781);
      rule.orbit3(0.06155571479286930973, 0.04903514912150116258);
      rule.orbit6(0.05616284266172052831, 0.3086091801161286834, 0.08703503959232695596);
      layout.degree = 6;
      layout.rule = "13-point positive degree-6 rule (centroid weight 1/13)";
      break;
    default: {
      const int n = perfect_square_root(count);  // a square: has_triangle_rule said so
      layout.points = subdivision_centroids(n);
      layout.degree = 1;
      layout.rule = fmt::format("{}-point centroids of the regular {}x{} subdivision", count, n, n);
      return layout;
    }
  }
  layout.points = rule.take();
  return layout;
}

ParticleLayout make_layout(ElementShape shape, const ParticlesPerElement& request) {
  return shape == ElementShape::quad4 ? quad_layout(request.nx, request.ny)
                                      : triangle_layout(request.triangle);
}

}  // namespace slide::transfer
