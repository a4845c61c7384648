// The case-file reader (case_file.hpp). toml++ parses; this file checks. Every table has
// one reader function, and they all go through `Section`: it knows the table's dotted
// path and where the table sits in the file, refuses keys it does not know, and reads
// typed values with their admissible ranges, so that every fault becomes one line
//   case.toml:12: fem.end_time = -1 is not admissible (expected > 0 s)
//
// Policy on keys that the chosen options do not use: keys that contradict the
// configuration are errors (the geometry keys of another mesh generator, strength
// parameters of a linear elastic material, failure-stage settings of a geostatic-only
// case); tuning keys of an option not selected are accepted and ignored (rbf_neighbours
// with "rbf", gravity_stage_* with "k0"), so that switching an option is a one-line edit.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include <toml++/toml.h>

#include "common/case_file.hpp"
#include "common/error.hpp"

namespace slide {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// ----------------------------------------------------------------------------- names

/// The spellings of the mesh generators (those of the solvers' algorithms are in
/// algorithms.hpp).
constexpr std::array<Named<MeshGenerator>, 3> generator_names{{
    {"profile", MeshGenerator::profile},
    {"blocks", MeshGenerator::blocks},
    {"gmsh", MeshGenerator::gmsh},
}};
/// Point counts of the symmetric triangle rules the transfer offers.
constexpr std::array<int, 8> triangle_rule_sizes{1, 3, 4, 6, 7, 12, 13, 16};

/// Boundary names of generated (profile, blocks) meshes and of the MPM grid.
const std::vector<std::string_view> generated_mesh_boundaries{"left", "right", "base"};
const std::vector<std::string_view> grid_boundaries{"left", "right", "base", "top"};

// ----------------------------------------------------------------------------- text

std::string join(const auto& items) {
  std::string text;
  for (const auto& item : items) {
    if (!text.empty()) text += ", ";
    text += fmt::format("{}", item);
  }
  return text;
}

std::string format_point(const Vec2& p) {
  return fmt::format("({}, {})", p.x(), p.y());
}

/// toml++'s messages may span lines; ours are one line.
std::string one_line(std::string_view text) {
  std::string line(text);
  std::replace(line.begin(), line.end(), '\n', ' ');
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line;
}

std::string_view describe(toml::node_type type) {
  switch (type) {
    case toml::node_type::none:
      return "nothing";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
  }
  return "an unknown value";
}

/// "file:line" when toml++ knows the line, else "file".
std::string locate(const std::string& file, const toml::source_region& region) {
  if (region.begin.line == 0) return file;
  return fmt::format("{}:{}", file, region.begin.line);
}

// ----------------------------------------------------------------------------- ranges

/// The admissible values of a number: an interval, open or closed at each end (NaN is
/// never admissible; ±infinity only where a closed infinite end says so), with the unit
/// and an optional reason for messages.
struct Range {
  double min = -infinity;
  bool min_closed = false;
  double max = infinity;
  bool max_closed = false;
  std::string_view unit = {};
  std::string note = {};

  bool contains(double v) const {
    return (min_closed ? v >= min : v > min) && (max_closed ? v <= max : v < max);
  }

  std::string expected() const {
    const std::string unit_text = unit.empty() ? "" : fmt::format(" {}", unit);
    std::string text;
    if (min == -infinity && max == infinity) {
      text = "a finite number";
    } else if (max == infinity) {
      text = fmt::format("{} {}{}", min_closed ? "≥" : ">", min, unit_text);
    } else if (min == -infinity) {
      text = fmt::format("{} {}{}", max_closed ? "≤" : "<", max, unit_text);
    } else {
      text = fmt::format("in {}{}, {}{}{}", min_closed ? '[' : '(', min, max,
                         max_closed ? ']' : ')', unit_text);
    }
    return note.empty() ? text : fmt::format("{}, {}", text, note);
  }
};

Range any_number() {
  return {};
}
Range positive(std::string_view unit = {}) {
  return {.min = 0.0, .unit = unit};
}
Range non_negative(std::string_view unit = {}) {
  return {.min = 0.0, .min_closed = true, .unit = unit};
}
/// [0, 1): damping coefficients.
Range unit_interval_open_above() {
  return {.min = 0.0, .min_closed = true, .max = 1.0, .max_closed = false};
}
/// (0, 1]: Courant numbers.
Range courant_range() {
  return {.min = 0.0, .max = 1.0, .max_closed = true};
}

// ----------------------------------------------------------------------------- values

/// Conversions of single nodes (table values or array items); `dotted` names the node
/// in messages, e.g. "mesh.surface[2][0]".
class NodeReader {
 public:
  explicit NodeReader(const std::string& file) : file_(&file) {}

  const std::string& file() const { return *file_; }

