// OpenSees JSON models and recorder files, see opensees_reader.hpp.
#include "common/io/opensees_reader.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/base/error.hpp"
#include "common/geometry/element.hpp"

namespace slide {
namespace {

using Json = nlohmann::json;

constexpr std::array<std::pair<std::string_view, ElementType>, 4> element_classes{{
    {"FourNodeQuad", ElementType::quad4_2x2},
    {"SSPquad", ElementType::quad4_1gp},
    {"SSPquadUP", ElementType::quad4_1gp},
    {"Tri31", ElementType::tri3},
}};

/// A node on an edge of the bounding box lies within this fraction of the box's size of
/// it (the JSON print has six significant digits).
constexpr double edge_tolerance = 1e-6;

std::string read_text(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error("{}: no such file", path.string());
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw Error("{}: cannot read the file", path.string());
  return text.str();
}

std::size_t line_of(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
}

/// The end (one past the closing brace) of the JSON object that starts at `open`, found
/// by counting braces outside strings; npos when it does not close.
std::size_t object_end(std::string_view text, std::size_t open) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = open; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"')
      in_string = true;
    else if (c == '{')
      ++depth;
    else if (c == '}' && --depth == 0)
      return i + 1;
  }
  return std::string_view::npos;
}

/// nlohmann's message without its "[json.exception.…] " prefix and parse position.
std::string reason(const Json::exception& error) {
  std::string what = error.what();
  if (const std::size_t colon_at = what.rfind(": "); colon_at != std::string::npos) {
    what = what.substr(colon_at + 2);
  } else if (const std::size_t bracket = what.find("] "); bracket != std::string::npos) {
    what = what.substr(bracket + 2);
  }
  return what;
}

/// The "geometry" object of an OpenSees JSON print, parsed on its own (the rest of the
/// document may be invalid JSON, see the header).
Json parse_geometry(const std::filesystem::path& path) {
  const std::string text = read_text(path);
  const std::string where = path.string();
  const std::size_t key = text.find("\"geometry\"");
  if (key == std::string::npos) {
    throw Error("{}: no \"geometry\" object: not a model printed by OpenSees's print -JSON", where);
  }
  const std::size_t open = text.find('{', key);
  const std::size_t colon = text.find(':', key);
  if (open == std::string::npos || colon == std::string::npos || colon > open ||
      text.find_first_not_of(" \t\r\n", colon + 1) != open) {
    throw Error("{}:{}: \"geometry\" is not followed by an object", where, line_of(text, key));
  }
  const std::size_t end = object_end(text, open);
  if (end == std::string_view::npos) {
    throw Error("{}:{}: the \"geometry\" object does not close (truncated file?)", where,
                line_of(text, open));
  }
  try {
    return Json::parse(text.begin() + static_cast<std::ptrdiff_t>(open),
                       text.begin() + static_cast<std::ptrdiff_t>(end));
  } catch (const Json::parse_error& error) {
    // error.byte counts from the start of the parsed range, 1-based.
    const std::size_t at = open + (error.byte > 0 ? error.byte - 1 : 0);
    throw Error("{}:{}: invalid JSON in \"geometry\" ({})", where, line_of(text, at),
                reason(error));
  } catch (const Json::exception& error) {  // e.g. a number beyond the range of a double
    throw Error("{}: invalid JSON in \"geometry\" ({})", where, reason(error));
  }
}

/// Field readers that name the item and field at fault.
class Item {
 public:
  Item(const Json& json, std::string where) : json_(json), where_(std::move(where)) {
    if (!json_.is_object()) throw Error("{}: expected an object", where_);
  }
  const Json& field(std::string_view name) const {
    const auto it = json_.find(name);
    if (it == json_.end()) throw Error("{}: field \"{}\" missing", where_, name);
    return *it;
  }
  bool has(std::string_view name) const { return json_.contains(name); }
  std::int64_t integer(std::string_view name) const { return as_integer(field(name), name); }
  std::int64_t as_integer(const Json& value, std::string_view name) const {
    if (value.is_number_integer()) return value.get<std::int64_t>();
    // OpenSees prints material tags as strings ("material": "1").
    if (value.is_string()) {
      const std::string& s = value.get_ref<const std::string&>();
      std::int64_t n = 0;
      const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
      if (ec == std::errc() && end == s.data() + s.size()) return n;
    }
    throw Error("{}: \"{}\" is {}, expected an integer tag", where_, name, value.dump());
  }
  std::string string(std::string_view name) const {
    const Json& value = field(name);
    if (!value.is_string())
      throw Error("{}: \"{}\" is {}, expected a string", where_, name, value.dump());
    return value.get<std::string>();
  }
  const Json& array(std::string_view name) const {
    const Json& value = field(name);
    if (!value.is_array())
      throw Error("{}: \"{}\" is {}, expected an array", where_, name, value.dump());
    return value;
  }
  const std::string& where() const { return where_; }

