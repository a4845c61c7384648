// The case reader's own toolkit, shared by the section readers case_file_<section>.cpp
// and private to them (not installed with case_file.hpp): `Section`, the typed and
// ranged access to one TOML table that turns every fault into one line
//   case.toml:12: fem.end_time = -1 is not admissible (expected > 0 s)
// the readers of values several sections share, and the section readers themselves.
#pragma once

#include <algorithm>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/base/error.hpp"
#include "common/base/numeric.hpp"
#include "common/physics/material.hpp"
#include "common/settings/fem_spec.hpp"
#include "common/settings/mesh_spec.hpp"
#include "common/settings/metrics_spec.hpp"
#include "common/settings/mpm_spec.hpp"
#include "common/settings/transfer_spec.hpp"

namespace slide::case_reader {

inline constexpr double infinity = std::numeric_limits<double>::infinity();

/// Boundary names of generated (profile, blocks) meshes and of the MPM grid.
inline const std::vector<std::string_view> generated_mesh_boundaries{"left", "right", "base"};
inline const std::vector<std::string_view> grid_boundaries{"left", "right", "base", "top"};

// ----------------------------------------------------------------------------- text

std::string join(const auto& items) {
  std::string text;
  for (const auto& item : items) {
    if (!text.empty()) text += ", ";
    text += fmt::format("{}", item);
  }
  return text;
}

std::string format_point(const Vec2& p);
/// toml++'s messages may span lines; ours are one line.
std::string one_line(std::string_view text);
/// "a string", "an integer", …: what a value is, for messages.
std::string_view describe(toml::node_type type);
/// "file:line" when toml++ knows the line, else "file".
std::string locate(const std::string& file, const toml::source_region& region);

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

inline Range any_number() {
  return {};
}
inline Range positive(std::string_view unit = {}) {
  return {.min = 0.0, .unit = unit};
}
inline Range non_negative(std::string_view unit = {}) {
  return {.min = 0.0, .min_closed = true, .unit = unit};
}
/// [0, 1): damping coefficients.
inline Range unit_interval_open_above() {
  return {.min = 0.0, .min_closed = true, .max = 1.0, .max_closed = false};
}
/// (0, 1]: Courant numbers.
inline Range courant_range() {
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

// ----------------------------------------------------------------------------- shared values

/// Particles per element or cell: an integer n (n × n) or [nx, ny], each 1..10.
std::pair<int, int> read_particle_layout(const Section& s, std::string_view key, int fallback);

/// A boundary table: name → condition. `names` restricts the names (empty: any name,
/// as for Gmsh physical groups). `friction_problem`, when not empty, is what is wrong
/// with a "friction" condition here (no coefficient given, or a stage without friction).
BoundaryTable read_boundaries(const Section& parent, std::string_view key,
                              const std::vector<std::string_view>& names,
                              std::string_view friction_problem);

/// The problem of a friction boundary when the section gives no coefficient.
std::string friction_problem(const Section& s);

/// A recorder's `name` (it names OUT/recorders/<name>.csv): letters, digits, - and _, not
/// one of `taken` (the names of the stage's recorders before it).
std::string read_recorder_name(const Section& r, const std::vector<std::string>& taken);

/// A non-empty list of [x, y] points under `key`.
std::vector<Vec2> read_points(const Section& s, std::string_view key);

/// A material reference: the name must be one of the case's materials.
std::string read_material_name(const Section& s, std::string_view key,
                               const MaterialTable& materials);

/// The output schedule and time step of a stage section ([fem] or [mpm]), after its
/// end_time: checkpoint_times (within the run), checkpoint_every, output_every,
/// vtk_every (a whole multiple of output_every, when that is not 0, since frames are
/// written at output steps), courant and time_step. One reading for both stages, as
/// they share the run loop (common/run).
template <class StageSpec>
void read_schedule_and_step(const Section& s, StageSpec& spec) {
  const Range within_run{.min = 0.0,
                         .max = spec.end_time,
                         .max_closed = true,
                         .unit = "s",
                         .note = fmt::format("within {}.end_time", s.path())};
  spec.checkpoint_times = s.numbers("checkpoint_times", within_run, true);
  spec.checkpoint_every = s.number("checkpoint_every", non_negative("s"), 0.0);
  spec.output_every = s.number("output_every", non_negative("s"), 0.0);
  if (s.has("vtk_every")) {
    const double every = s.number("vtk_every", non_negative("s"));
    if (every > 0.0 && spec.output_every > 0.0 && !is_whole_multiple(every, spec.output_every)) {
      s.fail("vtk_every",
             fmt::format("{} s is not a whole multiple of {}.output_every = {} s (frames are "
                         "written at output steps)",
                         every, s.path(), spec.output_every));
    }
    spec.vtk_every = every;
  }
  spec.courant = s.number("courant", courant_range(), spec.courant);
  spec.time_step = s.number("time_step", non_negative("s"), 0.0);
}

// ----------------------------------------------------------------------------- sections

/// [[materials]] (case_file_materials.cpp).
MaterialTable read_materials(const Section& root);
/// [mesh] (case_file_mesh.cpp); a Gmsh file is looked for relative to `case_folder`.
MeshSpec read_mesh(const Section& root, const MaterialTable& materials,
                   const std::filesystem::path& case_folder);
/// Bounding box of the initial body, when the case file alone determines it.
std::optional<std::pair<Vec2, Vec2>> body_box(const MeshSpec& mesh);
/// [fem] (case_file_fem.cpp).
/// A motion file is looked for relative to `case_folder`.
FemSpec read_fem(const Section& root, const MeshSpec& mesh,
                 const std::filesystem::path& case_folder);
/// [transfer] (case_file_transfer.cpp).
TransferSpec read_transfer(const Section& root, const FemSpec& fem);
/// [mpm] (case_file_mpm.cpp): the grid must hold the body, the run outlast every transfer.
MpmSpec read_mpm(const Section& root, const MaterialTable& materials, const MeshSpec& mesh,
                 const TransferSpec& transfer);
/// [metrics] (case_file_metrics.cpp).
MetricsSpec read_metrics(const Section& root);
/// [opensees] (case_file_mesh.cpp): only with an OpenSees mesh, whose recorders it names.
std::optional<OpenSeesImportSpec> read_opensees_import(const Section& root, const MeshSpec& mesh,
                                                       const std::filesystem::path& case_folder);

}  // namespace slide::case_reader
