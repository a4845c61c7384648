// The case reader's shared helpers (case_file_reader.hpp).
#include "common/input/case_file_reader.hpp"

#include "common/geometry/triangle_rules.hpp"

namespace slide::case_reader {

std::string format_point(const Vec2& p) {
  return fmt::format("({}, {})", p.x(), p.y());
}

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

std::string locate(const std::string& file, const toml::source_region& region) {
  if (region.begin.line == 0) return file;
  return fmt::format("{}:{}", file, region.begin.line);
}

std::string read_recorder_name(const Section& r, const std::vector<std::string>& taken) {
  std::string name = r.string("name");
  if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                             "0123456789-_") != std::string::npos) {
    r.fail("name", fmt::format("\"{}\" is not a file name of letters, digits, - and _", name));
  }
  if (std::find(taken.begin(), taken.end(), name) != taken.end()) {
    r.fail("name", fmt::format("\"{}\" twice", name));
  }
  return name;
}

std::vector<Vec2> read_points(const Section& s, std::string_view key) {
  std::vector<Vec2> points;
  const auto& items = s.reader().array(s.node(key), s.dotted(key));
  if (items.empty()) s.fail(key, "an empty list");
  for (std::size_t i = 0; i < items.size(); ++i) {
    points.push_back(s.reader().point(items[i], fmt::format("{}[{}]", s.dotted(key), i)));
  }
  return points;
}

std::pair<int, int> read_particle_layout(const Section& s, std::string_view key, int fallback) {
  if (!s.has(key)) return {fallback, fallback};
  const auto& reader = s.reader();
  const toml::node& node = s.node(key);
  // The bound fem2mpm's --particles-per-element has (common/geometry/triangle_rules.hpp).
  constexpr int most = max_particles_per_direction;
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

std::string friction_problem(const Section& s) {
  return s.has("friction_coefficient")
             ? std::string()
             : fmt::format("needs {}, which is missing", s.dotted("friction_coefficient"));
}

}  // namespace slide::case_reader
