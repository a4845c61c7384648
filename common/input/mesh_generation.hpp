// Building the FE mesh a case describes, and checking it. In common/ because the FE
// phase meshes the body with it and pure MPM fills the same body with particles.
//
//  - "profile": a mapped mesh of the polygon between the base y = 0 and a surface
//    polyline: vertical lines of nodes at x positions that hit every surface point,
//    the same number of element rows in every column (round(max height / h)), each
//    column's nodes spread evenly between the base and the surface.
//  - "blocks": transfinite (bilinear) mapped blocks with explicit corners and cell
//    counts; coincident nodes of neighbouring blocks are merged.
//  - "gmsh": a Gmsh .msh file (gmsh_reader.hpp).
// tri3 meshes of the generated kinds split every quad into two triangles, alternating
// the diagonal so that the mesh has no preferred direction.
//
// Generated meshes carry the node sets "left" (x = x_min), "right" (x = x_max) and
// "base" (y = y_min) with outward normals (−1,0), (1,0), (0,−1).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "common/geometry/mesh.hpp"
#include "common/input/case_file.hpp"

namespace slide {

/// The largest mesh the generators build: 10⁷ elements, about 3 GB of FE state and, at
/// the element sizes that resolve a slope (0.1–1 m), a slope 1,000–30,000 times its own
/// height across. A larger request is a unit or typing error (element_size = 1e-300
/// asks for 10³⁰⁰ elements); refusing it names the key instead of failing to allocate.
inline constexpr double max_generated_elements = 1.0e7;

/// The mesh of `c.mesh` with material ids from `c.materials`; validated.
Mesh build_mesh(const Case& c);

Mesh generate_profile_mesh(const MeshSpec& spec, std::int32_t material_id);
Mesh generate_block_mesh(const MeshSpec& spec, const MaterialTable& materials);

/// The first fault of a block's corners, if any: not finite, not counter-clockwise (or
/// degenerate), or not convex (the bilinear map of a non-convex quadrilateral folds over
/// itself). generate_block_mesh and the case reader both refuse a block by it; the text
/// names no block, the caller says which.
std::optional<std::string> block_corners_problem(const MeshBlock& block);

/// Where blocks `a` and `b`, sharing (part of) an edge, put their nodes at different
/// places along it (the mesh would have hanging nodes), if they do. The case reader asks
/// before any mesh is built, to name the block's line in the case file.
std::optional<std::string> shared_edge_mismatch(const MeshBlock& a, const MeshBlock& b);

}  // namespace slide