  std::string where(const toml::node& node) const { return locate(*file_, node.source()); }

  [[noreturn]] void fail(const toml::node& node, std::string_view dotted,
                         std::string_view problem) const {
    throw Error("{}: {}: {}", where(node), dotted, problem);
  }

  [[noreturn]] void wrong_type(const toml::node& node, std::string_view dotted,
                               std::string_view expected) const {
    fail(node, dotted, fmt::format("expected {}, found {}", expected, describe(node.type())));
  }

  [[noreturn]] void inadmissible(const toml::node& node, std::string_view dotted,
                                 std::string_view value, std::string_view expected) const {
    throw Error("{}: {} = {} is not admissible (expected {})", where(node), dotted, value,
                expected);
  }

  /// A number; TOML integers are accepted where a real number is expected.
  double number(const toml::node& node, std::string_view dotted, const Range& range) const {
    double value = 0.0;
    if (const auto* real = node.as_floating_point()) {
      value = real->get();
    } else if (const auto* integer = node.as_integer()) {
      value = static_cast<double>(integer->get());
    } else {
      wrong_type(node, dotted, "a number");
    }
    if (!range.contains(value))
      inadmissible(node, dotted, fmt::format("{}", value), range.expected());
    return value;
  }

  int integer(const toml::node& node, std::string_view dotted, int min, int max) const {
    const auto* value = node.as_integer();
    if (value == nullptr) wrong_type(node, dotted, "an integer");
    const std::int64_t v = value->get();
    if (v < min || v > max) {
      const std::string expected = max == std::numeric_limits<int>::max()
                                       ? fmt::format("an integer ≥ {}", min)
                                       : fmt::format("an integer in {}..{}", min, max);
      inadmissible(node, dotted, fmt::format("{}", v), expected);
    }
    return static_cast<int>(v);
  }

  std::string string(const toml::node& node, std::string_view dotted) const {
    const auto* value = node.as_string();
    if (value == nullptr) wrong_type(node, dotted, "a string");
    return value->get();
  }

  const toml::array& array(const toml::node& node, std::string_view dotted) const {
    const auto* value = node.as_array();
    if (value == nullptr) wrong_type(node, dotted, "an array");
    return *value;
  }

  /// A point [x, y], m.
  Vec2 point(const toml::node& node, std::string_view dotted) const {
    const auto& items = array(node, dotted);
    if (items.size() != 2) {
      fail(node, dotted, fmt::format("expected a point [x, y], found {} numbers", items.size()));
    }
    return {number(items[0], fmt::format("{}[0]", dotted), any_number()),
            number(items[1], fmt::format("{}[1]", dotted), any_number())};
  }

 private:
  const std::string* file_;
};

// ----------------------------------------------------------------------------- tables

/// One TOML table being read. On construction it refuses every key not in `keys` (a
/// table whose keys are names, like a boundary table, passes no list); its accessors
/// read required or optional values with their ranges.
class Section {
 public:
  using Keys = std::vector<std::string_view>;

  Section(const toml::table& table, std::string path, const NodeReader& reader,
          std::optional<Keys> keys)
      : table_(&table), path_(std::move(path)), reader_(reader) {
    if (!keys) return;
    for (const auto& [key, node] : table) {
      if (std::find(keys->begin(), keys->end(), key.str()) == keys->end()) {
        throw Error("{}: {}: unknown key (expected one of: {})",
                    locate(reader_.file(), key.source()), dotted(key.str()), join(*keys));
      }
    }
  }

  const toml::table& table() const { return *table_; }
  const NodeReader& reader() const { return reader_; }
  const std::string& path() const { return path_; }
  std::string dotted(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }
  bool has(std::string_view key) const { return table_->get(key) != nullptr; }

  /// "file:line" of the table (its header), or "file" for the document root.
  std::string where() const {
    return path_.empty() ? reader_.file() : locate(reader_.file(), table_->source());
  }
  /// "file:line" of the key's value if present, else of the table.
  std::string where(std::string_view key) const {
    const toml::node* node = table_->get(key);
    return node != nullptr ? reader_.where(*node) : where();
  }

  [[noreturn]] void fail(std::string_view key, std::string_view problem) const {
    throw Error("{}: {}: {}", where(key), dotted(key), problem);
  }
  [[noreturn]] void missing(std::string_view key) const {
    throw Error("{}: {}: missing required key", where(), dotted(key));
  }
  /// For a key that the configuration does not allow: an error if it is present.
  void reject(std::string_view key, std::string_view reason) const {
    if (has(key)) fail(key, reason);
  }

  const toml::node& node(std::string_view key) const {
    const toml::node* value = table_->get(key);
    if (value == nullptr) missing(key);
    return *value;
  }

