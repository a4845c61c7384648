// The finite element model of the FE phase (docs/method.md §3): the mesh with everything the
// kernels precompute from it, and the state that the stages advance.
//
//  - FemModel: constant during a run (made by make_model, fem/model_setup.hpp). Reference geometry
//  per Gauss point (shape-function
//    gradients ∂N/∂x and integration weights w·det J), hourglass data of one-point quads,
//    the lumped (row-sum) nodal masses m_I = Σ_e ∫ N_I ρ dA, gravity loads m_I g and the
//    node → element adjacency used to gather nodal forces.
//  - FemState: what evolves and what a checkpoint stores (common/physics/fe_fields.hpp:
//    nodal u, v, a, p; Gauss-point stress, strain, material state; hourglass forces).
//  - NodalConstraints: the boundary conditions of one stage, node by node, in the form
//    the shared nodal update (common/physics/nodal_update.hpp) consumes.
//
// Everything is a structure of arrays indexed by node, element or Gauss point; Gauss
// points are stored element by element in the order of the element's quadrature rule.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/algorithms.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/fe_fields.hpp"
#include "common/physics/material.hpp"
#include "common/physics/nodal_update.hpp"

namespace slide::fem {

using Mat3 = Eigen::Matrix3d;  // the elasticity matrix (common/physics/constitutive.hpp)

/// What the kernels integrate with. Small strain evaluates it once on the reference
/// geometry; updated Lagrangian re-evaluates it on the current geometry every step.
struct ElementGeometry {
  std::vector<ShapeGradients> gradients;  ///< per Gauss point: row k = ∂N_k/∂x, 1/m
  std::vector<double> weight;             ///< per Gauss point: w·det J, m² (per m)
  /// One-point quads only, per element: the Flanagan–Belytschko hourglass vector γ and
  /// the physical hourglass stiffness K_q (already scaled by the hourglass coefficient).
  std::vector<Vec4> hourglass_vector;
  std::vector<Mat2> hourglass_stiffness;
};

/// The element rule's points on the reference element (the same for every element).
struct QuadratureRule {
  std::vector<Vec2> local;     ///< per Gauss point of one element: ξ of the rule
  std::vector<double> weight;  ///< per Gauss point of one element: w of the rule
};

/// Per material: the initial elastic constants.
struct ElasticConstants {
  std::vector<Mat3> matrix;        ///< plane strain D
  std::vector<double> wave_speed;  ///< c_p = sqrt(M/ρ), m/s
};

/// Per element, on the reference geometry.
struct ElementConstants {
  std::vector<double> centre_det_reference;  ///< det J at the centre on X
  std::vector<double> volume_reference;      ///< V_0^e, m² (per m)
  std::vector<double> density;               ///< ρ: the material's, or dry above the water
  std::vector<double> mass;                  ///< m_e = ρ V_0^e, kg (per m)
  /// The P-wave speed of the Courant step: the material's c_p, or undrained
  /// V_p,u = sqrt((M + K_f/n)/ρ_sat) in a saturated element (docs/method.md §10), m/s.
  std::vector<double> wave_speed;
  /// The P-wave speed of the skeleton alone, sqrt(M/ρ) (the stiffness β_K damps): the
  /// wave_speed of a dry element, less in a saturated one, m/s.
  std::vector<double> skeleton_wave_speed;
};

/// A face the pore water flows through (two-point flux, fem/pore_fluid.hpp): between the
/// saturated elements `from` and `to`, or from `from` to a drained face (`to` = −1) held
/// at `pressure`. The flow from → to is T (φ_from − φ_to), φ = p − ρ_w (g − a)·x.
struct FluidFace {
  Index from = 0;
  Index to = -1;
  double transmissibility = 0.0;      ///< T, m²/(Pa·s) (per m)
  Vec2 offset = Vec2::Zero();         ///< x_to − x_from (centres, or the face's midpoint), m
  double pressure = 0.0;              ///< a drained face's p, Pa
  std::array<Index, 2> side{-1, -1};  ///< a drained face's two nodes (−1 for inner faces)
};

/// The pore water of a model with saturated elements (docs/method.md §10, fem/pore_fluid.hpp):
/// one pore pressure p per saturated element (compression positive), stored with the
/// element's storage S_e, driven by the element's volume change and by Darcy flow across
/// its faces; the nodal p of the output is the node's hydrostatic p plus the
/// storage-weighted mean excess of the elements around it. Empty (active() false) for a
/// dry model.
/// The elevation of a piecewise-linear water table at x (constant beyond its ends).
inline double profile_level(const std::vector<Vec2>& profile, double x) {
  if (x <= profile.front().x()) return profile.front().y();
  for (std::size_t i = 1; i < profile.size(); ++i) {
    if (x <= profile[i].x()) {
      const double t = (x - profile[i - 1].x()) / (profile[i].x() - profile[i - 1].x());
      return profile[i - 1].y() + t * (profile[i].y() - profile[i - 1].y());
    }
  }
  return profile.back().y();
}

struct PoreFluid {
  double density = 1000.0;          ///< ρ_w, kg/m³
  double bulk_modulus = 2.2e9;      ///< K_f, Pa
  double tension_limit = -100e3;    ///< lowest p, Pa
  Vec2 level_point = Vec2::Zero();  ///< a point of the water table, (0, level)
  /// A water table varying along x (WaterSpec::profile; gravity along −y), else empty.
  std::vector<Vec2> profile;
  Vec2 gravity = Vec2::Zero();  ///< g, m/s²
  /// A reservoir's free surface: a point of it, (0, level); none without a reservoir.
  std::optional<Vec2> reservoir_point;
  /// The x range (min, max) the reservoir covers, m.
  Vec2 reservoir_extent{-std::numeric_limits<double>::infinity(),
                        std::numeric_limits<double>::infinity()};

