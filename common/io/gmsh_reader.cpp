// Gmsh .msh import (ASCII 4.1 and 2.2), see gmsh_reader.hpp.
//
// Sections read: $MeshFormat, $PhysicalNames, $Entities (4.1: which physical groups an
// entity belongs to), $Nodes, $Elements; every other section is skipped. Element types:
// 3 (4-node quadrangle), 2 (3-node triangle), 1 (2-node line, boundary groups), 15
// (point: it only excuses its node, below). The file is read as a stream of white-space
// separated tokens (as Gmsh itself reads it), remembering the line of every token for
// the messages.
//
// What the reader makes of it (each error names the file, the line and the Gmsh tag of
// the element, node or group at fault):
//  - surface elements: each in exactly one 2-D physical group, whose name is a material
//    of the case; det J of one sign at every corner (no re-entrant or zero-area element);
//    orientation consistent within each elementary (geometric) surface entity, the
//    element's 2nd tag in 2.2, its block's entity in 4.1. Gmsh orients all elements of
//    a surface alike, clockwise when its curve loop is clockwise: a wholly clockwise
//    entity is turned counter-clockwise, an element turned against the rest of its
//    entity is an error (the mesh folds over itself; a tie goes to the entity's first
//    element);
//  - nodes: those of the surface elements, numbered in increasing tag order (tags need
//    not be contiguous), so a 2.2 and a 4.1 export of the same mesh, whose $Nodes
//    sections list the nodes in different orders, read the same. Every element's nodes
//    must be in $Nodes. A node no surface element uses is an error, unless only point
//    elements use it: then it is dropped (a geometry point Gmsh saved on its own);
//  - node sets: one per 1-D physical group, the nodes of its lines, with the outward
//    normal of the surface-element edges the lines lie on (each line must be an edge of
//    exactly one surface element, and the group must be straight). A line in no group
//    is ignored but must still be an edge of the mesh (no dangling lines);
//  - physical groups: every 1-D or 2-D name of $PhysicalNames must hold elements;
//  - tri3: quadrangles are split along their shorter diagonal (of the two diagonals that
//    leave both triangles counter-clockwise); triangles are taken as they are.
#include "common/io/gmsh_reader.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/base/error.hpp"

namespace slide {
namespace {

// A boundary group is straight when every node lies within this fraction of the group's
// length from its line, and every line's normal is within ~1e-3 rad of the group's.
constexpr double straightness_tolerance = 1e-6;
constexpr double normal_tolerance = 1e-6;  // 1 − cos(angle)

constexpr int gmsh_line = 1;
constexpr int gmsh_triangle = 2;
constexpr int gmsh_quadrangle = 3;
constexpr int gmsh_point = 15;

/// Nodes of the supported Gmsh element types, 0 for the others.
int gmsh_node_count(std::int64_t type) {
  switch (type) {
    case gmsh_line:
      return 2;
    case gmsh_triangle:
      return 3;
    case gmsh_quadrangle:
      return 4;
    case gmsh_point:
      return 1;
    default:
      return 0;
  }
}

std::string_view gmsh_type_name(std::int64_t type) {
  switch (type) {
    case 4:
      return "4-node tetrahedron";
    case 5:
      return "8-node hexahedron";
    case 6:
      return "6-node prism";
    case 7:
      return "5-node pyramid";
    case 8:
      return "3-node line";
    case 9:
      return "6-node triangle";
    case 10:
      return "9-node quadrangle";
    case 16:
      return "8-node quadrangle";
    default:
      return "not a linear 2-D element";
  }
}

/// The file as a stream of tokens, with the line of each and the section being read.
class Scanner {
 public:
  Scanner(std::string file, std::string text) : file_(std::move(file)), text_(std::move(text)) {}