 private:
  const Json& json_;
  std::string where_;
};

struct JsonNode {
  std::int64_t tag = 0;
  int ndf = 2;
  Vec2 x = Vec2::Zero();
};

struct JsonElement {
  std::int64_t tag = 0;
  std::string type;
  std::vector<std::int64_t> nodes;
  std::string material;
};

struct JsonModel {
  std::vector<JsonNode> nodes;        ///< increasing tag
  std::vector<JsonElement> elements;  ///< increasing tag, every class
};

JsonNode read_node(const Json& json, std::size_t position, const std::string& file) {
  const Item item(json, fmt::format("{}: geometry.nodes[{}]", file, position));
  JsonNode node;
  node.tag = item.integer("name");
  const Item tagged(json, fmt::format("{}: node {}", file, node.tag));
  const std::int64_t ndf = tagged.has("ndf") ? tagged.integer("ndf") : 2;
  if (ndf < 2 || ndf > 3) {
    throw Error(
        "{}: ndf = {}, expected 2 (displacements) or 3 (u–p: displacements and pore "
        "pressure)",
        tagged.where(), ndf);
  }
  node.ndf = static_cast<int>(ndf);
  const Json& crd = tagged.array("crd");
  if (crd.size() != 2) {
    throw Error("{} has {} coordinates, expected 2 (a 2D model: model BasicBuilder -ndm 2)",
                tagged.where(), crd.size());
  }
  for (int k = 0; k < 2; ++k) {
    const Json& c = crd[static_cast<std::size_t>(k)];
    if (!c.is_number() || !std::isfinite(c.get<double>())) {
      throw Error("{}: coordinate {} is {}, expected a finite number", tagged.where(), k + 1,
                  c.dump());
    }
    node.x[k] = c.get<double>();
  }
  return node;
}

/// An element; the nodes and material only of the classes the import reads (the others
/// are judged against mesh.ignore_elements later).
JsonElement read_element(const Json& json, std::size_t position, const std::string& file) {
  const Item item(json, fmt::format("{}: geometry.elements[{}]", file, position));
  JsonElement element;
  element.tag = item.integer("name");
  const Item tagged(json, fmt::format("{}: element {}", file, element.tag));
  element.type = tagged.string("type");
  if (!opensees_element_type(element.type)) return element;
  for (const Json& n : tagged.array("nodes"))
    element.nodes.push_back(tagged.as_integer(n, "nodes"));
  element.material = std::to_string(tagged.integer("material"));
  return element;
}

JsonModel read_json_model(const std::filesystem::path& path) {
  const Json geometry = parse_geometry(path);
  const std::string file = path.string();
  const Item root(geometry, file + ": geometry");
  JsonModel model;
  const Json& nodes = root.array("nodes");
  for (std::size_t i = 0; i < nodes.size(); ++i)
    model.nodes.push_back(read_node(nodes[i], i, file));
  const Json& elements = root.array("elements");
  for (std::size_t i = 0; i < elements.size(); ++i) {
    model.elements.push_back(read_element(elements[i], i, file));
  }
  const auto by_tag = [](const auto& a, const auto& b) { return a.tag < b.tag; };
  std::sort(model.nodes.begin(), model.nodes.end(), by_tag);
  std::sort(model.elements.begin(), model.elements.end(), by_tag);
  for (std::size_t i = 1; i < model.nodes.size(); ++i) {
    if (model.nodes[i].tag == model.nodes[i - 1].tag) {
      throw Error("{}: node tag {} appears twice", file, model.nodes[i].tag);
    }
  }
  for (std::size_t i = 1; i < model.elements.size(); ++i) {
    if (model.elements[i].tag == model.elements[i - 1].tag) {
      throw Error("{}: element tag {} appears twice", file, model.elements[i].tag);
    }
  }
  return model;
}

