// Import of Gmsh meshes (.msh, ASCII format 4.1 or 2.2) for real cross-sections.
//
// Physical groups give meaning to the mesh: 2-D physical groups (surfaces) name the
// materials (each name must be a material of the case) and 1-D physical groups (lines)
// name the boundaries (node sets, referenced by name in the case's boundary tables).
// Only 4-node quadrangles and 3-node triangles are accepted; a mesh of quads read for
// a tri3 analysis is split into triangles, a triangle mesh cannot serve quad4 types.
//
// A bad mesh is an error naming the file, the line and the Gmsh tag at fault:
//  - an element that is re-entrant or has zero area (det J ≤ 0 at a corner), or whose
//    orientation differs from the rest of its elementary surface entity (a folded or
//    overlapping mesh). Gmsh orients all the elements of one surface alike, clockwise
//    when the surface's curve loop is clockwise: such a wholly clockwise surface is
//    accepted and its elements are turned counter-clockwise;
//  - an element referring to a node that is not in $Nodes;
//  - a node that no surface element uses. Only a node that nothing but point elements
//    use is dropped silently: Gmsh may save the mesh vertex of a geometry point on its
//    own (with Mesh.SaveAll = 0 a 4.1 file holds only the nodes of saved elements);
//  - a line element that is not an edge of a surface element (dangling), whether in a
//    physical group or not;
//  - a 1-D or 2-D physical group of $PhysicalNames that holds no elements.
#pragma once

#include <filesystem>

#include "common/geometry/mesh.hpp"
#include "common/physics/material.hpp"

namespace slide {

/// Reads `path` into a mesh of `type`; throws Error (file, line, problem) on a malformed
/// file, an unsupported element, an unknown material name, an empty physical group or
/// any of the bad meshes above.
Mesh read_gmsh(const std::filesystem::path& path, ElementType type, const MaterialTable& materials);

}  // namespace slide