  /// Skips white space; true at the end of the file.
  bool at_end() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) != 0) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    return pos_ >= text_.size();
  }

  /// The next token; `what` says what was expected, for the message at the end of file.
  std::string_view token(std::string_view what) {
    if (at_end()) {
      fail(token_line_, "truncated ${} section: end of file while reading {}", section_, what);
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) == 0) {
      ++pos_;
    }
    token_line_ = line_;
    return std::string_view(text_).substr(start, pos_ - start);
  }

  std::int64_t integer(std::string_view what) {
    const std::string_view t = number_token(what);
    std::int64_t value = 0;
    const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (error != std::errc() || end != t.data() + t.size()) {
      fail(token_line_, "expected {} (an integer), found '{}'", what, t);
    }
    return value;
  }

  /// An integer that counts something (≥ 0).
  std::int64_t count(std::string_view what) {
    const std::int64_t value = integer(what);
    if (value < 0) fail(token_line_, "{} = {} is negative", what, value);
    return value;
  }

  double real(std::string_view what) {
    const std::string_view t = number_token(what);
    double value = 0.0;
    const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (error != std::errc() || end != t.data() + t.size() || !std::isfinite(value)) {
      fail(token_line_, "expected {} (a number), found '{}'", what, t);
    }
    return value;
  }

  /// The rest of the current line, trimmed (a physical group's quoted name).
  std::string rest_of_line() {
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    std::string_view rest = std::string_view(text_).substr(pos_, end - pos_);
    pos_ = end;
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.front())) != 0) {
      rest.remove_prefix(1);
    }
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.back())) != 0) {
      rest.remove_suffix(1);
    }
    return std::string(rest);
  }

  /// Enters section `name`: messages about truncation name it.
  void begin_section(std::string_view name) { section_ = name; }
  /// Expects `$End<section>` as the next token.
  void end_section() {
    const std::string end = "$End" + section_;
    const std::string_view t = token(end);
    if (t != end) {
      fail(token_line_,
           "expected {} (more entries than the section's count announces?), found "
           "'{}'",
           end, t);
    }
  }
  /// Skips a section this reader does not use, up to its `$End<name>`.
  void skip_section(std::string_view name) {
    begin_section(name);
    const std::string end = "$End" + section_;
    while (token(end) != end) {
    }
  }

  std::size_t line() const { return token_line_; }
  const std::string& file() const { return file_; }

  template <typename... Args>
  [[noreturn]] void fail(std::size_t line, fmt::format_string<Args...> format,
                         Args&&... args) const {
    throw Error("{}:{}: {}", file_, line, fmt::format(format, std::forward<Args>(args)...));
  }

 private:
  /// A token that should be a number: a `$...` keyword here means the section ended
  /// before its announced count.
  std::string_view number_token(std::string_view what) {
    const std::string_view t = token(what);
    if (t.front() == '$') {
      fail(token_line_, "truncated ${} section: expected {}, found {}", section_, what, t);
    }
    return t;
  }

  std::string file_;
  std::string text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t token_line_ = 1;
  std::string section_ = "MeshFormat";
};

struct RawNode {
  std::int64_t tag;
  Vec2 x;
  std::size_t line;
};

/// A point, line, triangle or quadrangle as the file gives it.
struct RawElement {
  std::int64_t tag;
  int type;
  int node_count;
  std::array<std::int64_t, 4> nodes{};
  std::vector<int> physicals;  ///< physical groups (of the element's dimension)
  int entity;                  ///< the elementary (geometric) entity it meshes, 0 if not given
  std::size_t line;
};

struct PhysicalName {
  std::string name;
  std::size_t line;
};

/// A surface element as the mesh takes it: the raw indices of its nodes, its material.
struct Polygon {
  std::array<std::size_t, 4> nodes;
  int count;
  std::int32_t material;
  std::size_t element;  ///< index in the reader's elements
};

/// The edges of the surface elements: the node pair (lower index first) → the directed
/// edges a → b of the counter-clockwise elements that have it (two for an inner edge).
using Edges = std::map<std::pair<Index, Index>, std::vector<std::pair<Index, Index>>>;

/// A line element of a boundary group, directed counter-clockwise along its element.
struct BoundaryLine {
  Index from;
  Index to;  ///< counter-clockwise along the adjacent element
  const RawElement* element;
};

/// Which raw nodes (of `node_count`) the surface elements use.
std::vector<bool> used_nodes(const std::vector<Polygon>& polygons, std::size_t node_count) {
  std::vector<bool> used(node_count, false);
  for (const Polygon& polygon : polygons) {
    for (int k = 0; k < polygon.count; ++k) used[polygon.nodes[static_cast<std::size_t>(k)]] = true;
  }
  return used;
}

/// Each surface element's nodes in the mesh's numbering, counter-clockwise (the elements
/// of a clockwise entity turned); a triangle's fourth node is -1.
std::vector<std::array<Index, 4>> counter_clockwise_elements(const std::vector<Polygon>& polygons,
                                                             const std::vector<int>& orientation,
                                                             const std::vector<Index>& new_index) {
  std::vector<std::array<Index, 4>> elements;
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& polygon = polygons[i];
    std::array<Index, 4> v{};
    for (std::size_t k = 0; k < 4; ++k) {
      v[k] = k < static_cast<std::size_t>(polygon.count) ? new_index[polygon.nodes[k]] : -1;
    }
    const auto count = static_cast<std::size_t>(polygon.count);
    if (orientation[i] < 0) std::reverse(v.begin() + 1, v.begin() + static_cast<long>(count));
    elements.push_back(v);
  }
  return elements;
}

/// The directed edges of the counter-clockwise elements, by node pair.
Edges element_edges(const std::vector<Polygon>& polygons,
                    const std::vector<std::array<Index, 4>>& elements) {
  Edges edges;
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const auto& v = elements[i];
    const auto count = static_cast<std::size_t>(polygons[i].count);
    for (std::size_t k = 0; k < count; ++k) {
      const Index a = v[k];
      const Index b = v[(k + 1) % count];
      edges[{std::min(a, b), std::max(a, b)}].emplace_back(a, b);
    }
  }
  return edges;
}

