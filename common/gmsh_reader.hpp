// Import of Gmsh meshes (.msh, ASCII format 4.1 or 2.2) for real cross-sections.
//
// Physical groups give meaning to the mesh: 2-D physical groups (surfaces) name the
// materials (each name must be a material of the case) and 1-D physical groups (lines)
// name the boundaries (node sets, referenced by name in the case's boundary tables).
// Only 4-node quadrangles and 3-node triangles are accepted; a mesh of quads read for
// a tri3 analysis is split into triangles, a triangle mesh cannot serve quad4 types.
#pragma once

#include <filesystem>

#include "common/material.hpp"
#include "common/mesh.hpp"

namespace slide {

/// Reads `path` into a mesh of `type`; throws Error (file, line, problem) on a malformed
/// file, an unsupported element, an unknown material name or a missing physical group.
Mesh read_gmsh(const std::filesystem::path& path, ElementType type, const MaterialTable& materials);

}  // namespace slide