  double number(std::string_view key, const Range& range) const {
    return reader_.number(node(key), dotted(key), range);
  }
  double number(std::string_view key, const Range& range, double fallback) const {
    return has(key) ? number(key, range) : fallback;
  }
  int integer(std::string_view key, int min, int max, int fallback) const {
    return has(key) ? reader_.integer(node(key), dotted(key), min, max) : fallback;
  }

  bool boolean(std::string_view key, bool fallback) const {
    if (!has(key)) return fallback;
    const auto* value = node(key).as_boolean();
    if (value == nullptr) reader_.wrong_type(node(key), dotted(key), "a boolean (true or false)");
    return value->get();
  }

  std::string string(std::string_view key) const { return reader_.string(node(key), dotted(key)); }
  std::string string(std::string_view key, std::string fallback) const {
    return has(key) ? string(key) : fallback;
  }

  /// One of the enumerators of `names`; `fallback` when absent (required if none).
  template <typename E, std::size_t N>
  E choice(std::string_view key, const std::array<Named<E>, N>& names,
           std::optional<E> fallback) const {
    if (!has(key)) {
      if (fallback) return *fallback;
      missing(key);
    }
    const std::string text = string(key);
    for (const auto& named : names) {
      if (named.name == text) return named.value;
    }
    std::vector<std::string_view> spelled;
    for (const auto& named : names) spelled.push_back(named.name);
    reader_.inadmissible(node(key), dotted(key), fmt::format("\"{}\"", text),
                         fmt::format("one of: {}", join(spelled)));
  }

  /// A list of numbers, each in `range`, optionally strictly increasing.
  std::vector<double> numbers(std::string_view key, const Range& range, bool increasing) const {
    std::vector<double> values;
    if (!has(key)) return values;
    const auto& items = reader_.array(node(key), dotted(key));
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::string item = fmt::format("{}[{}]", dotted(key), i);
      values.push_back(reader_.number(items[i], item, range));
      if (increasing && i > 0 && values[i] <= values[i - 1]) {
        reader_.fail(items[i], item,
                     fmt::format("{} does not follow {}: the list must increase strictly",
                                 values[i], values[i - 1]));
      }
    }
    return values;
  }

  /// A sub-table; `keys` as in the constructor.
  std::optional<Section> optional_table(std::string_view key, std::optional<Keys> keys) const {
    if (!has(key)) return std::nullopt;
    const auto* sub = node(key).as_table();
    if (sub == nullptr) reader_.wrong_type(node(key), dotted(key), "a table");
    return Section(*sub, dotted(key), reader_, std::move(keys));
  }
  Section table(std::string_view key, std::optional<Keys> keys) const {
    auto sub = optional_table(key, std::move(keys));
    if (!sub) throw Error("{}: {}: missing required table [{}]", where(), dotted(key), dotted(key));
    return *sub;
  }

  /// An array of tables ([[key]]), each read as a Section named "key[i]".
  std::vector<Section> tables(std::string_view key, const Keys& keys) const {
    const auto& items = reader_.array(node(key), dotted(key));
    std::vector<Section> sections;
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::string item = fmt::format("{}[{}]", dotted(key), i);
      const auto* sub = items[i].as_table();
      if (sub == nullptr) reader_.wrong_type(items[i], item, "a table");
      sections.emplace_back(*sub, item, reader_, keys);
    }
    return sections;
  }

 private:
  const toml::table* table_;
  std::string path_;
  NodeReader reader_;
};

/// Particles per element or cell: an integer n (n × n) or [nx, ny], each 1..10.
std::pair<int, int> read_particle_layout(const Section& s, std::string_view key, int fallback) {
  if (!s.has(key)) return {fallback, fallback};
  const auto& reader = s.reader();
  const toml::node& node = s.node(key);
  constexpr int most = 10;
  if (node.is_integer()) {
    const int n = reader.integer(node, s.dotted(key), 1, most);
    return {n, n};
  }
  if (!node.is_array()) reader.wrong_type(node, s.dotted(key), "an integer n or a pair [nx, ny]");
  const auto& items = *node.as_array();
  if (items.size() != 2) {
    reader.fail(node, s.dotted(key),
                fmt::format("expected [nx, ny], found {} items", items.size()));
  }
  return {reader.integer(items[0], fmt::format("{}[0]", s.dotted(key)), 1, most),
          reader.integer(items[1], fmt::format("{}[1]", s.dotted(key)), 1, most)};
}

