#include "common/io/vtk_output.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string_view>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkTypeUInt8Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"

namespace slide {

const char* const vtk_conventions =
    "SI units (m, s, kg, Pa). Plane strain in the x-y plane, y up, z out of the plane. "
    "stress, strain: tension positive, components [xx, yy, zz, xy] as in the checkpoints; "
    "stress_tensor, strain_tensor: the same tensors as [XX, YY, ZZ, XY, YZ, XZ] "
    "(YZ = XZ = 0). pressure = -(xx + yy + zz)/3 of stress, compression positive. "
    "von_mises_stress = q = sqrt(3 J2). strain, eps_q, plastic strains: dimensionless. "
    "affine_velocity_gradient: C = dv/dx as [xx, xy, yx, yy], 1/s.";

VtkField vtk_field(std::string name, std::span<const double> values) {
  return {std::move(name), VtkLayout::scalar, values};
}

VtkField vtk_field(std::string name, std::span<const Vec2> values) {
  return {
      std::move(name), VtkLayout::vector,
      std::span<const double>(values.empty() ? nullptr : values.front().data(), 2 * values.size())};
}

VtkField vtk_field(std::string name, std::span<const Vec4> values, VtkLayout layout) {
  return {
      std::move(name), layout,
      std::span<const double>(values.empty() ? nullptr : values.front().data(), 4 * values.size())};
}

VtkField vtk_field(std::string name, std::span<const std::int32_t> values) {
  return {std::move(name), VtkLayout::scalar, values};
}

VtkField vtk_field(std::string name, std::span<const std::int64_t> values) {
  return {std::move(name), VtkLayout::scalar, values};
}

VtkField vtk_field(std::string name, std::span<const std::uint8_t> values) {
  return {std::move(name), VtkLayout::scalar, values};
}

namespace {

/// Values per tuple as our arrays hold them.
int source_components(VtkLayout layout) {
  switch (layout) {
    case VtkLayout::scalar:
      return 1;
    case VtkLayout::vector:
      return 2;
    case VtkLayout::stress_like:
    case VtkLayout::matrix:
      return 4;
  }
  return 1;
}

void name_components(vtkAbstractArray& array, std::initializer_list<const char*> names) {
  int c = 0;
  for (const char* name : names) array.SetComponentName(c++, name);
}

/// A Float64 array of `stored` components per tuple, each tuple made by `fill` from the
/// field's values of that tuple.
template <typename Fill>
vtkSmartPointer<vtkDoubleArray> double_array(const std::string& name, std::span<const double> in,
                                             std::size_t tuples, int per_tuple, int stored,
                                             Fill fill) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(stored);
  array->SetNumberOfTuples(static_cast<vtkIdType>(tuples));
  double* out = array->GetPointer(0);
  const auto from = static_cast<std::size_t>(per_tuple), to = static_cast<std::size_t>(stored);
  for (std::size_t i = 0; i < tuples; ++i) fill(in.data() + i * from, out + i * to);
  return array;
}

template <typename VtkArray, typename T>
vtkSmartPointer<VtkArray> integer_array(const std::string& name, std::span<const T> in) {
  auto array = vtkSmartPointer<VtkArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfTuples(static_cast<vtkIdType>(in.size()));
  std::copy(in.begin(), in.end(), array->GetPointer(0));
  return array;
}

/// The VTK arrays of one field: one, or two for a stress-like field.
std::vector<vtkSmartPointer<vtkAbstractArray>> make_arrays(const VtkField& field,
                                                           std::size_t expected_tuples,
                                                           const std::filesystem::path& path) {
  const std::size_t size = std::visit([](auto span) { return span.size(); }, field.values);
  const auto per_tuple = source_components(field.layout);
  if (size != expected_tuples * static_cast<std::size_t>(per_tuple)) {
    throw Error("{}: VTK field {} has {} values, expected {} × {}", path.string(), field.name, size,
                expected_tuples, per_tuple);
  }
  std::vector<vtkSmartPointer<vtkAbstractArray>> arrays;
  if (const auto* ints = std::get_if<std::span<const std::int32_t>>(&field.values)) {
    arrays.push_back(integer_array<vtkTypeInt32Array>(field.name, *ints));
  } else if (const auto* longs = std::get_if<std::span<const std::int64_t>>(&field.values)) {
    arrays.push_back(integer_array<vtkTypeInt64Array>(field.name, *longs));
  } else if (const auto* flags = std::get_if<std::span<const std::uint8_t>>(&field.values)) {
    arrays.push_back(integer_array<vtkTypeUInt8Array>(field.name, *flags));
  } else {
    const auto values = std::get<std::span<const double>>(field.values);
    switch (field.layout) {
      case VtkLayout::scalar:
        arrays.push_back(double_array(field.name, values, expected_tuples, 1, 1,
                                      [](const double* a, double* b) { b[0] = a[0]; }));
        break;
      case VtkLayout::vector: {
        auto array =
            double_array(field.name, values, expected_tuples, 2, 3, [](const double* a, double* b) {
              b[0] = a[0];
              b[1] = a[1];
              b[2] = 0.0;
            });
        name_components(*array, {"x", "y", "z"});
        arrays.push_back(array);
        break;
      }
      case VtkLayout::stress_like:
      case VtkLayout::matrix: {
        const bool stress_like = field.layout == VtkLayout::stress_like;
        auto array = double_array(field.name, values, expected_tuples, 4, 4,
                                  [](const double* a, double* b) { std::copy(a, a + 4, b); });
        if (stress_like) {
          name_components(*array, {"xx", "yy", "zz", "xy"});
        } else {
          name_components(*array, {"xx", "xy", "yx", "yy"});
        }
        arrays.push_back(array);
        if (!stress_like) break;
        auto tensor = double_array(field.name + "_tensor", values, expected_tuples, 4, 6,
                                   [](const double* a, double* b) {
                                     std::copy(a, a + 4, b);
                                     b[4] = 0.0;
                                     b[5] = 0.0;
                                   });
        name_components(*tensor, {"XX", "YY", "ZZ", "XY", "YZ", "XZ"});
        arrays.push_back(tensor);
        break;
      }
    }
  }
  return arrays;
}

template <typename Data>
void add_fields(Data* data, const std::vector<VtkField>& fields, std::size_t tuples,
                const std::filesystem::path& path) {
  for (const auto& field : fields) {
    for (const auto& array : make_arrays(field, tuples, path)) data->AddArray(array);
  }
}

/// The field data every file carries: its time and the conventions.
void add_time_and_conventions(vtkUnstructuredGrid* grid, double time) {
  vtkNew<vtkDoubleArray> time_value;
  time_value->SetName("TimeValue");
  time_value->SetNumberOfTuples(1);
  time_value->SetValue(0, time);
  grid->GetFieldData()->AddArray(time_value);
  vtkNew<vtkStringArray> conventions;
  conventions->SetName("conventions");
  conventions->InsertNextValue(vtk_conventions);
  grid->GetFieldData()->AddArray(conventions);
}

vtkNew<vtkPoints> make_points(std::span<const Vec2> points) {
  vtkNew<vtkPoints> vtk_points;
  vtk_points->SetDataTypeToDouble();
  vtk_points->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  double* out = static_cast<vtkDoubleArray*>(vtk_points->GetData())->GetPointer(0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    out[3 * i] = points[i].x();
    out[3 * i + 1] = points[i].y();
    out[3 * i + 2] = 0.0;
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
    writer->SetCompressorTypeToNone();
    writer->SetHeaderTypeToUInt64();
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

void write_vtk_mesh(const std::filesystem::path& path, double time, std::span<const Vec2> points,
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
  add_fields(grid->GetPointData(), point_fields, points.size(), path);
  add_fields(grid->GetCellData(), cell_fields, cells, path);
  add_time_and_conventions(grid, time);
  write_grid(path, grid);
}

void write_vtk_points(const std::filesystem::path& path, double time, std::span<const Vec2> points,
                      const std::vector<VtkField>& point_fields) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(make_points(points));
  // One vertex per point: cell i is point i.
  const auto n = static_cast<vtkIdType>(points.size());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) {
    offsets->SetValue(i, i);
    connectivity->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> vertices;
  vertices->SetData(offsets, connectivity);
  grid->SetCells(VTK_VERTEX, vertices);
  add_fields(grid->GetPointData(), point_fields, points.size(), path);
  add_time_and_conventions(grid, time);
  write_grid(path, grid);
}

namespace {

/// The XML name of an array's value type (VTK's own words: Float64, Int32, ...).
std::string_view xml_type_name(vtkAbstractArray& array) {
  switch (array.GetDataType()) {
    case VTK_DOUBLE:
      return "Float64";
    case VTK_FLOAT:
      return "Float32";
    case VTK_INT:
      return "Int32";
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
      return array.GetDataTypeSize() == 8 ? "Int64" : "Int32";
    case VTK_UNSIGNED_CHAR:
      return "UInt8";
    default:
      throw Error("VTK array {}: no XML type name for VTK type {}", array.GetName(),
                  array.GetDataType());
  }
}

}  // namespace

void write_vtk_points_collection(const std::filesystem::path& path,
                                 std::span<const std::string> pieces,
                                 const std::vector<VtkField>& point_fields) {
  std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <PUnstructuredGrid GhostLevel=\"0\">\n"
      "    <PPointData>\n";
  for (const auto& field : point_fields) {
    // The arrays of an empty field: the names, types and components of the pieces'.
    VtkField empty{field.name, field.layout, {}};
    std::visit([&](auto span) { empty.values = decltype(span){}; }, field.values);
    for (const auto& array : make_arrays(empty, 0, path)) {
      text += fmt::format("      <PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                          xml_type_name(*array), array->GetName(), array->GetNumberOfComponents());
    }
  }
  text +=
      "    </PPointData>\n"
      "    <PPoints>\n"
      "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      "    </PPoints>\n";
  for (const auto& piece : pieces) text += fmt::format("    <Piece Source=\"{}\"/>\n", piece);
  text += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_text_atomically(path, text);
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
