// Material points for pure MPM (no FE phase, docs/method.md §5): the body's geometry filled
// with the same per-cell layout the transfer uses, and the initial stresses.
//
// Layout: in every grid cell, the N_px × N_py Gauss–Legendre points of the cell
// (common/geometry/element.hpp tensor_gauss_legendre); a point is kept when it lies inside the
// body. Each point carries the share of the cell its Gauss weight stands for:
//   V_p = h² w_i w_j / 4,  M_p = ρ V_p,  GIMP size (h/N_px, h/N_py),  element = −1.
// A cell entirely inside the body thus holds exactly its volume h².
//
// K0 stresses of level ground: σyy = −ρ g (y_s(x) − y), σxx = σzz = K0 σyy, σxy = 0,
// with K0 = ν/(1 − ν) and y_s(x) the height of the body's top surface above the point.
#pragma once

#include <span>
#include <vector>

#include "common/base/ranks.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/material.hpp"
#include "common/physics/particles.hpp"
#include "mpm/grid.hpp"

namespace slide::mpm {

/// Particles filling the axis-aligned box [lower, upper] (its edges on grid lines) with
/// the per-cell Gauss–Legendre layout; material `material_id` of `materials`.
Particles generate_box_particles(const GridGeometry& grid, const Vec2& lower, const Vec2& upper,
                                 int per_cell_x, int per_cell_y, const MaterialTable& materials,
                                 std::int32_t material_id);

/// Particles filling the elements of `mesh` (reference coordinates), in cell order, ids
/// their rows; a particle takes the material of the element it falls in. Throws Error
/// when none is inside the grid. Only the rows of `part` (Part::rows) of the body's n are
/// made (each MPI rank its own, as keep_part would keep of the whole), with the ids of the
/// whole; `whole_count`, when given, receives n.
Particles generate_mesh_particles(const GridGeometry& grid, const Mesh& mesh, int per_cell_x,
                                  int per_cell_y, const MaterialTable& materials,
                                  const Part& part = {}, std::size_t* whole_count = nullptr);

/// y_s(x_p): the highest point of the mesh boundary on the vertical line through each
/// particle (exact for any mesh made of straight-sided elements).
std::vector<double> mesh_surface_heights(const Mesh& mesh, std::span<const Vec2> points);

/// K0 stresses of level ground (see the header comment) from the surface heights.
void apply_k0_stresses(Particles& particles, const MaterialTable& materials,
                       std::span<const double> surface_height, double gravity = 9.81);

}  // namespace slide::mpm