/// A boundary table: name → condition. `names` restricts the names (empty: any name,
/// as for Gmsh physical groups). `friction_problem`, when not empty, is what is wrong
/// with a "friction" condition here (no coefficient given, or a stage without friction).
BoundaryTable read_boundaries(const Section& parent, std::string_view key,
                              const std::vector<std::string_view>& names,
                              std::string_view friction_problem) {
  const Section s = parent.table(key, names.empty() ? std::nullopt : std::optional(names));
  BoundaryTable boundaries;
  for (const auto& [name, node] : s.table()) {
    const std::string dotted = s.dotted(name.str());
    const std::string text = s.reader().string(node, dotted);
    const BoundaryCondition condition =
        parse_boundary_condition(text, fmt::format("{}: {}", s.reader().where(node), dotted));
    if (condition == BoundaryCondition::friction && !friction_problem.empty()) {
      s.fail(name.str(), fmt::format("\"friction\" {}", friction_problem));
    }
    boundaries.emplace(std::string(name.str()), condition);
  }
  return boundaries;
}

/// The problem of a friction boundary when the section gives no coefficient.
std::string friction_problem(const Section& s) {
  return s.has("friction_coefficient")
             ? std::string()
             : fmt::format("needs {}, which is missing", s.dotted("friction_coefficient"));
}

// ----------------------------------------------------------------------------- [case]

void read_case_table(const Section& root, const std::filesystem::path& file, Case& c) {
  const Section s = root.table("case", Section::Keys{"name", "description"});
  c.name = s.string("name");
  const bool well_formed =
      !c.name.empty() && std::all_of(c.name.begin(), c.name.end(), [](char ch) {
        return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '-';
      });
  if (!well_formed) {
    s.reader().inadmissible(s.node("name"), s.dotted("name"), fmt::format("\"{}\"", c.name),
                            "a non-empty name of a-z, 0-9 and -");
  }
  // Programs and Makefiles find a case by its folder: cases/<name>/case.toml.
  const auto absolute = std::filesystem::absolute(file).lexically_normal();
  const auto folder = absolute.parent_path();
  if (folder.parent_path().filename() == "cases" && folder.filename() != c.name) {
    s.fail("name", fmt::format("\"{}\" differs from the case's folder name \"{}\"", c.name,
                               folder.filename().string()));
  }
  c.description = s.string("description", "");
}

// ----------------------------------------------------------------------------- [[materials]]

/// Material::validate owns the admissible ranges; its message names `path` and the key
/// ("materials[0]: density = -1 is not admissible (...)"). Rewrite it in the case-file
/// form, at the line of the offending key.
void validate_material(const Material& material, const Section& s) {
  try {
    material.validate(s.path());
  } catch (const Error& error) {
    const std::string_view message = error.what();
    const std::string prefix = s.path() + ": ";
    if (!message.starts_with(prefix)) throw Error("{}: {}", s.where(), message);
    const std::string_view rest = message.substr(prefix.size());
    const std::string key(rest.substr(0, rest.find(' ')));
    throw Error("{}: {}.{}", s.where(key), s.path(), rest);
  }
}

MaterialModel read_model(const Section& s, std::string_view key) {
  return parse_material_model(s.string(key), fmt::format("{}: {}", s.where(key), s.dotted(key)));
}

Material read_material(const Section& s) {
  Material m;
  m.name = s.string("name");
  if (m.name.empty()) s.fail("name", "a material needs a non-empty name");
  // `model` serves both phases; `fem_model` and `mpm_model` name a phase's own model
  // (the reference workflow: pressure-independent multi-yield in FE, Mohr–Coulomb in MPM).
  if (s.has("model") && s.has("fem_model")) {
    s.fail("fem_model", "give either model (both phases) or fem_model, not both");
  }
  m.model = read_model(s, s.has("fem_model") ? "fem_model" : "model");
  if (s.has("mpm_model")) m.mpm_model = read_model(s, "mpm_model");
  // Only finiteness here: the ranges are Material::validate's.
  m.density = s.number("density", any_number());
  m.youngs_modulus = s.number("youngs_modulus", any_number());
  m.poisson_ratio = s.number("poisson_ratio", any_number());
  const bool mohr_coulomb = m.uses(MaterialModel::mohr_coulomb);
  const bool multi_yield = m.uses(MaterialModel::pressure_independent_multi_yield);
  if (!mohr_coulomb && !multi_yield) {
    for (std::string_view key :
         {"friction_angle", "cohesion", "dilation_angle", "tension_cutoff"}) {
      s.reject(key, "not used by model \"linear-elastic\" (remove it, or use \"mohr-coulomb\")");
    }
  } else {
    m.friction_angle = s.number("friction_angle", any_number());
    m.cohesion = s.number("cohesion", any_number());
  }
  if (mohr_coulomb) {
    m.dilation_angle = s.number("dilation_angle", any_number(), 0.0);
  } else if (multi_yield) {
    for (std::string_view key : {"dilation_angle", "tension_cutoff"}) {
      s.reject(key,
               "not used by model \"pressure-independent-multi-yield\" (no dilation, no tension "
               "cut-off)");
    }
  }
  // Read whatever the models: a user switching fem_model back and forth keeps them.
  m.peak_shear_strain = s.number("peak_shear_strain", any_number(), m.peak_shear_strain);
  m.yield_surfaces = s.integer("yield_surfaces", 1, max_yield_surfaces, m.yield_surfaces);
  // The default cut-off is the apex c·cot φ (infinite for φ = 0); +inf may be written.
  const Range cutoff{.min = -infinity, .max = infinity, .max_closed = true};
  m.tension_cutoff = s.number("tension_cutoff", cutoff, m.apex_stress());
  validate_material(m, s);
  return m;
}

