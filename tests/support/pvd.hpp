// The (time, file) entries of a ParaView collection (.pvd) as the programs write them
// (common/io/vtk_output.cpp, one <DataSet .../> per line), for the tests of their frames.
#pragma once

#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/programs.hpp"

namespace slide::testing {

inline std::vector<std::pair<double, std::string>> pvd_entries(const std::filesystem::path& path) {
  std::vector<std::pair<double, std::string>> entries;
  std::istringstream in(read_text(path));
  for (std::string line; std::getline(in, line);) {
    const auto t = line.find("timestep=\""), f = line.find("file=\"");
    if (t == std::string::npos || f == std::string::npos) continue;
    entries.emplace_back(std::stod(line.substr(t + 10)),
                         line.substr(f + 6, line.find('"', f + 6) - f - 6));
  }
  return entries;
}

}  // namespace slide::testing