bool ignored(const std::vector<std::string>& ignore_elements, std::string_view type) {
  return std::find(ignore_elements.begin(), ignore_elements.end(), type) != ignore_elements.end();
}

std::string known_classes() {
  std::string names;
  for (const auto& [name, type] : element_classes)
    names += (names.empty() ? "" : ", ") + std::string(name);
  return names;
}

/// The class of the model's continuum elements; Error on an unknown class (not ignored),
/// on two classes, or on none.
std::string continuum_class(const JsonModel& model, const std::vector<std::string>& ignore_elements,
                            const std::string& file) {
  std::string found;
  std::int64_t first_tag = 0;
  for (const JsonElement& e : model.elements) {
    if (ignored(ignore_elements, e.type)) continue;
    if (!opensees_element_type(e.type)) {
      throw Error(
          "{}: element {} is a {}, which the import does not read (it reads {}; list "
          "other classes in mesh.ignore_elements to skip them)",
          file, e.tag, e.type, known_classes());
    }
    if (found.empty()) {
      found = e.type;
      first_tag = e.tag;
    } else if (e.type != found) {
      throw Error(
          "{}: element {} is a {} and element {} a {}: the import reads one element "
          "class per model",
          file, first_tag, found, e.tag, e.type);
    }
  }
  if (found.empty()) throw Error("{}: no element the import reads ({})", file, known_classes());
  return found;
}

void add_bounding_box_sets(Mesh& mesh) {
  Vec2 lo = mesh.nodes.front();
  Vec2 hi = lo;
  for (const Vec2& x : mesh.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double tolerance = edge_tolerance * std::max((hi - lo).maxCoeff(), 1e-300);
  NodeSet left{"left", {}, Vec2(-1.0, 0.0)};
  NodeSet right{"right", {}, Vec2(1.0, 0.0)};
  NodeSet base{"base", {}, Vec2(0.0, -1.0)};
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    const Vec2& x = mesh.nodes[n];
    const auto index = static_cast<Index>(n);
    if (x.x() <= lo.x() + tolerance) left.nodes.push_back(index);
    if (x.x() >= hi.x() - tolerance) right.nodes.push_back(index);
    if (x.y() <= lo.y() + tolerance) base.nodes.push_back(index);
  }
  mesh.node_sets = {std::move(left), std::move(right), std::move(base)};
}

/// The mesh checks' straightness of a node set, as validate_mesh applies it
/// (common/geometry/mesh.cpp): this share of the mesh's extent, at least 1 m.
constexpr double straightness_tolerance = 1e-6;

/// "20 30 60 50": the OpenSees tags of element e's nodes.
std::string node_tags_of(const OpenSeesMesh& model, Index e) {
  std::string tags;
  for (const Index node : model.mesh.element(e)) {
    if (!tags.empty()) tags += ' ';
    tags += std::to_string(model.node_tags[static_cast<std::size_t>(node)]);
  }
  return tags;
}

/// No element inverted or of zero area, by the test of validate_mesh (common/geometry/
/// mesh.cpp), which would otherwise name the element and node by their 0-based index in
/// the mesh: here they are named by their OpenSees tags.
void check_element_shapes(const OpenSeesMesh& model, const std::string& file) {
  const Mesh& mesh = model.mesh;
  const ElementShape shape = mesh.shape();
  const auto corners = reference_corners(shape);
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x = mesh.element_nodes(e, mesh.nodes);
    const double zero = degenerate_jacobian_fraction * longest_edge_squared(shape, x);
    const std::int64_t tag = model.element_tags[static_cast<std::size_t>(e)];
    if (shape == ElementShape::tri3) {
      const double area = element_area(shape, x);
      if (area <= zero) {
        throw Error(
            "{}: element {} (nodes {}) is inverted or has zero area (signed area {} m²): "
            "expected its nodes counter-clockwise",
            file, tag, node_tags_of(model, e), area);
      }
      continue;
    }
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const double det = jacobian(shape, x, corners[k]).determinant();
      if (det <= 0.25 * zero) {
        const Index node = mesh.element(e)[k];
        throw Error(
            "{}: element {} (nodes {}) is inverted or has zero area: det J = {} at its node {}; "
            "expected its nodes counter-clockwise",
            file, tag, node_tags_of(model, e), det,
            model.node_tags[static_cast<std::size_t>(node)]);
      }
    }
  }
}