MaterialTable read_materials(const Section& root) {
  if (!root.has("materials")) root.missing("materials");
  if (root.node("materials").is_table()) {
    root.fail("materials", "expected an array of tables ([[materials]]), found a table");
  }
  const Section::Keys keys{"name",          "model",          "fem_model",      "mpm_model",
                           "density",       "youngs_modulus", "poisson_ratio",  "friction_angle",
                           "cohesion",      "dilation_angle", "tension_cutoff", "peak_shear_strain",
                           "yield_surfaces"};
  MaterialTable materials;
  for (const Section& s : root.tables("materials", keys)) {
    Material material = read_material(s);
    for (const Material& other : materials) {
      if (other.name == material.name) {
        s.fail("name", fmt::format("\"{}\" is defined twice (material names must be unique)",
                                   material.name));
      }
    }
    materials.push_back(std::move(material));
  }
  if (materials.empty()) root.fail("materials", "at least one [[materials]] table is required");
  return materials;
}

/// A material reference: the name must be one of the case's materials.
std::string read_material_name(const Section& s, std::string_view key,
                               const MaterialTable& materials) {
  std::string name = s.string(key);
  const bool known = std::any_of(materials.begin(), materials.end(),
                                 [&](const Material& m) { return m.name == name; });
  if (!known) {
    std::vector<std::string_view> names;
    for (const Material& m : materials) names.push_back(m.name);
    s.fail(key, fmt::format("no material called \"{}\" (the case defines: {})", name, join(names)));
  }
  return name;
}

// ----------------------------------------------------------------------------- [mesh]

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

// ----------------------------------------------------------------------------- [fem]

/// [fem.damping]: Rayleigh damping either as α_M, β_K or as a ratio ξ at two frequencies
/// (then α_M, β_K are derived), never both; Cundall's local α with either.
DampingSpec read_damping(const Section& s) {
  DampingSpec damping;
  damping.local = s.number("local", unit_interval_open_above(), 0.0);
  if (!s.has("ratio")) {
    s.reject("frequencies", fmt::format("only used with {}", s.dotted("ratio")));
    damping.rayleigh_mass = s.number("rayleigh_mass", non_negative("1/s"), 0.0);
    damping.rayleigh_stiffness = s.number("rayleigh_stiffness", non_negative("s"), 0.0);
    return damping;
  }
  for (std::string_view key : {"rayleigh_mass", "rayleigh_stiffness"}) {
    if (s.has(key)) {
      throw Error(
          "{}: {} and {}: two forms of the Rayleigh damping (give either ratio and frequencies "
          "or rayleigh_mass and rayleigh_stiffness)",
          s.where(key), s.dotted("ratio"), s.dotted(key));
    }
  }
  DampingRatio ratio;
  ratio.ratio = s.number("ratio", unit_interval_open_above());
  if (!s.has("frequencies")) s.missing("frequencies");
  const std::vector<double> f = s.numbers("frequencies", positive("Hz"), true);
  if (f.size() != 2) {
    s.fail("frequencies", fmt::format("expected [f1, f2] in Hz, found {} numbers", f.size()));
  }
  ratio.frequencies = {f[0], f[1]};
  const RayleighCoefficients coefficients = rayleigh_coefficients(ratio);
  damping.rayleigh_mass = coefficients.mass;
  damping.rayleigh_stiffness = coefficients.stiffness;
  damping.ratio = ratio;
  return damping;
}