/// Appends counter-clockwise quadrangle `v` as two triangles, split along the shorter
/// diagonal of those that leave both triangles counter-clockwise (a–c on a tie, and when
/// neither does).
void append_split_quadrangle(Mesh& mesh, const std::array<Index, 4>& v, std::int32_t material) {
  const auto x_of = [&](Index node) -> const Vec2& {
    return mesh.nodes[static_cast<std::size_t>(node)];
  };
  const auto twice_area = [&](Index a, Index b, Index c) {
    const Vec2 ab = x_of(b) - x_of(a);
    const Vec2 ac = x_of(c) - x_of(a);
    return ab.x() * ac.y() - ab.y() * ac.x();
  };
  const bool ac_valid = twice_area(v[0], v[1], v[2]) > 0.0 && twice_area(v[0], v[2], v[3]) > 0.0;
  const bool bd_valid = twice_area(v[0], v[1], v[3]) > 0.0 && twice_area(v[1], v[2], v[3]) > 0.0;
  const double ac = (x_of(v[2]) - x_of(v[0])).norm();
  const double bd = (x_of(v[3]) - x_of(v[1])).norm();
  if ((ac_valid && (!bd_valid || ac <= bd)) || (!ac_valid && !bd_valid)) {
    mesh.connectivity.insert(mesh.connectivity.end(), {v[0], v[1], v[2], v[0], v[2], v[3]});
  } else {
    mesh.connectivity.insert(mesh.connectivity.end(), {v[0], v[1], v[3], v[1], v[2], v[3]});
  }
  mesh.material_id.insert(mesh.material_id.end(), {material, material});
}

/// The connectivity of `elements` in element shape `shape`: as they are, or for tri3
/// each quadrangle split in two.
void add_connectivity(Mesh& mesh, ElementShape shape, const std::vector<Polygon>& polygons,
                      const std::vector<std::array<Index, 4>>& elements) {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const auto& v = elements[i];
    const std::int32_t material = polygons[i].material;
    if (polygons[i].count == 3 || shape == ElementShape::quad4) {
      mesh.connectivity.insert(mesh.connectivity.end(), v.begin(), v.begin() + polygons[i].count);
      mesh.material_id.push_back(material);
    } else {
      append_split_quadrangle(mesh, v, material);
    }
  }
}

/// Outward normal of boundary line `line`, |line| long: for an edge a → b of a
/// counter-clockwise element, the tangent turned clockwise.
Vec2 outward_normal(const Mesh& mesh, const BoundaryLine& line) {
  const Vec2 t = mesh.nodes[static_cast<std::size_t>(line.to)] -
                 mesh.nodes[static_cast<std::size_t>(line.from)];
  return Vec2(t.y(), -t.x());
}

/// The diagonal of the bounding box of `lines`: the group's length scale.
double bounding_size(const Mesh& mesh, const std::vector<BoundaryLine>& lines) {
  Vec2 low = mesh.nodes[static_cast<std::size_t>(lines.front().from)];
  Vec2 high = low;
  for (const BoundaryLine& line : lines) {
    for (const Index node : {line.from, line.to}) {
      low = low.cwiseMin(mesh.nodes[static_cast<std::size_t>(node)]);
      high = high.cwiseMax(mesh.nodes[static_cast<std::size_t>(node)]);
    }
  }
  return (high - low).norm();
}

using DimTag = std::pair<int, int>;

class GmshReader {
 public:
  GmshReader(const std::filesystem::path& path, std::string text, ElementType type,
             const MaterialTable& materials)
      : in_(path.string(), std::move(text)), type_(type), materials_(materials) {}

  Mesh read() {
    read_format();
    while (!in_.at_end()) {
      const std::string_view keyword = in_.token("a section");
      const std::size_t line = in_.line();
      if (keyword.size() < 2 || keyword.front() != '$') {
        in_.fail(line, "expected a section ($Nodes, $Elements, ...), found '{}'", keyword);
      }
      const std::string name(keyword.substr(1));
      if (name == "PhysicalNames") {
        read_physical_names();
      } else if (name == "Entities" && version_ == 41) {
        read_entities();
      } else if (name == "Nodes") {
        version_ == 41 ? read_nodes_41() : read_nodes_22();
        have_nodes_ = true;
      } else if (name == "Elements") {
        version_ == 41 ? read_elements_41() : read_elements_22();
        have_elements_ = true;
      } else {
        in_.skip_section(name);
      }
    }
    if (!have_nodes_) throw Error("{}: no $Nodes section", in_.file());
    if (!have_elements_) throw Error("{}: no $Elements section", in_.file());
    return assemble();
  }

 private:
  void read_format() {
    if (in_.at_end()) throw Error("{}:1: empty file (expected a Gmsh mesh)", in_.file());
    const std::string_view first = in_.token("$MeshFormat");
    if (first != "$MeshFormat") {
      in_.fail(in_.line(), "not a Gmsh mesh: bad header (expected $MeshFormat, found '{}')", first);
    }
    const std::string_view version = in_.token("the format version");
    const std::size_t line = in_.line();
    if (version == "4.1") {
      version_ = 41;
    } else if (version == "2.2") {
      version_ = 22;
    } else {
      in_.fail(line, "unsupported .msh version {} (expected 4.1 or 2.2, ASCII)", version);
    }
    const std::int64_t file_type = in_.integer("the file type (0: ASCII)");
    if (file_type != 0) {
      in_.fail(line, "binary .msh files are not supported (export the mesh as ASCII)");
    }
    in_.integer("the data size");
    in_.end_section();
  }