/// The bounding box's edges straight, by the test of validate_mesh (the box's tolerance
/// can exceed it when the model spans the origin), the nodes named by their tags.
void check_edges_straight(const OpenSeesMesh& model, const std::string& file) {
  const Mesh& mesh = model.mesh;
  double extent = 0.0;
  for (const Vec2& p : mesh.nodes) extent = std::max(extent, p.cwiseAbs().maxCoeff());
  const double straightness = straightness_tolerance * std::max(extent, 1.0);
  for (const NodeSet& set : mesh.node_sets) {
    const auto first = static_cast<std::size_t>(set.nodes.front());
    for (const Index n : set.nodes) {
      const auto node = static_cast<std::size_t>(n);
      const double off = std::abs((mesh.nodes[node] - mesh.nodes[first]).dot(set.normal));
      if (off > straightness) {
        throw Error(
            "{}: the {} edge of the model is not straight: node {} at ({}, {}) is {:.3g} m off "
            "the line through node {} (expected at most {:.3g} m)",
            file, set.name, model.node_tags[node], mesh.nodes[node].x(), mesh.nodes[node].y(), off,
            model.node_tags[first], straightness);
      }
    }
  }
}

/// Parses a number of a recorder row; OpenSees writes "nan", "-nan", "inf" for bad
/// values, which from_chars reads and the caller refuses.
std::optional<double> parse_number(std::string_view token) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size()) {
    // "-nan" is not from_chars syntax.
    if (token == "-nan" || token == "-NaN") return std::numeric_limits<double>::quiet_NaN();
    return std::nullopt;
  }
  return value;
}

/// The first white-space separated token of `line` at or after `from`, and where it ends.
std::pair<std::string_view, std::size_t> next_token(std::string_view line, std::size_t from) {
  const std::size_t begin = line.find_first_not_of(" \t\r,", from);
  if (begin == std::string_view::npos) return {{}, line.size()};
  std::size_t end = line.find_first_of(" \t\r,", begin);
  if (end == std::string_view::npos) end = line.size();
  return {line.substr(begin, end - begin), end};
}

}  // namespace

std::optional<ElementType> opensees_element_type(std::string_view element_class) {
  for (const auto& [name, type] : element_classes) {
    if (name == element_class) return type;
  }
  return std::nullopt;
}

ElementType read_opensees_element_type(const std::filesystem::path& path,
                                       const std::vector<std::string>& ignore_elements) {
  const JsonModel model = read_json_model(path);
  return *opensees_element_type(continuum_class(model, ignore_elements, path.string()));
}