FemSpec read_fem(const Section& root, const MeshSpec& mesh) {
  const Section s =
      root.table("fem", Section::Keys{"failure_stage", "kinematics", "end_time", "checkpoint_times",
                                      "checkpoint_every", "output_every", "courant", "time_step",
                                      "hourglass_coefficient", "friction_coefficient",
                                      "speed_limit_factor", "damping", "geostatic", "failure"});
  FemSpec fem;
  fem.failure_stage = s.boolean("failure_stage", true);
  fem.kinematics =
      s.choice("kinematics", kinematics_names, std::optional(Kinematics::small_strain));
  if (fem.failure_stage) {
    fem.end_time = s.number("end_time", positive("s"));
  } else {
    for (std::string_view key : {"end_time", "checkpoint_times", "checkpoint_every", "failure"}) {
      s.reject(key, "only used when fem.failure_stage = true");
    }
  }
  const Range within_run{.min = 0.0,
                         .max = fem.end_time,
                         .max_closed = true,
                         .unit = "s",
                         .note = "within fem.end_time"};
  fem.checkpoint_times = s.numbers("checkpoint_times", within_run, true);
  fem.checkpoint_every = s.number("checkpoint_every", non_negative("s"), 0.0);
  fem.output_every = s.number("output_every", non_negative("s"), 0.0);
  fem.courant = s.number("courant", courant_range(), fem.courant);
  fem.time_step = s.number("time_step", non_negative("s"), 0.0);
  fem.hourglass_coefficient =
      s.number("hourglass_coefficient", non_negative(), fem.hourglass_coefficient);
  fem.friction_coefficient = s.number("friction_coefficient", non_negative(), 0.0);
  fem.speed_limit_factor = s.number("speed_limit_factor", positive(), fem.speed_limit_factor);
  if (auto damping = s.optional_table(
          "damping",
          Section::Keys{"rayleigh_mass", "rayleigh_stiffness", "ratio", "frequencies", "local"})) {
    fem.damping = read_damping(*damping);
  }

  // Generated meshes know left, right and base; Gmsh meshes name their own boundaries
  // (physical lines), checked against the mesh when it is read.
  const std::vector<std::string_view> names = mesh.generator == MeshGenerator::gmsh
                                                  ? std::vector<std::string_view>{}
                                                  : generated_mesh_boundaries;
  const Section geostatic = s.table("geostatic", Section::Keys{"boundaries"});
  fem.geostatic_boundaries = read_boundaries(
      geostatic, "boundaries", names,
      "is not admissible in the geostatic stage (a linear static solve: free, roller or fixed)");
  if (fem.failure_stage) {
    const Section failure = s.table("failure", Section::Keys{"boundaries"});
    fem.failure_boundaries = read_boundaries(failure, "boundaries", names, friction_problem(s));
  }
  return fem;
}

// ----------------------------------------------------------------------------- [transfer]

TransferSpec read_transfer(const Section& root, const FemSpec& fem) {
  TransferSpec transfer;
  const auto s = root.optional_table(
      "transfer",
      Section::Keys{"particles_per_element", "particles_per_triangle", "stress_interpolation",
                    "rbf_polynomial", "rbf_shape", "rbf_neighbours", "sweep_times", "main_time"});
  if (!s) return transfer;  // every key has a default
  std::tie(transfer.particles_x, transfer.particles_y) =
      read_particle_layout(*s, "particles_per_element", transfer.particles_x);
  if (s->has("particles_per_triangle")) {
    const int n = s->integer("particles_per_triangle", 1, std::numeric_limits<int>::max(),
                             transfer.particles_triangle);
    if (std::find(triangle_rule_sizes.begin(), triangle_rule_sizes.end(), n) ==
        triangle_rule_sizes.end()) {
      s->reader().inadmissible(s->node("particles_per_triangle"),
                               s->dotted("particles_per_triangle"), fmt::format("{}", n),
                               fmt::format("one of: {}", join(triangle_rule_sizes)));
    }
    transfer.particles_triangle = n;
  }
  transfer.stress_interpolation = s->choice("stress_interpolation", interpolation_names,
                                            std::optional(StressInterpolation::rbf));
  if (s->has("rbf_polynomial")) {
    transfer.rbf_polynomial =
        s->choice("rbf_polynomial", polynomial_names, std::optional<RbfPolynomial>());
  }
  transfer.rbf_shape = s->number("rbf_shape", non_negative("m"), 0.0);
  transfer.rbf_neighbours =
      s->integer("rbf_neighbours", 0, std::numeric_limits<int>::max(), transfer.rbf_neighbours);
  // A transfer needs an FE state: t_T lies within the FE run (t_T = 0: the geostatic
  // state).
  const Range fe_times{.min = 0.0,
                       .min_closed = true,
                       .max = fem.end_time,
                       .max_closed = true,
                       .unit = "s",
                       .note = "within fem.end_time"};
  transfer.sweep_times = s->numbers("sweep_times", fe_times, true);
  transfer.main_time = s->number("main_time", fe_times, 0.0);
  return transfer;
}

// ----------------------------------------------------------------------------- [mpm]