  // Per element.
  std::vector<std::uint8_t> saturated;      ///< 1: u–p (porous material, centre below the level)
  std::vector<double> storage;              ///< S_e = (n_e/K_f) A_e, m²/Pa (per m; 0 when dry)
  std::vector<double> element_hydrostatic;  ///< p_h at the centre (its nodes' mean), Pa
  std::vector<FluidFace> faces;             ///< the faces water crosses
  // Per node (the output's nodal p).
  std::vector<double> node_storage;      ///< Σ S_e of the saturated elements around the node
  std::vector<std::uint8_t> prescribed;  ///< 1: p held at its hydrostatic value
  std::vector<double> hydrostatic;       ///< p_h(X_I), Pa (0 off the saturated elements)

  bool active() const { return !storage.empty(); }
  /// How deep x lies below the water table along gravity (−y without gravity), m;
  /// negative above it.
  double depth(const Vec2& x) const {
    if (!profile.empty()) return profile_level(profile, x.x()) - x.y();
    const double g = gravity.norm();
    const Vec2 down = g > 0.0 ? Vec2(gravity / g) : Vec2(0.0, -1.0);
    return down.dot(x - level_point);
  }
  /// The hydrostatic pressure of the water table at x, ρ_w |g| depth(x): negative
  /// (suction) above the table.
  double hydrostatic_at(const Vec2& x) const { return density * gravity.norm() * depth(x); }
};

/// Per node, lumped (row sums).
struct LumpedNodes {
  std::vector<double> mass;  ///< m_I = Σ_e ∫ N_I ρ dA, kg (per m)
  /// The constant external forces: m_I g, plus a reservoir's water load on the wetted
  /// boundary (fem/pore_fluid.hpp), N (per m).
  std::vector<Vec2> external_force;
};

/// Node → element slots (e·nodes_per_element + k), CSR: the forces of node n are the
/// slots slots[offsets[n] .. offsets[n+1]).
struct NodeAdjacency {
  std::vector<Index> offsets;
  std::vector<Index> slots;
};

/// The reference elevations of the model.
struct VerticalExtent {
  double y_min = 0.0;   ///< lowest reference elevation, m
  double height = 0.0;  ///< H: reference height of the model, m
};

struct FemModel {
  Mesh mesh;
  MaterialTable materials;
  Kinematics kinematics = Kinematics::small_strain;
  double hourglass_coefficient = 1.0;

  int nodes_per_element = 4;
  bool hourglass = false;  ///< quad4-1gp: physical hourglass stabilisation is on

  Vec2 gravity = gravity_vector();  ///< g, m/s²
  ElementGeometry reference;        ///< on the reference coordinates X
  QuadratureRule rule;
  ElasticConstants elastic;
  ElementConstants elements;
  LumpedNodes lumped;
  PoreFluid fluid;
  NodeAdjacency adjacency;
  VerticalExtent extent;

  Index node_count() const { return mesh.node_count(); }
  Index element_count() const { return mesh.element_count(); }
  /// Gauss points per element: the rule's.
  int gauss_per_element() const { return static_cast<int>(rule.local.size()); }
  Index gauss_count() const { return element_count() * gauss_per_element(); }
  const Material& material_of(Index element) const {
    return materials[static_cast<std::size_t>(mesh.material_id[static_cast<std::size_t>(element)])];
  }
};

/// The evolving state (common/physics/fe_fields.hpp: what checkpoints carry) with its
/// clock and the yield flags of the last update.
struct FemState : FeFields {
  double time = 0.0;                  ///< s, t = 0 at the start of the failure stage
  Index step = 0;                     ///< time steps since t = 0
  std::vector<std::uint8_t> yielded;  ///< 1 where the point yielded in the last update
};

/// Zero displacement, velocity, stress and state for every node and Gauss point.
FemState make_rest_state(const FemModel& model);

/// Current coordinates x = X + u.
std::vector<Vec2> current_coordinates(const FemModel& model, const FemState& state);
/// Same into an existing vector (no allocation once it has the right size).
void update_coordinates(const FemModel& model, const FemState& state, std::vector<Vec2>& x);

/// The boundary conditions of one stage, node by node (a corner node gets the
/// constraints of both of its sides).
struct NodalConstraints {
  std::vector<Index> offsets;  ///< CSR offsets, n_nodes + 1
  std::vector<NodalConstraint> constraints;

  std::span<const NodalConstraint> of(Index node) const {
    const auto begin = static_cast<std::size_t>(offsets[static_cast<std::size_t>(node)]);
    const auto end = static_cast<std::size_t>(offsets[static_cast<std::size_t>(node) + 1]);
    return {constraints.data() + begin, end - begin};
  }
};

/// Applies `table` (node-set name → condition) to the mesh; `where` names the table in
/// errors (e.g. "case.toml: fem.failure.boundaries"). A name that is not a node set of
/// the mesh is an Error; node sets the table does not name are free.
NodalConstraints make_constraints(const Mesh& mesh, const BoundaryTable& table,
                                  std::string_view where);

/// The condition each node set of the mesh gets from `table`, in mesh order (free when
/// the table does not name it): what a checkpoint's /boundary group records.
std::vector<BoundaryCondition> node_set_conditions(const Mesh& mesh, const BoundaryTable& table);

}  // namespace slide::fem
