// The case reader's [mesh] table: a profile, blocks or a Gmsh file.
// Section, the ranges and the shared readers are in case_file_reader.hpp.

#include "common/input/case_file_reader.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/io/opensees_reader.hpp"

namespace slide::case_reader {

namespace {

/// The spellings of the mesh generators (those of the solvers' algorithms are in
/// algorithms.hpp).
constexpr std::array<Named<MeshGenerator>, 4> generator_names{{
    {"profile", MeshGenerator::profile},
    {"blocks", MeshGenerator::blocks},
    {"gmsh", MeshGenerator::gmsh},
    {"opensees", MeshGenerator::opensees},
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

/// A file named by `key`, relative to the case's folder; returned absolute so that it
/// reads from anywhere. `what` describes it for an empty value ("a .msh file").
std::filesystem::path read_file_path(const Section& s, std::string_view key,
                                     const std::filesystem::path& case_folder,
                                     std::string_view what) {
  const std::string file = s.string(key);
  if (file.empty()) s.fail(key, fmt::format("expected the path of {}", what));
  std::filesystem::path path = std::filesystem::absolute(case_folder / file).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    s.fail(key, fmt::format("\"{}\" does not exist (looked for {})", file, path.string()));
  }
  return path;
}

void read_gmsh_file(const Section& s, const std::filesystem::path& case_folder, MeshSpec& mesh) {
  mesh.gmsh_file = read_file_path(s, "file", case_folder, "a .msh file");
}

/// generator = "opensees": file, materials = { "<tag>" = "<material>" }, ignore_elements.
void read_opensees_model(const Section& s, const MaterialTable& materials,
                         const std::filesystem::path& case_folder, MeshSpec& mesh) {
  const NodeReader& reader = s.reader();
  mesh.opensees_file = read_file_path(s, "file", case_folder, "a model printed by print -JSON");
  const auto* table = s.node("materials").as_table();
  if (table == nullptr) {
    reader.wrong_type(s.node("materials"), s.dotted("materials"),
                      "a table of OpenSees material tags, e.g. { \"1\" = \"soil\" }");
  }
  for (const auto& [tag, name] : *table) {
    const std::string item = fmt::format("{}.{}", s.dotted("materials"), tag.str());
    const std::string material = reader.string(name, item);
    if (std::none_of(materials.begin(), materials.end(),
                     [&](const Material& m) { return m.name == material; })) {
      reader.fail(name, item, fmt::format("'{}' is not a material of the case", material));
    }
    mesh.opensees_materials.emplace(std::string(tag.str()), material);
  }
  if (mesh.opensees_materials.empty()) {
    s.fail("materials", "map at least one OpenSees material tag to a material of the case");
  }
  if (s.has("ignore_elements")) {
    const auto& items = reader.array(s.node("ignore_elements"), s.dotted("ignore_elements"));
    for (std::size_t i = 0; i < items.size(); ++i) {
      mesh.ignore_elements.push_back(
          reader.string(items[i], fmt::format("{}[{}]", s.dotted("ignore_elements"), i)));
    }
  }
  // The element type is the model's (opensees_reader.hpp); a case that names one must
  // name the same.
  const ElementType type = read_opensees_element_type(mesh.opensees_file, mesh.ignore_elements);
  if (s.has("element") && mesh.element_type != type) {
    s.fail("element", fmt::format("\"{}\" differs from the model's elements, which are {}",
                                  to_string(mesh.element_type), to_string(type)));
  }
  mesh.element_type = type;
}

}  // namespace

MeshSpec read_mesh(const Section& root, const MaterialTable& materials,
                   const std::filesystem::path& case_folder) {
  const Section s = root.table(
      "mesh", Section::Keys{"generator", "element", "element_size", "surface", "material", "blocks",
                            "file", "materials", "ignore_elements"});
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
      reject_all({"blocks", "file", "materials", "ignore_elements"});
      read_profile(s, materials, mesh);
      break;
    case MeshGenerator::blocks:
      reject_all({"element_size", "surface", "material", "file", "materials", "ignore_elements"});
      read_blocks(s, materials, mesh);
      break;
    case MeshGenerator::gmsh:
      reject_all({"element_size", "surface", "material", "blocks", "materials", "ignore_elements"});
      read_gmsh_file(s, case_folder, mesh);
      break;
    case MeshGenerator::opensees:
      reject_all({"element_size", "surface", "material", "blocks"});
      read_opensees_model(s, materials, case_folder, mesh);
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
    case MeshGenerator::opensees:
      return std::nullopt;
  }
  return std::nullopt;
}

std::optional<OpenSeesImportSpec> read_opensees_import(const Section& root, const MeshSpec& mesh,
                                                       const std::filesystem::path& case_folder) {
  const auto s = root.optional_table(
      "opensees", Section::Keys{"reference_time", "start_time", "displacement", "velocity",
                                "acceleration", "pore_pressure", "stress", "strain"});
  if (!s) return std::nullopt;
  if (mesh.generator != MeshGenerator::opensees) {
    s->fail("displacement",
            "[opensees] names the recorders of an OpenSees model: it needs "
            "mesh.generator = \"opensees\"");
  }
  OpenSeesImportSpec spec;
  if (s->has("reference_time")) spec.reference_time = s->number("reference_time", any_number());
  spec.start_time = s->number("start_time", any_number(), 0.0);
  const auto file = [&](std::string_view key, bool required) {
    if (!required && !s->has(key)) return std::filesystem::path();
    return read_file_path(*s, key, case_folder, "a recorder file");
  };
  spec.displacement = file("displacement", true);
  spec.velocity = file("velocity", true);
  spec.acceleration = file("acceleration", false);
  spec.pore_pressure = file("pore_pressure", false);
  spec.stress = file("stress", true);
  spec.strain = file("strain", false);
  return spec;
}

}  // namespace slide::case_reader
