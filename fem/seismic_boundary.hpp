// The boundaries of a shaken failure stage (docs/method.md §8), node by node, in the
// form the explicit step consumes (fem/explicit_dynamics.hpp).
//
// Rigid base: the constraints of fem.failure.boundaries act on the velocity relative to
// the base, v − v_g (a fixed node follows the base, a roller moves with it along its
// normal, a frictional node slides on the moving base with Coulomb friction on v − v_g).
// The whole box moves with the base: a roller side too.
//
// Compliant base (Lysmer–Kuhlemeyer): each base node carries a dashpot c = ρ_r V_s,r L
// horizontally (L its share of the base's length) and the incident wave as the force
// 2 ρ_r V_s,r L v_in(t) (for an outcrop motion v_in = v_g/2); vertically the roller
// stays, or with a vertical motion the same with V_p,r and the node's static reaction
// (which the roller carried before) as a constant force.
//
// Lateral "tied": nodes of the left and right edges at the same elevation share their
// motion, both components: the periodic free field of level ground (OpenSees's
// `equalDOF 1 2` of site response). "tied-horizontal" shares the horizontal component
// only (docs/method.md §8 as written); a model one element wide then keeps its bending
// modes (a 20 m column of V_s = 200 m/s rang at 0.53 Hz, not at V_s/4H = 2.5 Hz), so
// it suits wide models only. "viscous": dashpots ρ V_p L
// normal and ρ V_s L tangential of the soil at the node. Both keep the static
// horizontal reaction of the roller they replace as a constant force, so that the
// stage starts in the equilibrium the geostatic stage left and only the motion of the
// shaking is free. A node of the taller edge with no partner at its elevation is viscous.
//
// Dashpots are integrated with the mean of the old and new velocity (c (v⁻ + v⁺)/2),
// which is unconditionally stable for any c dt/m.
#pragma once

#include <utility>
#include <vector>

#include "common/physics/ground_motion.hpp"
#include "common/settings/fem_spec.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

struct SeismicBoundary {
  SeismicBase base = SeismicBase::rigid;
  const GroundMotion* motion = nullptr;  ///< owned by the run
  /// Per node: dashpot coefficients (x, y), N·s/m per m of thickness; zero elsewhere.
  std::vector<Vec2> dashpot;
  /// Per node: the incident force per unit of the motion's velocity (x, y), N·s/m.
  std::vector<Vec2> incident;
  /// Per node: the static reaction of a released support, N per m.
  std::vector<Vec2> static_force;
  /// Left–right pairs sharing their horizontal velocity, and their vertical one when
  /// `tie_vertical`.
  std::vector<std::pair<Index, Index>> tied;
  /// The elements of the tied sides paired likewise (the elements along two consecutive
  /// pairs of nodes): they share their pore pressure (fem/pore_fluid.hpp).
  std::vector<std::pair<Index, Index>> tied_elements;
  bool tie_vertical = false;
  /// Whether the dashpots act on the velocity relative to the base (a rigid base: the
  /// far field moves with it) or on the absolute one (a compliant base).
  bool dashpots_in_base_frame = false;
  Index viscous_side_nodes = 0;  ///< side nodes with Lysmer dashpots

  /// The base velocity constraints act relative to over the step t → t + dt (zero for
  /// a compliant base).
  Vec2 frame_velocity(double t, double dt) const {
    return base == SeismicBase::rigid ? motion->step_velocity(t, dt) : Vec2::Zero();
  }
  /// The base displacement constraints are measured from (zero for a compliant base).
  Vec2 frame_displacement(double t) const {
    return base == SeismicBase::rigid ? motion->displacement(t) : Vec2::Zero();
  }
};

/// The reaction each node's supports carry in `state` (the geostatic equilibrium):
/// R = −(m g + f_ext − f_int), zero at free nodes up to the solve's residual.
std::vector<Vec2> support_reactions(const FemModel& model, const FemState& state);

/// What the case's motion does to each node. `reactions` from support_reactions of the
/// geostatic state. Throws Error when a tied side has no pair at all or a named edge
/// is missing.
SeismicBoundary make_seismic_boundary(const FemModel& model, const MotionSpec& spec,
                                      const GroundMotion& motion,
                                      const std::vector<Vec2>& reactions);

/// One line for the log: what the boundary does (e.g. "compliant base: 51 nodes,
/// ρ_r V_s,r = 1.8e6 Pa·s/m; tied sides: 20 pairs, 5 viscous nodes").
std::string describe(const SeismicBoundary& boundary, const MotionSpec& spec);

}  // namespace slide::fem