void read_domain(const Section& s, MpmSpec& mpm) {
  const NodeReader& reader = s.reader();
  const auto& corners = reader.array(s.node("domain"), s.dotted("domain"));
  if (corners.size() != 2) {
    s.fail("domain",
           fmt::format("expected [[xmin, ymin], [xmax, ymax]], found {} items", corners.size()));
  }
  mpm.domain_min = reader.point(corners[0], s.dotted("domain") + "[0]");
  mpm.domain_max = reader.point(corners[1], s.dotted("domain") + "[1]");
  if (!(mpm.domain_max.x() > mpm.domain_min.x() && mpm.domain_max.y() > mpm.domain_min.y())) {
    s.fail("domain", fmt::format("the upper-right corner {} must lie above and right of the "
                                 "lower-left corner {}",
                                 format_point(mpm.domain_max), format_point(mpm.domain_min)));
  }
}

void check_cells(const Section& s, const MpmSpec& mpm) {
  const Vec2 extent = mpm.domain_max - mpm.domain_min;
  for (int axis = 0; axis < 2; ++axis) {
    const double cells = extent[axis] / mpm.cell_size;
    if (std::abs(cells - std::round(cells)) > 1e-9 * cells || std::round(cells) < 1.0) {
      s.fail("cell_size",
             fmt::format("{} m does not divide the domain into whole cells ({}: {} m / {} m = "
                         "{:.6g} cells)",
                         mpm.cell_size, axis == 0 ? "x" : "y", extent[axis], mpm.cell_size, cells));
    }
  }
}

MpmSpec read_mpm(const Section& root, const MaterialTable& materials, const MeshSpec& mesh,
                 const TransferSpec& transfer) {
  const Section s = root.table("mpm", Section::Keys{"domain",
                                                    "cell_size",
                                                    "shape_function",
                                                    "update_scheme",
                                                    "velocity_transfer",
                                                    "pic_fraction",
                                                    "volumetric_smoothing",
                                                    "end_time",
                                                    "checkpoint_times",
                                                    "checkpoint_every",
                                                    "output_every",
                                                    "courant",
                                                    "time_step",
                                                    "boundaries",
                                                    "friction_coefficient",
                                                    "local_damping",
                                                    "particle_exit",
                                                    "rest_threshold",
                                                    "rest_duration",
                                                    "speed_limit_factor",
                                                    "particles_per_cell",
                                                    "initial_stress",
                                                    "gravity_stage_duration",
                                                    "gravity_stage_damping"});
  MpmSpec mpm;
  read_domain(s, mpm);
  mpm.cell_size = s.number("cell_size", positive("m"));
  check_cells(s, mpm);
  if (const auto box = body_box(mesh)) {
    const bool inside = (box->first.array() >= mpm.domain_min.array()).all() &&
                        (box->second.array() <= mpm.domain_max.array()).all();
    if (!inside) {
      s.fail("domain", fmt::format("the grid {}–{} does not contain the initial body {}–{}",
                                   format_point(mpm.domain_min), format_point(mpm.domain_max),
                                   format_point(box->first), format_point(box->second)));
    }
  }
  mpm.shape_function =
      s.choice("shape_function", shape_function_names, std::optional(ShapeFunction::gimp));
  mpm.update_scheme =
      s.choice("update_scheme", update_scheme_names, std::optional(UpdateScheme::musl));
  mpm.velocity_transfer = s.choice("velocity_transfer", velocity_transfer_names,
                                   std::optional(VelocityTransfer::flip_pic));
  // pic_fraction is the tuning key of flip-pic: accepted and ignored with apic (the
  // policy at the top of this file), so a case switches transfer with one line.
  mpm.pic_fraction = s.number(
      "pic_fraction", Range{.min = 0.0, .min_closed = true, .max = 1.0, .max_closed = true}, 0.0);
  // On by default where it matters: plastic flow (ψ = 0 is isochoric) locks and
  // checkerboards; an elastic body does not need it (mpm/README.md, "Volumetric smoothing").
  const bool plastic = std::any_of(materials.begin(), materials.end(), [](const Material& m) {
    return m.model_of(Phase::mpm) != MaterialModel::linear_elastic;
  });
  mpm.volumetric_smoothing =
      s.choice("volumetric_smoothing", volumetric_smoothing_names,
               std::optional(plastic ? VolumetricSmoothing::cell : VolumetricSmoothing::none));
  // The MPM phase continues the clock from t_T: it must end after every transfer time.
  double latest_transfer = transfer.main_time;
  for (double t : transfer.sweep_times) latest_transfer = std::max(latest_transfer, t);
  mpm.end_time = s.number(
      "end_time", Range{.min = latest_transfer,
                        .unit = "s",
                        .note = latest_transfer > 0.0 ? "after the latest transfer time" : ""});
  const Range within_run{.min = 0.0,
                         .max = mpm.end_time,
                         .max_closed = true,
                         .unit = "s",
                         .note = "within mpm.end_time"};
  mpm.checkpoint_times = s.numbers("checkpoint_times", within_run, true);
  mpm.checkpoint_every = s.number("checkpoint_every", non_negative("s"), 0.0);
  mpm.output_every = s.number("output_every", non_negative("s"), 0.0);
  mpm.courant = s.number("courant", courant_range(), mpm.courant);
  mpm.time_step = s.number("time_step", non_negative("s"), 0.0);
  mpm.friction_coefficient = s.number("friction_coefficient", non_negative(), 0.0);
  mpm.boundaries = read_boundaries(s, "boundaries", grid_boundaries, friction_problem(s));
  mpm.local_damping = s.number("local_damping", unit_interval_open_above(), 0.0);
  mpm.particle_exit =
      s.choice("particle_exit", particle_exit_names, std::optional(ParticleExit::freeze));
  mpm.rest_threshold = s.number("rest_threshold", non_negative(), 0.0);
  mpm.rest_duration = s.number("rest_duration", non_negative("s"), 0.0);
  mpm.speed_limit_factor = s.number("speed_limit_factor", positive(), mpm.speed_limit_factor);
  std::tie(mpm.particles_x, mpm.particles_y) =
      read_particle_layout(s, "particles_per_cell", mpm.particles_x);
  mpm.initial_stress =
      s.choice("initial_stress", initial_stress_names, std::optional(InitialStress::k0));
  if (mpm.initial_stress == InitialStress::gravity) {
    mpm.gravity_stage_duration = s.number(
        "gravity_stage_duration",
        Range{.min = 0.0, .unit = "s", .note = "required by initial_stress = \"gravity\""});
  } else {
    mpm.gravity_stage_duration = s.number("gravity_stage_duration", non_negative("s"), 0.0);
  }
  mpm.gravity_stage_damping = s.number("gravity_stage_damping", unit_interval_open_above(), 0.0);
  return mpm;
}

