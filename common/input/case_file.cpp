// The case-file reader (case_file.hpp). toml++ parses; the section readers check, one file
// per table (case_file_<section>.cpp). Every table has one reader function, and they all
// go through `Section` (case_file_reader.hpp): it knows the table's dotted
// path and where the table sits in the file, refuses keys it does not know, and reads
// typed values with their admissible ranges, so that every fault becomes one line
//   case.toml:12: fem.end_time = -1 is not admissible (expected > 0 s)
//
// Policy on keys that the chosen options do not use: keys that contradict the
// configuration are errors (the geometry keys of another mesh generator, strength
// parameters of a linear elastic material, failure-stage settings of a geostatic-only
// case); tuning keys of an option not selected are accepted and ignored (rbf_neighbours
// with "rbf", gravity_stage_* with "k0"), so that switching an option is a one-line edit.
#include "common/input/case_file.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "common/input/case_file_reader.hpp"

namespace slide {

// This file is the reader's entry point: it calls the section readers by their names.
using namespace case_reader;

namespace {

void read_case_table(const Section& root, const std::filesystem::path& file, Case& c) {
  const Section s = root.table("case", Section::Keys{"name", "description", "gravity_angle"});
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
  // A verification device: a level model under gravity turned by θ is a model on an
  // incline of θ (falling towards +x), seen in the incline's frame (tests/seismic).
  const double angle =
      s.number("gravity_angle", Range{.min = -45.0, .max = 45.0, .unit = "degrees"}, 0.0);
  if (angle != 0.0) {
    const double theta = angle * std::numbers::pi / 180.0;
    c.gravity = gravity_acceleration * Vec2(std::sin(theta), -std::cos(theta));
  }
}

}  // namespace

// ----------------------------------------------------------------------------- API

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
      Section::Keys{"case", "materials", "mesh", "fem", "transfer", "mpm", "metrics", "opensees"});
  Case c;
  c.file = source_name;
  read_case_table(root, source_name, c);
  c.materials = read_materials(root);
  c.mesh = read_mesh(root, c.materials, source_name.parent_path());
  c.fem = read_fem(root, c.mesh, source_name.parent_path());
  for (std::size_t i = 0; i < c.materials.size(); ++i) {
    if (c.materials[i].saturable() && !c.fem.water) {
      throw Error(
          "{}: materials[{}] (\"{}\") has a porosity but the case has no [fem.water] (the water "
          "table below which it is saturated)",
          source_name.string(), i, c.materials[i].name);
    }
  }
  c.transfer = read_transfer(root, c.fem);
  c.mpm = read_mpm(root, c.materials, c.mesh, c.transfer);
  c.metrics = read_metrics(root);
  c.opensees = read_opensees_import(root, c.mesh, source_name.parent_path());
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
  // Read at most one byte more than any case file may have: a file that never ends
  // (/dev/zero) was read to 4.2 GB before failing.
  std::string text(max_case_file_bytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw Error("{}: cannot read the case file", path.string());
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > max_case_file_bytes) {
    throw Error("{}: larger than {} MiB, not a case file", path.string(),
                max_case_file_bytes >> 20);
  }
  return parse_case(text, path);
}

}  // namespace slide
