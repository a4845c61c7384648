// Stage 1 of the FE phase: geostatic equilibrium (docs/method.md §3).
//
// Linear elastic materials (each material's E and ν), gravity, and the geostatic
// boundary conditions: one sparse linear solve K u = f, with K the elastic stiffness
// (the same element kernels and hourglass stiffness the explicit stage uses) and f the
// consistent gravity load Σ_e ∫ N_I ρ g dA (equal to m_I g with the row-sum lumped
// mass). Constraints are eliminated node by node: a roller (or a friction boundary,
// which acts as a roller in this static stage) keeps only the tangential direction of
// its node, a fixed node or a corner between two non-parallel rollers keeps none. The
// stresses σ = D ε(u) at the Gauss points and the hourglass forces are kept; the
// displacements, velocities, accelerations and strains are reset to zero: t = 0 of
// the failure stage starts from this stressed but undeformed state.
#pragma once

#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "fem/fem_model.hpp"

namespace slide::fem {

struct GeostaticReport {
  Index equations = 0;           ///< unknowns after eliminating the constraints
  double max_displacement = 0;   ///< largest |u| of the solution (then reset), m
  double relative_residual = 0;  ///< |K u − f| / |f|
};

/// Solves the geostatic stage and writes the stressed, undeformed state into `state`
/// (which must have the model's sizes). `tied` pairs nodes that share their displacement
/// (periodic sides: the free field of an infinite layer or slope, which then carries a
/// turned gravity's downslope weight by base shear); the two nodes of a pair must have
/// the same constraints. Throws Error when the boundary conditions leave a rigid-body
/// motion free (singular stiffness).
GeostaticReport solve_geostatic(const FemModel& model, const NodalConstraints& constraints,
                                FemState& state,
                                std::span<const std::pair<Index, Index>> tied = {});

/// Nodes of two edges, each as (elevation, node) sorted by elevation, paired where their
/// elevations agree within `tolerance`, bottom to top (the tied sides of both stages).
std::vector<std::pair<Index, Index>> pair_by_elevation(
    std::span<const std::pair<double, Index>> left, std::span<const std::pair<double, Index>> right,
    double tolerance);

/// The left and right edges' nodes at equal elevations (within 1e-6 of the model's
/// height), bottom to top, as (left, right) pairs. Throws Error when there is none.
std::vector<std::pair<Index, Index>> pair_sides(const FemModel& model, std::string_view what);

}  // namespace slide::fem