  void read_physical_names() {
    in_.begin_section("PhysicalNames");
    const std::int64_t n = in_.count("the number of physical names");
    for (std::int64_t k = 0; k < n; ++k) {
      const auto dim = static_cast<int>(in_.integer("a physical group's dimension"));
      const std::size_t line = in_.line();
      const auto tag = static_cast<int>(in_.integer("a physical group's tag"));
      std::string name = in_.rest_of_line();
      if (name.size() >= 2 && name.front() == '"' && name.back() == '"') {
        name = name.substr(1, name.size() - 2);
      }
      if (name.empty()) in_.fail(line, "physical group {} (dimension {}) has no name", tag, dim);
      physical_names_[{dim, tag}] = PhysicalName{name, line};
    }
    in_.end_section();
  }

  void read_entities() {
    in_.begin_section("Entities");
    std::array<std::int64_t, 4> counts{};
    for (auto& c : counts) c = in_.count("the number of entities");
    for (int dim = 0; dim < 4; ++dim) {
      for (std::int64_t k = 0; k < counts[static_cast<std::size_t>(dim)]; ++k) {
        const auto tag = static_cast<int>(in_.integer("an entity tag"));
        // A point has its coordinates, the others their bounding box.
        for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) in_.real("entity coordinates");
        auto& physicals = entity_physicals_[{dim, tag}];
        const std::int64_t n_physicals = in_.count("the number of physical tags");
        for (std::int64_t p = 0; p < n_physicals; ++p) {
          physicals.push_back(static_cast<int>(in_.integer("a physical tag")));
        }
        if (dim > 0) {
          const std::int64_t n_bounding = in_.count("the number of bounding entities");
          for (std::int64_t b = 0; b < n_bounding; ++b) in_.integer("a bounding entity tag");
        }
      }
    }
    in_.end_section();
  }

  void add_node(std::int64_t tag, std::size_t line, double x, double y, double z) {
    // A 2-D mesh lies in the plane z = 0.
    if (std::abs(z) > 1e-9 * (1.0 + std::abs(x) + std::abs(y))) {
      in_.fail(line, "node {} has z = {} (a plane strain mesh lies in the plane z = 0)", tag, z);
    }
    if (!node_index_.emplace(tag, nodes_.size()).second) {
      in_.fail(line, "node tag {} appears twice", tag);
    }
    nodes_.push_back(RawNode{tag, Vec2(x, y), line});
  }

  void read_nodes_22() {
    in_.begin_section("Nodes");
    const std::int64_t n = in_.count("the number of nodes");
    for (std::int64_t k = 0; k < n; ++k) {
      const std::string what = fmt::format("node {} of {}", k + 1, n);
      const std::int64_t tag = in_.integer(what);
      const std::size_t line = in_.line();
      const double x = in_.real(what);
      const double y = in_.real(what);
      const double z = in_.real(what);
      add_node(tag, line, x, y, z);
    }
    in_.end_section();
  }

  void read_nodes_41() {
    in_.begin_section("Nodes");
    const std::int64_t blocks = in_.count("the number of node blocks");
    const std::int64_t n = in_.count("the number of nodes");
    in_.integer("the smallest node tag");
    in_.integer("the largest node tag");
    std::int64_t read = 0;
    std::vector<std::pair<std::int64_t, std::size_t>> tags;
    for (std::int64_t b = 0; b < blocks; ++b) {
      const std::int64_t dim = in_.integer("a node block's entity dimension");
      in_.integer("a node block's entity tag");
      const std::int64_t parametric = in_.integer("a node block's parametric flag");
      const std::int64_t in_block = in_.count("a node block's node count");
      tags.clear();
      for (std::int64_t k = 0; k < in_block; ++k) {
        tags.emplace_back(in_.integer(fmt::format("node {} of {}", read + k + 1, n)), in_.line());
      }
      for (std::int64_t k = 0; k < in_block; ++k) {
        const std::string what = fmt::format("coordinates of node {} of {}", read + k + 1, n);
        const double x = in_.real(what);
        const std::size_t line = in_.line();
        const double y = in_.real(what);
        const double z = in_.real(what);
        // Parametric nodes carry their entity coordinates (u, or u v) too.
        for (std::int64_t u = 0; parametric != 0 && u < dim; ++u) in_.real(what);
        add_node(tags[static_cast<std::size_t>(k)].first, line, x, y, z);
      }
      read += in_block;
    }
    if (read != n) {
      in_.fail(in_.line(), "$Nodes announces {} nodes but its blocks hold {}", n, read);
    }
    in_.end_section();
  }

  /// Reads the node tags of one element of Gmsh type `type` (in elementary entity
  /// `entity`) and stores it; `physicals` are the physical groups it belongs to.
  void read_element(std::int64_t tag, std::int64_t type, std::size_t line,
                    std::vector<int> physicals, int entity) {
    const int n = gmsh_node_count(type);
    if (n == 0) {
      in_.fail(line,
               "unsupported element type {} ({}) in element {}: only 4-node quadrangles (3), "
               "3-node triangles (2), 2-node lines (1) and points (15) are read",
               type, gmsh_type_name(type), tag);
    }
    RawElement element{tag, static_cast<int>(type), n, {}, std::move(physicals), entity, line};
    for (int k = 0; k < n; ++k) {
      element.nodes[static_cast<std::size_t>(k)] =
          in_.integer(fmt::format("node {} of element {}", k + 1, tag));
    }
    elements_.push_back(std::move(element));
  }

  void read_elements_22() {
    in_.begin_section("Elements");
    const std::int64_t n = in_.count("the number of elements");
    for (std::int64_t k = 0; k < n; ++k) {
      const std::string what = fmt::format("element {} of {}", k + 1, n);
      const std::int64_t tag = in_.integer(what);
      const std::size_t line = in_.line();
      const std::int64_t type = in_.integer(what);
      const std::int64_t n_tags = in_.count(what);
      std::vector<int> physicals;
      int entity = 0;
      for (std::int64_t t = 0; t < n_tags; ++t) {
        const auto value = static_cast<int>(in_.integer(what));
        // The first tag is the physical group (0: none), the second the entity.
        if (t == 0 && value != 0) physicals.push_back(value);
        if (t == 1) entity = value;
      }
      read_element(tag, type, line, std::move(physicals), entity);
    }
    in_.end_section();
  }

  void read_elements_41() {
    in_.begin_section("Elements");
    const std::int64_t blocks = in_.count("the number of element blocks");
    const std::int64_t n = in_.count("the number of elements");
    in_.integer("the smallest element tag");
    in_.integer("the largest element tag");
    std::int64_t read = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      const auto dim = static_cast<int>(in_.integer("an element block's entity dimension"));
      const auto entity = static_cast<int>(in_.integer("an element block's entity tag"));
      const std::int64_t type = in_.integer("an element block's element type");
      const std::int64_t in_block = in_.count("an element block's element count");
      const auto found = entity_physicals_.find({dim, entity});
      const std::vector<int> physicals =
          found == entity_physicals_.end() ? std::vector<int>{} : found->second;
      for (std::int64_t k = 0; k < in_block; ++k) {
        const std::int64_t tag = in_.integer(fmt::format("element {} of {}", read + k + 1, n));
        read_element(tag, type, in_.line(), physicals, entity);
      }
      read += in_block;
    }
    if (read != n) {
      in_.fail(in_.line(), "$Elements announces {} elements but its blocks hold {}", n, read);
    }
    in_.end_section();
  }

  /// Name of physical group (dim, tag): its $PhysicalNames name, or the tag itself.
  std::string group_name(int dim, int tag) const {
    const auto found = physical_names_.find({dim, tag});
    return found == physical_names_.end() ? std::to_string(tag) : found->second.name;
  }

  std::size_t raw_index(const RawElement& e, std::size_t k) const {
    const auto found = node_index_.find(e.nodes[k]);
    if (found == node_index_.end()) {
      in_.fail(e.line, "element {} refers to node {}, which is not in $Nodes", e.tag, e.nodes[k]);
    }
    return found->second;
  }

  std::int32_t material_of(const RawElement& e) const {
    if (e.physicals.empty()) {
      in_.fail(e.line,
               "surface element {} is in no physical group (every surface needs a physical "
               "group named after its material)",
               e.tag);
    }
    for (const int p : e.physicals) {
      if (group_name(2, p) != group_name(2, e.physicals.front())) {
        in_.fail(e.line, "surface element {} is in two physical groups, '{}' and '{}'", e.tag,
                 group_name(2, e.physicals.front()), group_name(2, p));
      }
    }
    const int group = e.physicals.front();
    const std::string name = group_name(2, group);
    for (std::size_t m = 0; m < materials_.size(); ++m) {
      if (materials_[m].name == name) return static_cast<std::int32_t>(m);
    }
    std::string known;
    for (const auto& m : materials_) known += (known.empty() ? "" : ", ") + m.name;
    const auto named = physical_names_.find({2, group});
    in_.fail(named == physical_names_.end() ? e.line : named->second.line,
             "physical surface '{}' is not a material of the case (materials: {})", name,
             known.empty() ? "none" : known);
  }

  /// Every element's node tags are in $Nodes (points included).
  void check_node_references() const {
    for (const RawElement& e : elements_) {
      for (int k = 0; k < e.node_count; ++k) raw_index(e, static_cast<std::size_t>(k));
    }
  }

  /// Every 1-D and 2-D physical group of $PhysicalNames holds elements: a boundary or a
  /// material named but not meshed is a mistake, not an empty set.
  void check_physical_groups_have_elements() const {
    std::map<DimTag, std::size_t> counts;
    for (const RawElement& e : elements_) {
      const int dim = e.type == gmsh_line ? 1 : e.type == gmsh_point ? 0 : 2;
      for (const int p : e.physicals) ++counts[{dim, p}];
    }
    for (const auto& [group, named] : physical_names_) {
      if (group.first != 1 && group.first != 2) continue;
      if (counts[group] == 0) {
        in_.fail(named.line,
                 "physical group '{}' (dimension {}, tag {}) has no elements (a {} named in "
                 "$PhysicalNames but not meshed)",
                 named.name, group.first, group.second, group.first == 1 ? "boundary" : "material");
      }
    }
  }

  /// Coordinates of a surface element's nodes, in the file's order.
  ElementNodes raw_coordinates(const RawElement& e) const {
    ElementNodes x = ElementNodes::Zero();
    for (int k = 0; k < e.node_count; ++k) {
      x.row(k) = nodes_[raw_index(e, static_cast<std::size_t>(k))].x.transpose();
    }
    return x;
  }

  /// +1 if surface element `e` is counter-clockwise as listed, −1 if clockwise. An element
  /// whose det J is not of one sign at all its corners (a re-entrant quadrangle) or is
  /// zero somewhere is an error whatever its orientation.
  int orientation_of(const RawElement& e) const {
    const ElementShape shape = e.type == gmsh_triangle ? ElementShape::tri3 : ElementShape::quad4;
    const ElementNodes x = raw_coordinates(e);
    const double sign = element_area(shape, x) < 0.0 ? -1.0 : 1.0;
    const double zero = degenerate_jacobian_fraction * longest_edge_squared(shape, x);
    const auto corners = reference_corners(shape);
    for (int k = 0; k < e.node_count; ++k) {
      // det J of the element turned counter-clockwise, at the node listed k-th.
      const double det =
          sign * jacobian(shape, x, corners[static_cast<std::size_t>(k)]).determinant();
      if (det <= zero) {
        const Vec2 centre = x.topRows(e.node_count).colwise().mean().transpose();
        in_.fail(e.line,
                 "element {} at ({:.6g}, {:.6g}) is inverted or has zero area: det J = {:.6g} "
                 "at its corner {} (node {} at ({:.6g}, {:.6g}))",
                 e.tag, centre.x(), centre.y(), det, k, e.nodes[static_cast<std::size_t>(k)],
                 x(k, 0), x(k, 1));
      }
    }
    return sign > 0.0 ? 1 : -1;
  }

  /// Orientation must be consistent within each surface entity: Gmsh orients all the
  /// elements of one surface alike (clockwise when its curve loop is), so an element
  /// turned against the rest of its surface is folded over its neighbours (or the file
  /// was edited). Returns each surface element's orientation; an entity wholly
  /// clockwise is fine and is turned by the caller.
  std::vector<int> consistent_orientations(const std::vector<std::size_t>& surface) const {
    struct Count {
      int counter_clockwise = 0;
      int clockwise = 0;
      int first = 0;  ///< orientation of its first element, breaks a tie
    };
    std::vector<int> orientation;
    std::map<int, Count> entities;
    for (const std::size_t i : surface) {
      orientation.push_back(orientation_of(elements_[i]));
      Count& count = entities[elements_[i].entity];
      if (count.first == 0) count.first = orientation.back();
      ++(orientation.back() > 0 ? count.counter_clockwise : count.clockwise);
    }
    const auto name = [](int o) { return o > 0 ? "counter-clockwise" : "clockwise"; };
    for (std::size_t s = 0; s < surface.size(); ++s) {
      const RawElement& e = elements_[surface[s]];
      const Count& count = entities.at(e.entity);
      const int majority = count.counter_clockwise > count.clockwise   ? 1
                           : count.clockwise > count.counter_clockwise ? -1
                                                                       : count.first;
      if (orientation[s] == majority) continue;
      const ElementShape shape = e.type == gmsh_triangle ? ElementShape::tri3 : ElementShape::quad4;
      const ElementNodes x = raw_coordinates(e);
      const Vec2 centre = x.topRows(e.node_count).colwise().mean().transpose();
      in_.fail(e.line,
               "element {} at ({:.6g}, {:.6g}) is {} (det J = {:.6g} at its centre) but {} of "
               "the {} elements of surface entity {} are {}: the mesh folds over itself there "
               "(Gmsh orients all the elements of one surface alike)",
               e.tag, centre.x(), centre.y(), name(orientation[s]),
               jacobian(shape, x, reference_centre(shape)).determinant(),
               majority > 0 ? count.counter_clockwise : count.clockwise,
               count.counter_clockwise + count.clockwise, e.entity, name(majority));
    }
    return orientation;
  }

  /// The mesh of the surface elements, after the checks of the file comment.
  Mesh assemble() {
    check_node_references();
    const std::vector<Polygon> polygons = surface_polygons();
    std::vector<std::size_t> surface;
    for (const Polygon& polygon : polygons) surface.push_back(polygon.element);
    check_physical_groups_have_elements();
    const std::vector<int> orientation = consistent_orientations(surface);

    Mesh mesh;
    mesh.element_type = type_;
    const std::vector<bool> used = used_nodes(polygons, nodes_.size());
    const std::vector<Index> new_index = renumber_used_nodes(mesh, used);
    const auto elements = counter_clockwise_elements(polygons, orientation, new_index);
    add_connectivity(mesh, shape_of(type_), polygons, elements);
    add_boundary_groups(mesh, new_index, element_edges(polygons, elements));
    check_unused_nodes(used);
    return mesh;
  }

  /// A quadrilateral element type cannot use triangles: the error, at the first, says
  /// how many of each the mesh has and the two ways on (tri3 splits the quadrangles of
  /// a mixed mesh; Gmsh can make quadrangles only).
  void refuse_triangles() const {
    const RawElement* first = nullptr;
    std::size_t triangles = 0, quadrangles = 0;
    for (const RawElement& e : elements_) {
      if (e.type == gmsh_triangle && first == nullptr) first = &e;
      triangles += e.type == gmsh_triangle ? 1 : 0;
      quadrangles += e.type == gmsh_quadrangle ? 1 : 0;
    }
    if (first == nullptr) return;
    in_.fail(first->line,
             "element {} is a triangle, which element type {} cannot use ({} mesh: {} "
             "triangles, {} quadrangles): use mesh.element = \"tri3\" (quadrangles are split "
             "in two), or mesh with quadrangles only (Gmsh: Mesh.RecombineAll = 1; "
             "Mesh.SubdivisionAlgorithm = 1; cases/README.md)",
             first->tag, to_string(type_), quadrangles > 0 ? "a mixed" : "a triangle", triangles,
             quadrangles);
  }

  /// The triangles and quadrangles with their raw nodes and material. A triangle in a
  /// quad4 mesh, an element listed twice and a file with none are errors.
  std::vector<Polygon> surface_polygons() const {
    const ElementShape shape = shape_of(type_);
    std::vector<Polygon> polygons;
    std::unordered_set<std::int64_t> surface_tags;
    if (shape == ElementShape::quad4) refuse_triangles();
    for (std::size_t i = 0; i < elements_.size(); ++i) {
      const RawElement& e = elements_[i];
      if (e.type != gmsh_triangle && e.type != gmsh_quadrangle) continue;
      // Gmsh 2.2 repeats an element once per physical group it belongs to.
      if (!surface_tags.insert(e.tag).second) {
        in_.fail(e.line,
                 "surface element {} appears twice (is it in two physical groups?); every "
                 "surface element needs exactly one, naming its material",
                 e.tag);
      }
      Polygon polygon{{}, e.node_count, material_of(e), i};
      for (int k = 0; k < e.node_count; ++k) {
        polygon.nodes[static_cast<std::size_t>(k)] = raw_index(e, static_cast<std::size_t>(k));
      }
      polygons.push_back(polygon);
    }
    if (polygons.empty()) {
      throw Error("{}: no quadrangles or triangles (a 2-D mesh is expected)", in_.file());
    }
    return polygons;
  }

  /// Adds the used nodes to `mesh` in increasing tag order (so a 2.2 and a 4.1 export
  /// read the same); returns each raw node's new index, -1 if unused.
  std::vector<Index> renumber_used_nodes(Mesh& mesh, const std::vector<bool>& used) const {
    std::vector<std::size_t> by_tag(nodes_.size());
    for (std::size_t r = 0; r < nodes_.size(); ++r) by_tag[r] = r;
    std::sort(by_tag.begin(), by_tag.end(),
              [&](std::size_t a, std::size_t b) { return nodes_[a].tag < nodes_[b].tag; });
    std::vector<Index> new_index(nodes_.size(), -1);
    for (const std::size_t r : by_tag) {
      if (!used[r]) continue;
      new_index[r] = mesh.node_count();
      mesh.nodes.push_back(nodes_[r].x);
    }
    return new_index;
  }

  /// A node no surface element uses is an error, unless only point elements refer to it
  /// (the mesh vertex of a geometry point, which Gmsh may save on its own): it is dropped.
  void check_unused_nodes(const std::vector<bool>& used) const {
    std::vector<bool> of_a_point(nodes_.size(), false);
    for (const RawElement& e : elements_) {
      if (e.type == gmsh_point) of_a_point[raw_index(e, 0)] = true;
    }
    for (std::size_t r = 0; r < nodes_.size(); ++r) {
      if (used[r] || of_a_point[r]) continue;
      in_.fail(nodes_[r].line,
               "node {} at ({:.6g}, {:.6g}) belongs to no element (every node of $Nodes must be "
               "a node of a surface element)",
               nodes_[r].tag, nodes_[r].x.x(), nodes_[r].x.y());
    }
  }

  /// One node set per 1-D physical group, with the outward normal of the surface-element
  /// edges its lines lie on.
  void add_boundary_groups(Mesh& mesh, const std::vector<Index>& new_index,
                           const Edges& edges) const {
    for (const auto& [group, lines] : boundary_lines(new_index, edges)) {
      mesh.node_sets.push_back(boundary_node_set(mesh, group_name(1, group), lines));
    }
  }

  /// The lines of each 1-D physical group (physical tag → lines), each directed along
  /// the one surface element whose edge it is.
  std::map<int, std::vector<BoundaryLine>> boundary_lines(const std::vector<Index>& new_index,
                                                          const Edges& edges) const {
    std::map<int, std::vector<BoundaryLine>> groups;
    for (const RawElement& e : elements_) {
      if (e.type != gmsh_line) continue;
      const auto& directed = edge_of_line(e, new_index, edges);
      for (const int group : e.physicals) {
        if (directed.size() > 1) {
          in_.fail(e.line,
                   "line element {} of physical group '{}' lies between two surface elements (a "
                   "boundary group must lie on the outside of the mesh)",
                   e.tag, group_name(1, group));
        }
        groups[group].push_back(BoundaryLine{directed.front().first, directed.front().second, &e});
      }
    }
    return groups;
  }

  /// The directed element edges line element `e` lies on. Every line, in a physical
  /// group or not, must be an edge of the surface mesh: a dangling line is a curve
  /// meshed apart from the surfaces.
  const Edges::mapped_type& edge_of_line(const RawElement& e, const std::vector<Index>& new_index,
                                         const Edges& edges) const {
    const Index a = new_index[raw_index(e, 0)];
    const Index b = new_index[raw_index(e, 1)];
    const auto found = edges.find({std::min(a, b), std::max(a, b)});
    if (a < 0 || b < 0 || found == edges.end()) {
      const std::string group =
          e.physicals.empty()
              ? std::string("in no physical group")
              : fmt::format("of physical group '{}'", group_name(1, e.physicals.front()));
      in_.fail(e.line, "line element {} (nodes {} and {}) {} is not an edge of any surface element",
               e.tag, e.nodes[0], e.nodes[1], group);
    }
    return found->second;
  }

  /// The node set `name` of `lines`, whose normal is their length-weighted mean outward
  /// normal; the group must be straight.
  NodeSet boundary_node_set(const Mesh& mesh, const std::string& name,
                            const std::vector<BoundaryLine>& lines) const {
    const double size = bounding_size(mesh, lines);
    const Vec2 normal = mean_outward_normal(mesh, name, lines, size);
    const Vec2& origin = mesh.nodes[static_cast<std::size_t>(lines.front().from)];
    NodeSet set{name, {}, normal};
    for (const BoundaryLine& line : lines) {
      check_on_group_line(mesh, name, line, normal, origin, size);
      set.nodes.insert(set.nodes.end(), {line.from, line.to});
    }
    std::sort(set.nodes.begin(), set.nodes.end());
    set.nodes.erase(std::unique(set.nodes.begin(), set.nodes.end()), set.nodes.end());
    return set;
  }

  /// The unit length-weighted mean outward normal of `lines`; an error when the normals
  /// cancel out (relative to the group's size `size`).
  Vec2 mean_outward_normal(const Mesh& mesh, const std::string& name,
                           const std::vector<BoundaryLine>& lines, double size) const {
    Vec2 sum = Vec2::Zero();
    for (const BoundaryLine& line : lines) sum += outward_normal(mesh, line);
    if (!(sum.norm() > straightness_tolerance * size)) {
      in_.fail(lines.front().element->line,
               "physical group '{}' is not straight (the outward normals of its lines cancel out)",
               name);
    }
    return sum.normalized();
  }

  /// Line `line` of group `name` keeps the group straight: its outward normal is the
  /// group's `normal` and its nodes lie on the group's line through `origin`.
  void check_on_group_line(const Mesh& mesh, const std::string& name, const BoundaryLine& line,
                           const Vec2& normal, const Vec2& origin, double size) const {
    const double cosine = outward_normal(mesh, line).normalized().dot(normal);
    if (cosine < 1.0 - normal_tolerance) {
      in_.fail(line.element->line,
               "physical group '{}' is not straight: line element {} is turned by {:.3g}° "
               "from the group's mean normal ({:.6g}, {:.6g}) (a boundary needs one outward "
               "normal)",
               name, line.element->tag,
               std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi, normal.x(),
               normal.y());
    }
    for (const Index node : {line.from, line.to}) {
      const Vec2& p = mesh.nodes[static_cast<std::size_t>(node)];
      const double offset = std::abs((p - origin).dot(normal));
      if (offset > straightness_tolerance * size) {
        in_.fail(line.element->line,
                 "physical group '{}' is not straight: node ({}, {}) of line element {} is "
                 "{:.3g} m off the group's line (a boundary needs one outward normal)",
                 name, p.x(), p.y(), line.element->tag, offset);
      }
    }
  }

  Scanner in_;
  ElementType type_;
  const MaterialTable& materials_;
  int version_ = 0;  ///< 41 or 22
  bool have_nodes_ = false;
  bool have_elements_ = false;
  std::map<DimTag, PhysicalName> physical_names_;
  std::map<DimTag, std::vector<int>> entity_physicals_;
  std::vector<RawNode> nodes_;
  std::unordered_map<std::int64_t, std::size_t> node_index_;  ///< tag → index in nodes_
  std::vector<RawElement> elements_;
};

}  // namespace

Mesh read_gmsh(const std::filesystem::path& path, ElementType type,
               const MaterialTable& materials) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error("{}: cannot open the Gmsh mesh file", path.string());
  std::ostringstream text;
  text << file.rdbuf();
  return GmshReader(path, std::move(text).str(), type, materials).read();
}

}  // namespace slide