// ----------------------------------------------------------------------------- [metrics]

MetricsSpec read_metrics(const Section& root) {
  const Section s =
      root.table("metrics", Section::Keys{"initial_length", "initial_height", "bin_width",
                                          "profile_percentile", "foundation_level"});
  MetricsSpec metrics;
  metrics.initial_length = s.number("initial_length", positive("m"));
  metrics.initial_height = s.number("initial_height", positive("m"));
  metrics.bin_width = s.number("bin_width", positive("m"), metrics.bin_width);
  metrics.profile_percentile =
      s.number("profile_percentile", Range{.min = 0.0, .max = 100.0, .max_closed = true},
               metrics.profile_percentile);
  metrics.foundation_level = s.number("foundation_level", non_negative("m"), 0.0);
  return metrics;
}

}  // namespace

// ----------------------------------------------------------------------------- API

RayleighCoefficients rayleigh_coefficients(const DampingRatio& ratio) {
  // ξ(ω) = α_M/(2ω) + β_K ω/2 = ξ at ω1 and ω2: two linear equations in α_M, β_K.
  const double omega1 = 2.0 * std::numbers::pi * ratio.frequencies[0];
  const double omega2 = 2.0 * std::numbers::pi * ratio.frequencies[1];
  return {.mass = 2.0 * ratio.ratio * omega1 * omega2 / (omega1 + omega2),
          .stiffness = 2.0 * ratio.ratio / (omega1 + omega2)};
}

std::int32_t Case::material_index(std::string_view material_name) const {
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == material_name) return static_cast<std::int32_t>(i);
  }
  throw Error("{}: no material called \"{}\"", file.string(), material_name);
}

Case parse_case(std::string_view text, const std::filesystem::path& source_name) {
  const std::string file = source_name.string();
  toml::table document;
  try {
    document = toml::parse(text);
  } catch (const toml::parse_error& error) {
    throw Error("{}: TOML syntax error: {}", locate(file, error.source()),
                one_line(error.description()));
  }
  const NodeReader reader(file);
  const Section root(
      document, "", reader,
      Section::Keys{"case", "materials", "mesh", "fem", "transfer", "mpm", "metrics"});
  Case c;
  c.file = source_name;
  read_case_table(root, source_name, c);
  c.materials = read_materials(root);
  c.mesh = read_mesh(root, c.materials, source_name.parent_path());
  c.fem = read_fem(root, c.mesh);
  c.transfer = read_transfer(root, c.fem);
  c.mpm = read_mpm(root, c.materials, c.mesh, c.transfer);
  c.metrics = read_metrics(root);
  return c;
}

Case load_case(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error("{}: is a folder; expected a case file (e.g. {})", path.string(),
                (path / "case.toml").string());
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("{}: cannot open the case file", path.string());
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error("{}: cannot read the case file", path.string());
  return parse_case(text.str(), path);
}

}  // namespace slide
