#include "fem/geostatic.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "common/base/error.hpp"
#include "fem/element_kernels.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

namespace {

/// The directions in which a node may move: u_I = T_I a_I with T_I one column per free
/// direction (0, 1 or 2 columns).
struct FreeDirections {
  int count = 2;
  std::array<Vec2, 2> direction{Vec2::UnitX(), Vec2::UnitY()};
};

FreeDirections free_directions(std::span<const NodalConstraint> constraints) {
  FreeDirections free;
  const Vec2* first_normal = nullptr;
  for (const auto& constraint : constraints) {
    switch (constraint.condition) {
      case BoundaryCondition::free:
        break;
      case BoundaryCondition::fixed:
        free.count = 0;
        return free;
      case BoundaryCondition::roller:
      case BoundaryCondition::friction: {
        const Vec2& n = constraint.normal;
        if (first_normal == nullptr) {
          first_normal = &n;
          free.count = 1;
          free.direction[0] = Vec2(-n.y(), n.x());
        } else if (std::abs(first_normal->x() * n.y() - first_normal->y() * n.x()) > 1e-9) {
          free.count = 0;  // two rollers that are not parallel: a corner
          return free;
        }
        break;
      }
    }
  }
  return free;
}

/// Euclidean norm by a plain loop (Eigen's vectorised reduction trips a false
/// -Wmaybe-uninitialized of GCC 12 with AVX-512).
double euclidean_norm(const Eigen::VectorXd& v) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i) sum += v[i] * v[i];
  return std::sqrt(sum);
}

double smallest_pivot_ratio(const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& solver) {
  if (solver.info() != Eigen::Success) return 0.0;
  const Eigen::VectorXd d = solver.vectorD();
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    smallest = std::min(smallest, std::abs(d[i]));
    largest = std::max(largest, std::abs(d[i]));
  }
  return largest > 0.0 ? smallest / largest : 0.0;
}

/// The reduced equations: each node's free directions T_I (the constraints) and the
/// index of its first unknown; equations = the number of unknowns.
struct ReducedSystem {
  std::vector<FreeDirections> free;
  std::vector<Index> first_equation;  ///< of each node (tied nodes share their leader's)
  Index equations = 0;
};

/// The unknowns: each node's free directions, numbered node by node; the second node of
/// a tied pair takes the first one's numbers (it moves with it).
ReducedSystem reduce(const FemModel& model, const NodalConstraints& constraints,
                     std::span<const std::pair<Index, Index>> tied) {
  const auto n_nodes = static_cast<std::size_t>(model.node_count());
  ReducedSystem r;
  r.free.resize(n_nodes);
  r.first_equation.assign(n_nodes, 0);
  std::vector<Index> leader(n_nodes, -1);
  for (const auto& [first, second] : tied) leader[static_cast<std::size_t>(second)] = first;
  for (std::size_t n = 0; n < n_nodes; ++n) {
    r.free[n] = free_directions(constraints.of(static_cast<Index>(n)));
    if (leader[n] >= 0) continue;
    r.first_equation[n] = r.equations;
    r.equations += r.free[n].count;
  }
  for (const auto& [first, second] : tied) {
    const auto a = static_cast<std::size_t>(first);
    const auto b = static_cast<std::size_t>(second);
    if (r.free[a].count != r.free[b].count ||
        (r.free[a].count == 1 && !r.free[a].direction[0].isApprox(r.free[b].direction[0]))) {
      throw Error(
          "geostatic stage: tied nodes {} and {} have different constraints (fem.geostatic.lateral "
          "= \"tied\" needs the same boundary on the left and right edges)",
          first, second);
    }
    r.first_equation[b] = r.first_equation[a];
  }
  return r;
}

/// The reduced stiffness Tᵀ K T.
Eigen::SparseMatrix<double> reduced_stiffness(const FemModel& model, const ReducedSystem& r) {
  const int npe = model.nodes_per_element;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(model.element_count() * 4 * npe * npe));
  for (Index e = 0; e < model.element_count(); ++e) {
    const ElementMatrix k = element_stiffness(model, model.reference, e);
    const auto nodes = model.mesh.element(e);
    for (int i = 0; i < npe; ++i) {
      const auto ni = static_cast<std::size_t>(nodes[static_cast<std::size_t>(i)]);
      for (int j = 0; j < npe; ++j) {
        const auto nj = static_cast<std::size_t>(nodes[static_cast<std::size_t>(j)]);
        const Mat2 block = k.block<2, 2>(2 * i, 2 * j);
        for (int a = 0; a < r.free[ni].count; ++a) {
          for (int b = 0; b < r.free[nj].count; ++b) {
            const double value = r.free[ni].direction[static_cast<std::size_t>(a)].dot(
                block * r.free[nj].direction[static_cast<std::size_t>(b)]);
            triplets.emplace_back(r.first_equation[ni] + a, r.first_equation[nj] + b, value);
          }
        }
      }
    }
  }
  Eigen::SparseMatrix<double> stiffness(r.equations, r.equations);
  stiffness.setFromTriplets(triplets.begin(), triplets.end());
  return stiffness;
}

