#include "common/io/vtk_output.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"

namespace slide {

VtkField vtk_field(std::string name, std::span<const double> values) {
  return {std::move(name), 1, values};
}

VtkField vtk_field(std::string name, std::span<const Vec2> values) {
  return {
      std::move(name), 2, {values.empty() ? nullptr : values.front().data(), 2 * values.size()}};
}

VtkField vtk_field(std::string name, std::span<const Vec4> values) {
  return {
      std::move(name), 4, {values.empty() ? nullptr : values.front().data(), 4 * values.size()}};
}

namespace {

vtkNew<vtkDoubleArray> make_array(const VtkField& field, std::size_t expected_tuples,
                                  const std::filesystem::path& path) {
  const auto components = static_cast<std::size_t>(field.components);
  if (field.values.size() != expected_tuples * components) {
    throw Error("{}: VTK field {} has {} values, expected {} × {}", path.string(), field.name,
                field.values.size(), expected_tuples, components);
  }
  const int stored = field.components == 2 ? 3 : field.components;
  vtkNew<vtkDoubleArray> array;
  array->SetName(field.name.c_str());
  array->SetNumberOfComponents(stored);
  array->SetNumberOfTuples(static_cast<vtkIdType>(expected_tuples));
  double tuple[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < expected_tuples; ++i) {
    for (std::size_t c = 0; c < components; ++c) tuple[c] = field.values[i * components + c];
    array->SetTypedTuple(static_cast<vtkIdType>(i), tuple);
  }
  return array;
}

vtkNew<vtkPoints> make_points(std::span<const Vec2> points) {
  vtkNew<vtkPoints> vtk_points;
  vtk_points->SetDataTypeToDouble();
  vtk_points->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    vtk_points->SetPoint(static_cast<vtkIdType>(i), points[i].x(), points[i].y(), 0.0);
  }
  return vtk_points;
}

/// True when the file's last non-blank bytes are the closing tag of a VTK XML file.
bool ends_with_closing_tag(const std::filesystem::path& file) {
  constexpr std::string_view tag = "</VTKFile>";
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  const std::streamoff size = in.tellg();
  if (!in || size < static_cast<std::streamoff>(tag.size())) return false;
  const std::streamoff tail = std::min<std::streamoff>(size, 64);
  std::string end(static_cast<std::size_t>(tail), '\0');
  in.seekg(size - tail);
  in.read(end.data(), tail);
  const auto last = end.find_last_not_of(" \t\r\n");
  return in && last != std::string::npos && last + 1 >= tag.size() &&
         std::string_view(end).substr(last + 1 - tag.size(), tag.size()) == tag;
}

/// Why a frame could not be written, in the words the other writers use: VTK's
/// OutOfDiskSpaceError and a frame cut short on a (nearly) full file system are "No
/// space left on device", as the HDF5 and text writers say it.
std::string write_failure(const std::filesystem::path& temporary, unsigned long error_code) {
  std::error_code ec;
  const auto space = std::filesystem::space(temporary.parent_path(), ec);
  constexpr std::uintmax_t nearly_full = 1 << 16;
  if (error_code == vtkErrorCode::OutOfDiskSpaceError || (!ec && space.available < nearly_full)) {
    return "No space left on device";
  }
  if (error_code != vtkErrorCode::NoError) return vtkErrorCode::GetStringFromErrorCode(error_code);
  return "the frame was cut short";
}

void write_grid(const std::filesystem::path& path, vtkUnstructuredGrid* grid) {
  // VTK reports errors itself on stderr (a coloured report of many lines); ours is the
  // one line of the exception below.
  vtkObject::GlobalWarningDisplayOff();
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
    const int written = writer->Write();
    // On a full disk the XML writer can report success with the file cut short: the
    // frame is only renamed into place when it is complete.
    if (written != 1 || writer->GetErrorCode() != vtkErrorCode::NoError ||
        !ends_with_closing_tag(temporary)) {
      throw Error("{}: cannot write the VTK frame ({}); the former file is kept", path.string(),
                  write_failure(temporary, writer->GetErrorCode()));
    }
  });
}

}  // namespace

void write_vtk_mesh(const std::filesystem::path& path, std::span<const Vec2> points,
                    ElementShape shape, std::span<const Index> connectivity,
                    const std::vector<VtkField>& point_fields,
                    const std::vector<VtkField>& cell_fields) {
  const auto per_cell = static_cast<std::size_t>(nodes_per_element(shape));
  const std::size_t cells = connectivity.size() / per_cell;
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(make_points(points));
  grid->Allocate(static_cast<vtkIdType>(cells));
  const int cell_type = shape == ElementShape::quad4 ? VTK_QUAD : VTK_TRIANGLE;
  vtkIdType ids[4];
  for (std::size_t e = 0; e < cells; ++e) {
    for (std::size_t k = 0; k < per_cell; ++k) ids[k] = connectivity[e * per_cell + k];
    grid->InsertNextCell(cell_type, static_cast<vtkIdType>(per_cell), ids);
  }
  for (const auto& field : point_fields) {
    grid->GetPointData()->AddArray(make_array(field, points.size(), path));
  }
  for (const auto& field : cell_fields) {
    grid->GetCellData()->AddArray(make_array(field, cells, path));
  }
  write_grid(path, grid);
}

void write_vtk_points(const std::filesystem::path& path, std::span<const Vec2> points,
                      const std::vector<VtkField>& point_fields) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(make_points(points));
  grid->Allocate(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    vtkIdType id = static_cast<vtkIdType>(i);
    grid->InsertNextCell(VTK_VERTEX, 1, &id);
  }
  for (const auto& field : point_fields) {
    grid->GetPointData()->AddArray(make_array(field, points.size(), path));
  }
  write_grid(path, grid);
}

void PvdCollection::add(double time, const std::filesystem::path& file) {
  const auto folder = path_.parent_path();
  const std::string relative =
      file.is_absolute() ? std::filesystem::relative(file, folder).string() : file.string();
  entries_.emplace_back(time, relative);
  write();
}

void PvdCollection::resume(double time) {
  entries_.clear();
  std::ifstream in(path_);
  std::string line;
  auto attribute = [&line](std::string_view key) -> std::optional<std::string> {
    const std::string pattern = std::string(key) + "=\"";
    const auto begin = line.find(pattern);
    if (begin == std::string::npos) return std::nullopt;
    const auto value_begin = begin + pattern.size();
    const auto end = line.find('"', value_begin);
    if (end == std::string::npos) return std::nullopt;
    return line.substr(value_begin, end - value_begin);
  };
  while (std::getline(in, line)) {
    const auto timestep = attribute("timestep");
    const auto file = attribute("file");
    if (!timestep || !file) continue;
    const double t = std::strtod(timestep->c_str(), nullptr);
    if (t <= time) entries_.emplace_back(t, *file);
  }
}

void PvdCollection::write() const {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& [time, file] : entries_) {
    xml << fmt::format("    <DataSet timestep=\"{:.17g}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                       time, file);
  }
  xml << "  </Collection>\n</VTKFile>\n";
  write_text_atomically(path_, xml.str());
}

}  // namespace slide