OpenSeesMesh read_opensees_mesh(const std::filesystem::path& path,
                                const std::map<std::string, std::string>& material_of_tag,
                                const std::vector<std::string>& ignore_elements,
                                const MaterialTable& materials) {
  const std::string file = path.string();
  const JsonModel model = read_json_model(path);
  OpenSeesMesh result;
  result.element_class = continuum_class(model, ignore_elements, file);
  Mesh& mesh = result.mesh;
  mesh.element_type = *opensees_element_type(result.element_class);
  const auto k = static_cast<std::size_t>(mesh.nodes_per_element());

  std::unordered_map<std::int64_t, std::size_t> json_index;  // tag → position in model.nodes
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    json_index.emplace(model.nodes[i].tag, i);
    result.all_node_tags.push_back(model.nodes[i].tag);
  }
  std::vector<std::uint8_t> used(model.nodes.size(), 0);
  for (const JsonElement& e : model.elements) {
    if (e.type != result.element_class) {
      ++result.ignored[e.type];
      continue;
    }
    if (e.nodes.size() != k) {
      throw Error("{}: element {} ({}) has {} nodes, expected {}", file, e.tag, e.type,
                  e.nodes.size(), k);
    }
    for (const std::int64_t tag : e.nodes) {
      const auto it = json_index.find(tag);
      if (it == json_index.end()) {
        throw Error("{}: element {} uses node {}, which the model does not have", file, e.tag, tag);
      }
      used[it->second] = 1;
    }
  }
  // Mesh nodes: the used ones, in increasing tag order.
  std::vector<Index> mesh_index(model.nodes.size(), -1);
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    if (!used[i]) continue;
    mesh_index[i] = static_cast<Index>(mesh.nodes.size());
    mesh.nodes.push_back(model.nodes[i].x);
    result.node_tags.push_back(model.nodes[i].tag);
    result.node_dofs.push_back(model.nodes[i].ndf);
  }
  for (const JsonElement& e : model.elements) {
    if (e.type != result.element_class) continue;
    const auto material = material_of_tag.find(e.material);
    if (material == material_of_tag.end()) {
      throw Error(
          "{}: element {} has material {}, which mesh.materials does not map to a "
          "material of the case",
          file, e.tag, e.material);
    }
    const auto id = std::find_if(materials.begin(), materials.end(),
                                 [&](const Material& m) { return m.name == material->second; });
    if (id == materials.end()) {
      throw Error(
          "{}: mesh.materials maps OpenSees material {} to '{}', which is not a material "
          "of the case",
          file, e.material, material->second);
    }
    mesh.material_id.push_back(static_cast<std::int32_t>(id - materials.begin()));
    for (const std::int64_t tag : e.nodes) mesh.connectivity.push_back(mesh_index[json_index[tag]]);
    result.element_tags.push_back(e.tag);
  }
  add_bounding_box_sets(mesh);
  check_element_shapes(result, file);
  check_edges_straight(result, file);
  return result;
}

RecorderRow read_recorder_row(const std::filesystem::path& path, double time, std::size_t columns,
                              std::string_view layout, RepeatedTime repeated) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error("{}: no such file", file);
  std::ifstream in(path);
  if (!in) throw Error("{}: cannot open the file", file);
  const double tolerance = std::max(recorder_time_tolerance * std::abs(time), 1e-9);

  std::string line;
  std::string chosen;
  std::size_t chosen_line = 0;
  double chosen_time = 0.0;
  double first_time = std::numeric_limits<double>::quiet_NaN();
  double last_time = first_time;
  std::size_t rows = 0;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const auto [token, end] = next_token(line, 0);
    if (token.empty()) continue;  // a blank line (e.g. the end of the file)
    const std::optional<double> t = parse_number(token);
    if (!t || !std::isfinite(*t)) {
      throw Error("{}:{}: the time column reads '{}', expected a number (record with -time)", file,
                  number, token);
    }
    if (rows++ == 0) first_time = *t;
    last_time = *t;
    const bool take = repeated == RepeatedTime::last || chosen_line == 0;
    if (std::abs(*t - time) <= tolerance && take) {
      chosen = line;
      chosen_line = number;
      chosen_time = *t;
    }
  }
  if (in.bad()) throw Error("{}: cannot read the file", file);
  if (rows == 0) throw Error("{}: no rows (the recorder wrote nothing)", file);
  if (chosen_line == 0) {
    throw Error("{}: no row at t = {} s (the rows run from t = {} to {} s, {} rows)", file, time,
                first_time, last_time, rows);
  }
  RecorderRow row;
  row.time = chosen_time;
  row.line = chosen_line;
  if (columns != any_columns) row.values.reserve(columns);
  std::size_t at = next_token(chosen, 0).second;
  for (;;) {
    const auto [token, end] = next_token(chosen, at);
    if (token.empty()) break;
    at = end;
    const std::optional<double> value = parse_number(token);
    if (!value) {
      throw Error("{}:{}: column {} reads '{}', expected a number", file, chosen_line,
                  row.values.size() + 2, token);
    }
    if (!std::isfinite(*value)) {
      throw Error("{}:{}: column {} is not finite ({}): the OpenSees analysis diverged there?",
                  file, chosen_line, row.values.size() + 2, token);
    }
    row.values.push_back(*value);
  }
  if (columns != any_columns && row.values.size() != columns) {
    throw Error("{}:{}: the row at t = {} s has {} values after the time, expected {} ({})", file,
                chosen_line, chosen_time, row.values.size(), columns, layout);
  }
  return row;
}

}  // namespace slide
