// A case's geometry as it gives it ([mesh] of case.toml, common/input/case-file.md): a
// generated mesh (a surface profile, mapped blocks), a Gmsh file or an OpenSees model,
// and the recorder files opensees2fem reads ([opensees]).
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"

namespace slide {

// ----------------------------------------------------------------------------- mesh

enum class MeshGenerator {
  profile,   ///< columns under a surface polyline over the base y = 0 (mapped mesh)
  blocks,    ///< multi-block transfinite (mapped) quads with explicit corner points
  gmsh,      ///< a Gmsh .msh file (4.1 or 2.2 ASCII)
  opensees,  ///< an OpenSees model printed with `print -JSON` (opensees_reader.hpp)
};

/// One mapped block: four corners counter-clockwise, cells along the first side (0→1)
/// and along the second side (1→2). Blocks that share an edge share its nodes.
struct MeshBlock {
  std::array<Vec2, 4> corners;
  int cells_u = 1;
  int cells_v = 1;
  std::string material;
};

struct MeshSpec {
  MeshGenerator generator = MeshGenerator::profile;
  ElementType element_type = ElementType::quad4_1gp;
  // profile
  double element_size = 1.0;  ///< target element size h, m
  std::vector<Vec2> surface;  ///< surface points, x increasing from the wall x = 0
  std::string material;       ///< material of the whole profile mesh
  // blocks
  std::vector<MeshBlock> blocks;
  // gmsh (relative paths are relative to the case file's folder)
  std::filesystem::path gmsh_file;
  // opensees: the JSON model, its nDMaterial tags → case materials, element classes to skip
  std::filesystem::path opensees_file;
  std::map<std::string, std::string> opensees_materials;
  std::vector<std::string> ignore_elements;

  /// The mesh file the case reads (Gmsh or OpenSees), empty for generated meshes.
  std::filesystem::path file() const {
    return generator == MeshGenerator::gmsh       ? gmsh_file
           : generator == MeshGenerator::opensees ? opensees_file
                                                  : std::filesystem::path();
  }
};

// ----------------------------------------------------------------------------- OpenSees import

/// [opensees]: the recorder files opensees2fem reads (tools/interop/README.md); paths
/// absolute (given relative to the case file's folder). Empty paths: not recorded.
struct OpenSeesImportSpec {
  /// The recorder time of the reference state (fem-solve's u = 0, the end of the gravity
  /// stage): displacement and strain are measured from the first row at this time.
  std::optional<double> reference_time;
  /// The recorder time of the start of the failure stage (t = 0 of the checkpoints); 0
  /// when loadConst -time 0.0 reset OpenSees's clock there.
  double start_time = 0.0;
  std::filesystem::path displacement;   ///< Node -dof 1 2 disp (required)
  std::filesystem::path velocity;       ///< Node -dof 1 2 vel (required)
  std::filesystem::path acceleration;   ///< Node -dof 1 2 accel (zero when absent)
  std::filesystem::path pore_pressure;  ///< Node -dof 3 vel of u–p nodes (zero when absent)
  std::filesystem::path stress;         ///< Element stress (required)
  std::filesystem::path strain;         ///< Element strain (from the displacements when absent)
};

}  // namespace slide
