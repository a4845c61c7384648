// The case reader's [mesh] table: a profile, blocks or a Gmsh file.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include <cmath>

#include "common/case_file_reader.hpp"

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

/// Nodes of a block edge (side k from corner k to corner k+1): evenly spaced, as the
/// transfinite map places them.
std::vector<Vec2> edge_nodes(const MeshBlock& block, int side) {
  const Vec2& a = block.corners[static_cast<std::size_t>(side)];
  const Vec2& b = block.corners[static_cast<std::size_t>((side + 1) % 4)];
  const int cells = side % 2 == 0 ? block.cells_u : block.cells_v;
  std::vector<Vec2> nodes;
  for (int i = 0; i <= cells; ++i) nodes.push_back(a + (b - a) * (static_cast<double>(i) / cells));
  return nodes;
}

/// Blocks that share (part of) an edge must put nodes at the same places there, or the
/// mesh would have hanging nodes. Returns a description of the first mismatch.
std::optional<std::string> check_block_edges(const MeshBlock& a, const MeshBlock& b) {
  for (int side_a = 0; side_a < 4; ++side_a) {
    const auto nodes_a = edge_nodes(a, side_a);
    const Vec2 p = nodes_a.front();
    const Vec2 q = nodes_a.back();
    const double length = (q - p).norm();
    const Vec2 t = (q - p) / length;
    const double spacing_a = length / static_cast<double>(nodes_a.size() - 1);
    for (int side_b = 0; side_b < 4; ++side_b) {
      const auto nodes_b = edge_nodes(b, side_b);
      const double spacing_b =
          (nodes_b.back() - nodes_b.front()).norm() / static_cast<double>(nodes_b.size() - 1);
      const double tol = 1e-6 * std::min(spacing_a, spacing_b);
      auto off_line = [&](const Vec2& r) {
        const Vec2 d = r - p;
        return std::abs(d.x() * t.y() - d.y() * t.x()) > tol;
      };
      if (off_line(nodes_b.front()) || off_line(nodes_b.back())) continue;
      const double s0 = (nodes_b.front() - p).dot(t);
      const double s1 = (nodes_b.back() - p).dot(t);
      const double lo = std::max(0.0, std::min(s0, s1));
      const double hi = std::min(length, std::max(s0, s1));
      if (hi - lo <= tol) continue;  // collinear but not overlapping, or touching at a point
      auto matched = [&](const std::vector<Vec2>& from, const std::vector<Vec2>& to) {
        for (const Vec2& r : from) {
          const double s = (r - p).dot(t);
          if (s < lo - tol || s > hi + tol) continue;
          const bool found = std::any_of(to.begin(), to.end(),
                                         [&](const Vec2& u) { return (u - r).norm() <= tol; });
          if (!found) return false;
        }
        return true;
      };
      if (!matched(nodes_a, nodes_b) || !matched(nodes_b, nodes_a)) {
        return fmt::format("from {} to {} (node spacing {:.6g} m here, {:.6g} m there)",
                           format_point(p + lo * t), format_point(p + hi * t), spacing_a,
                           spacing_b);
      }
    }
  }
  return std::nullopt;
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
  double twice_area = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec2& a = block.corners[i];
    const Vec2& b = block.corners[(i + 1) % 4];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  if (!(twice_area > 0.0)) {
    s.fail("corners", fmt::format("the corners are clockwise or degenerate (signed area {} m²); "
                                  "list them counter-clockwise",
                                  0.5 * twice_area));
  }
  // The bilinear map of a non-convex quadrilateral folds over itself.
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec2 in = block.corners[i] - block.corners[(i + 3) % 4];
    const Vec2 out = block.corners[(i + 1) % 4] - block.corners[i];
    if (!(in.x() * out.y() - in.y() * out.x() > 0.0)) {
      s.fail("corners", fmt::format("the quadrilateral is not convex at corner {} {}", i,
                                    format_point(block.corners[i])));
    }
  }
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
      if (auto mismatch = check_block_edges(mesh.blocks[i], mesh.blocks[j])) {
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
