// The case reader's [mesh] table: a profile, blocks or a Gmsh file.
// Section, the ranges and the shared readers are in case_file_reader.hpp.

#include "common/input/case_file_reader.hpp"
#include "common/input/mesh_generation.hpp"

namespace slide::case_reader {

namespace {

/// The spellings of the mesh generators (those of the solvers' algorithms are in
/// algorithms.hpp).
constexpr std::array<Named<MeshGenerator>, 3> generator_names{{
    {"profile", MeshGenerator::profile},
    {"blocks", MeshGenerator::blocks},
    {"gmsh", MeshGenerator::gmsh},
}};

void read_profile(const Section& s, const MaterialTable& materials, MeshSpec& mesh) {
  const NodeReader& reader = s.reader();
  mesh.element_size = s.number("element_size", positive("m"));
  const auto& items = reader.array(s.node("surface"), s.dotted("surface"));
  if (items.size() < 2) {
    s.fail("surface", fmt::format("expected at least 2 points [x, y], found {}", items.size()));
  }
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string item = fmt::format("{}[{}]", s.dotted("surface"), i);
    const Vec2 p = reader.point(items[i], item);
    if (i == 0 && p.x() != 0.0) {
      reader.fail(items[i], item,
                  fmt::format("{}: the surface must start at the wall x = 0", format_point(p)));
    }
    if (i > 0 && p.x() <= mesh.surface.back().x()) {
      reader.fail(items[i], item,
                  fmt::format("{}: x must increase strictly along the surface (previous x = {})",
                              format_point(p), mesh.surface.back().x()));
    }
    if (!(p.y() > 0.0)) {
      reader.fail(items[i], item,
                  fmt::format("{}: the surface must lie above the base (y > 0)", format_point(p)));
    }
    mesh.surface.push_back(p);
  }
  mesh.material = read_material_name(s, "material", materials);
}

MeshBlock read_block(const Section& s, const MaterialTable& materials) {
  const NodeReader& reader = s.reader();
  MeshBlock block;
  const auto& corners = reader.array(s.node("corners"), s.dotted("corners"));
  if (corners.size() != 4) {
    s.fail("corners", fmt::format("expected 4 corner points, found {}", corners.size()));
  }
  for (std::size_t i = 0; i < 4; ++i) {
    block.corners[i] = reader.point(corners[i], fmt::format("{}[{}]", s.dotted("corners"), i));
  }
  // The mesher's own rule (mesh_generation.hpp), reported at the corners' line.
  if (const auto problem = block_corners_problem(block)) s.fail("corners", *problem);
  const auto& cells = reader.array(s.node("cells"), s.dotted("cells"));
  if (cells.size() != 2) {
    s.fail("cells", fmt::format("expected [nu, nv], found {} items", cells.size()));
  }
  constexpr int most = std::numeric_limits<int>::max();
  block.cells_u = reader.integer(cells[0], fmt::format("{}[0]", s.dotted("cells")), 1, most);
  block.cells_v = reader.integer(cells[1], fmt::format("{}[1]", s.dotted("cells")), 1, most);
  block.material = read_material_name(s, "material", materials);
  return block;
}

void read_blocks(const Section& s, const MaterialTable& materials, MeshSpec& mesh) {
  const auto sections = s.tables("blocks", Section::Keys{"corners", "cells", "material"});
  if (sections.empty()) s.fail("blocks", "at least one [[mesh.blocks]] table is required");
  for (const Section& block : sections) mesh.blocks.push_back(read_block(block, materials));
  for (std::size_t i = 0; i < mesh.blocks.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (auto mismatch = shared_edge_mismatch(mesh.blocks[i], mesh.blocks[j])) {
        sections[i].fail("cells", fmt::format("its nodes on the edge it shares with {}, {}, do "
                                              "not match theirs: choose cells that give equal "
                                              "spacing",
                                              sections[j].path(), *mismatch));
      }
    }
  }
}

void read_gmsh_file(const Section& s, const std::filesystem::path& case_folder, MeshSpec& mesh) {
  const std::string file = s.string("file");
  if (file.empty()) s.fail("file", "expected the path of a .msh file");
  // Relative to the case's folder; stored absolute so that it reads from anywhere.
  mesh.gmsh_file = std::filesystem::absolute(case_folder / file).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(mesh.gmsh_file, ec)) {
    s.fail("file",
           fmt::format("\"{}\" does not exist (looked for {})", file, mesh.gmsh_file.string()));
  }
}

}  // namespace

MeshSpec read_mesh(const Section& root, const MaterialTable& materials,
                   const std::filesystem::path& case_folder) {
  const Section s = root.table("mesh", Section::Keys{"generator", "element", "element_size",
                                                     "surface", "material", "blocks", "file"});
  MeshSpec mesh;
  mesh.generator = s.choice("generator", generator_names, std::optional<MeshGenerator>());
  if (s.has("element")) {
    mesh.element_type = parse_element_type(
        s.string("element"), fmt::format("{}: {}", s.where("element"), s.dotted("element")));
  }
  const std::string not_here =
      fmt::format("not used by generator \"{}\"", name_of(generator_names, mesh.generator));
  const auto reject_all = [&](std::initializer_list<std::string_view> keys) {
    for (std::string_view key : keys) s.reject(key, not_here);
  };
  switch (mesh.generator) {
    case MeshGenerator::profile:
      reject_all({"blocks", "file"});
      read_profile(s, materials, mesh);
      break;
    case MeshGenerator::blocks:
      reject_all({"element_size", "surface", "material", "file"});
      read_blocks(s, materials, mesh);
      break;
    case MeshGenerator::gmsh:
      reject_all({"element_size", "surface", "material", "blocks"});
      read_gmsh_file(s, case_folder, mesh);
      break;
  }
  return mesh;
}

/// Bounding box of the initial body, when the case file alone determines it.
std::optional<std::pair<Vec2, Vec2>> body_box(const MeshSpec& mesh) {
  Vec2 lo = Vec2::Constant(infinity);
  Vec2 hi = Vec2::Constant(-infinity);
  auto add = [&](const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  switch (mesh.generator) {
    case MeshGenerator::profile:
      for (const Vec2& p : mesh.surface) add(p);
      add(Vec2(0.0, 0.0));
      return std::pair{lo, hi};
    case MeshGenerator::blocks:
      for (const MeshBlock& block : mesh.blocks) {
        for (const Vec2& p : block.corners) add(p);
      }
      return std::pair{lo, hi};
    case MeshGenerator::gmsh:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace slide::case_reader