/// The reduced load Tᵀ f: gravity, and with pore water the hydrostatic pressure's push
/// Q p_h on the skeleton, so that the solid carries the effective stress.
Eigen::VectorXd reduced_load(const FemModel& model, const ReducedSystem& r) {
  std::vector<Vec2> force = model.lumped.external_force;
  if (model.fluid.active()) {
    const auto npe = static_cast<std::size_t>(model.nodes_per_element);
    std::vector<Vec2> element_force(static_cast<std::size_t>(model.element_count()) * npe,
                                    Vec2::Zero());
    add_pore_pressure_forces(model, model.reference, model.fluid.element_hydrostatic,
                             element_force);
    for (std::size_t slot = 0; slot < element_force.size(); ++slot) {
      force[static_cast<std::size_t>(model.mesh.connectivity[slot])] += element_force[slot];
    }
  }
  Eigen::VectorXd load = Eigen::VectorXd::Zero(r.equations);
  for (std::size_t n = 0; n < r.free.size(); ++n) {
    for (int a = 0; a < r.free[n].count; ++a) {
      load[r.first_equation[n] + a] +=
          r.free[n].direction[static_cast<std::size_t>(a)].dot(force[n]);
    }
  }
  return load;
}

/// Stresses σ = D B u and hourglass forces Q = K_q q through the explicit stress kernel
/// (one elastic "step" of length 1 with velocity u from the unstressed state), on a
/// state at rest.
void set_elastic_state(const FemModel& model, const std::vector<Vec2>& displacement,
                       FemState& state) {
  std::vector<ConstitutiveModel> elastic;
  for (const auto& material : model.materials)
    elastic.push_back(ConstitutiveModel::elastic(material));
  state = make_rest_state(model);
  state.velocity = displacement;
  update_stresses(model, model.reference, elastic, 1.0, false, state);
  const FemState stressed = std::move(state);
  state = make_rest_state(model);
  state.stress = stressed.stress;
  state.hourglass_force = stressed.hourglass_force;
}

}  // namespace

GeostaticReport solve_geostatic(const FemModel& model, const NodalConstraints& constraints,
                                FemState& state, std::span<const std::pair<Index, Index>> tied) {
  const ReducedSystem r = reduce(model, constraints, tied);
  if (r.equations == 0) throw Error("geostatic stage: every node is fixed, nothing to solve");
  const Eigen::SparseMatrix<double> stiffness = reduced_stiffness(model, r);
  const Eigen::VectorXd load = reduced_load(model, r);

  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(stiffness);
  Eigen::VectorXd solution;
  if (solver.info() == Eigen::Success) solution = solver.solve(load);
  const double load_norm = euclidean_norm(load);
  const double residual =
      solution.size() == r.equations && solution.allFinite()
          ? euclidean_norm(stiffness * solution - load) / std::max(load_norm, 1e-300)
          : std::numeric_limits<double>::infinity();
  // A free rigid-body motion leaves a pivot at round-off level (≈ 1e-16 of the largest)
  // even when gravity does not load it; the pivots of a supported body stay within a
  // few orders of magnitude of each other.
  if (!(residual < 1e-6) || !(smallest_pivot_ratio(solver) > 1e-10)) {
    throw Error(
        "geostatic stage: the stiffness matrix is singular (the geostatic boundaries leave a "
        "rigid-body motion free, or an element has no stiffness)");
  }

  // Nodal displacements u_I = T_I a_I.
  std::vector<Vec2> displacement(r.free.size(), Vec2::Zero());
  GeostaticReport report{r.equations, 0.0, residual};
  for (std::size_t n = 0; n < r.free.size(); ++n) {
    for (int a = 0; a < r.free[n].count; ++a) {
      displacement[n] +=
          solution[r.first_equation[n] + a] * r.free[n].direction[static_cast<std::size_t>(a)];
    }
    report.max_displacement = std::max(report.max_displacement, displacement[n].norm());
  }
  set_elastic_state(model, displacement, state);
  if (model.fluid.active()) {
    // The state before shaking: r_u = (p − p_static)/σ′v0 from here on.
    state.pore_pressure = model.fluid.hydrostatic;
    state.static_pore_pressure = model.fluid.hydrostatic;
    state.element_pore_pressure = model.fluid.element_hydrostatic;
    for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
      state.initial_vertical_effective_stress[gp] = -state.stress[gp][1];
      state.initial_mean_effective_stress[gp] = mean_stress(state.stress[gp]);
    }
    std::ranges::fill(state.max_pore_pressure_ratio, 0.0);
  }
  return report;
}

std::vector<std::pair<Index, Index>> pair_by_elevation(
    std::span<const std::pair<double, Index>> left, std::span<const std::pair<double, Index>> right,
    double tolerance) {
  std::vector<std::pair<Index, Index>> pairs;
  std::size_t j = 0;
  for (const auto& [y, node] : left) {
    while (j < right.size() && right[j].first < y - tolerance) ++j;
    if (j < right.size() && std::abs(right[j].first - y) <= tolerance) {
      pairs.emplace_back(node, right[j].second);
      ++j;
    }
  }
  return pairs;
}

std::vector<std::pair<Index, Index>> pair_sides(const FemModel& model, std::string_view what) {
  auto by_elevation = [&](const char* name) {
    const NodeSet* set = model.mesh.find_node_set(name);
    if (set == nullptr) throw Error("{}: the mesh has no node set \"{}\"", what, name);
    std::vector<std::pair<double, Index>> nodes;
    for (const Index n : set->nodes)
      nodes.emplace_back(model.mesh.nodes[static_cast<std::size_t>(n)].y(), n);
    std::ranges::sort(nodes);
    return nodes;
  };
  const auto left = by_elevation("left");
  const auto right = by_elevation("right");
  const auto pairs = pair_by_elevation(left, right, 1e-6 * std::max(model.extent.height, 1.0));
  if (pairs.size() != left.size() || pairs.size() != right.size()) {
    throw Error(
        "{}: the left and right edges' nodes are not at the same elevations ({} and {} "
        "nodes, {} paired)",
        what, left.size(), right.size(), pairs.size());
  }
  return pairs;
}

}  // namespace slide::fem
