// .vti input/output of GridData (VTK XML image data). The only file of the
// grid-field module that includes VTK.
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLImageDataWriter.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "fields/grid_field.hpp"
#include "io/vtk_messages.hpp"

namespace magenc {

namespace {

// Six integers "x0 x1 y0 y1 z0 z1" of the attribute `attr` in `tag`; false when absent or malformed.
bool parse_extent(const std::string& tag, const std::string& attr, long long ext[6]) {
  const auto a = tag.find(" " + attr + "=\"");
  if (a == std::string::npos) return false;
  const char* p = tag.c_str() + a + attr.size() + 3;
  for (int i = 0; i < 6; ++i) {
    char* end = nullptr;
    errno = 0;
    ext[i] = std::strtoll(p, &end, 10);
    if (end == p || errno != 0) return false;
    p = end;
  }
  while (*p == ' ') ++p;
  return *p == '"';
}

// What VTK's reader does not check, checked on the file's XML text before VTK reads it:
// - the declared WholeExtent is sane (x1 >= x0, ...) and at most kMaxGridPoints nodes: VTK would
//   otherwise try to allocate whatever the file claims (2e9 x 2e9 -> std::bad_alloc);
// - exactly one <Piece> whose Extent is the WholeExtent (as solve_field writes): VTK accepts a
//   smaller piece and leaves the rest of the arrays unfilled (garbage samples);
// - the closing tags are there (</Piece>, </ImageData>, </VTKFile>): VTK accepts a file cut after
//   its data.
constexpr long long kMaxGridPoints = 50'000'000;  // x 64 bytes (VTK arrays + GridData) = 3.2 GB
void check_vti_structure(const std::string& name) {
  std::ifstream in(name, std::ios::binary);
  if (!in) throw InputError("grid file " + name + ": cannot open");
  in.seekg(0, std::ios::end);
  const long long size = in.tellg();
  // The XML part: everything before raw appended data (solve_field's files), or the whole file when
  // the data is inline (ascii/base64), up to 64 MiB.
  const long long head_n = std::min<long long>(size, 64LL << 20);
  std::string head(std::size_t(head_n), '\0');
  in.seekg(0);
  in.read(head.data(), head_n);
  const auto appended = head.find("<AppendedData");
  const std::string xml = appended == std::string::npos ? head : head.substr(0, appended);
  const std::string bad = "grid file " + name + ": ";
  const auto img = xml.find("<ImageData");
  if (img == std::string::npos) throw InputError(bad + "no <ImageData> element: not VTK XML image data (.vti)");
  const std::string img_tag = xml.substr(img, xml.find('>', img) - img);
  long long whole[6];
  if (!parse_extent(img_tag, "WholeExtent", whole))
    throw InputError(bad + "<ImageData> has no valid WholeExtent (six integers)");
  long double nodes = 1;
  for (int d = 0; d < 3; ++d) {
    if (whole[2 * d + 1] < whole[2 * d] || whole[2 * d] < -(1LL << 40) || whole[2 * d + 1] > (1LL << 40))
      throw InputError(bad + "WholeExtent axis " + std::to_string(d) + " is [" + std::to_string(whole[2 * d]) + ", " +
                       std::to_string(whole[2 * d + 1]) + "]: allowed lo <= hi");
    nodes *= static_cast<long double>(whole[2 * d + 1] - whole[2 * d] + 1);
  }
  if (nodes > kMaxGridPoints)
    throw InputError(bad + "WholeExtent declares " + num(double(nodes)) + " nodes (about " +
                     num(double(nodes) * 64 / 1e9) + " GB to read): allowed at most " + num(double(kMaxGridPoints)) +
                     " nodes");
  std::size_t pieces = 0;
  for (auto p = xml.find("<Piece", img); p != std::string::npos; p = xml.find("<Piece", p + 1)) {
    ++pieces;
    long long ext[6];
    if (!parse_extent(xml.substr(p, xml.find('>', p) - p), "Extent", ext))
      throw InputError(bad + "<Piece> has no valid Extent (six integers)");
    for (int i = 0; i < 6; ++i)
      if (ext[i] != whole[i])
        throw InputError(bad + "piece Extent differs from WholeExtent: allowed one piece covering the whole grid");
  }
  if (pieces != 1)
    throw InputError(bad + std::to_string(pieces) + " <Piece> elements: allowed exactly one covering the whole grid");
  // Closing tags: </Piece> and </ImageData> in the XML part, </VTKFile> at the very end.
  std::string tail(std::size_t(std::min<long long>(size, 256)), '\0');
  in.seekg(size - static_cast<long long>(tail.size()));
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.back()))) tail.pop_back();
  const std::string& body = appended == std::string::npos ? tail : xml;
  const bool closed = tail.size() >= 10 && tail.compare(tail.size() - 10, 10, "</VTKFile>") == 0 &&
                      (appended == std::string::npos ? size <= head_n && head.find("</ImageData>") != std::string::npos
                                                     : body.find("</ImageData>") != std::string::npos) &&
                      (appended == std::string::npos || tail.find("</AppendedData>") != std::string::npos);
  if (!closed) throw InputError(bad + "truncated (closing </ImageData> or </VTKFile> tag missing)");
}

}  // namespace

GridData read_grid_vti(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError("grid file " + name + " does not exist or is not a file (expected a .vti written by solve_field)");
  const VtkMessageCapture vtk_messages;  // VTK's multi-line messages become the one-line error below
  vtkNew<vtkXMLImageDataReader> reader;
  if (!reader->CanReadFile(name.c_str()))
    throw InputError("grid file " + name + " is not VTK XML image data (.vti)");
  check_vti_structure(name);
  reader->SetFileName(name.c_str());
  {
    // An ascii .vti is parsed with strtod, which raises FE_OVERFLOW for values such as 1e999: bad
    // input, which the reader's error code or GridData::validate (finite values) turns into an
    // InputError, so the read itself is untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    reader->Update();
  }
  vtkImageData* img = reader->GetOutput();
  if (reader->GetErrorCode() != 0 || img == nullptr || img->GetNumberOfPoints() == 0 || vtk_messages.error())
    throw InputError("grid file " + name + " could not be read as VTK image data (empty or corrupt" +
                     (vtk_messages.error() ? ": " + vtk_messages.first_message() : std::string()) + ")");

  const double* dir = img->GetDirectionMatrix()->GetData();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (std::abs(dir[3 * r + c] - (r == c ? 1.0 : 0.0)) > 1e-12)
        throw InputError("grid file " + name + " has a rotated image (direction matrix is not identity): not supported");

  GridData g;
  g.source = name;
  int dims[3];
  double origin[3], spacing[3];
  img->GetDimensions(dims);
  img->GetOrigin(origin);
  img->GetSpacing(spacing);
  for (int d = 0; d < 3; ++d) {
    g.dims[d] = dims[d];
    g.origin_mm[d] = origin[d];
    g.spacing_mm[d] = spacing[d];
  }
  const vtkIdType n = img->GetNumberOfPoints();
  vtkDataArray* b = img->GetPointData()->GetArray("B");
  vtkDataArray* bz = img->GetPointData()->GetArray("Bz");
  if (b != nullptr && b->GetNumberOfComponents() != 3)
    throw InputError("grid file " + name + ": point array `B` has " + std::to_string(b->GetNumberOfComponents()) +
                     " components, expected 3");
  if (bz != nullptr && bz->GetNumberOfComponents() != 1)
    throw InputError("grid file " + name + ": point array `Bz` must have 1 component");
  if ((b != nullptr && b->GetNumberOfTuples() != n) || (bz != nullptr && bz->GetNumberOfTuples() != n))
    throw InputError("grid file " + name + ": a point array has fewer or more values than the grid has nodes (" +
                     std::to_string(n) + ")");
  if (b == nullptr && bz == nullptr)
    throw InputError("grid file " + name + " has neither point array `B` (T, 3 components) nor `Bz` (T)");
  if (b != nullptr) {
    g.Bx_T.resize(std::size_t(n));
    g.By_T.resize(std::size_t(n));
    for (vtkIdType i = 0; i < n; ++i) {
      g.Bx_T[std::size_t(i)] = b->GetComponent(i, 0);
      g.By_T[std::size_t(i)] = b->GetComponent(i, 1);
    }
  }
  g.Bz_T.resize(std::size_t(n));
  for (vtkIdType i = 0; i < n; ++i) g.Bz_T[std::size_t(i)] = bz ? bz->GetComponent(i, 0) : b->GetComponent(i, 2);
  g.validate();
  return g;
}

void write_grid_vti(const std::filesystem::path& file, const GridData& g) {
  g.validate();
  vtkNew<vtkImageData> img;
  img->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  img->SetOrigin(g.origin_mm.x(), g.origin_mm.y(), g.origin_mm.z());
  img->SetSpacing(g.spacing_mm.x(), g.spacing_mm.y(), g.is_plane() ? 1.0 : g.spacing_mm.z());
  const vtkIdType n = vtkIdType(g.nodes());
  vtkNew<vtkDoubleArray> bz;
  bz->SetName("Bz");
  bz->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i) bz->SetValue(i, g.Bz_T[std::size_t(i)]);
  img->GetPointData()->AddArray(bz);
  if (g.has_B()) {
    vtkNew<vtkDoubleArray> b;
    b->SetName("B");
    b->SetNumberOfComponents(3);
    b->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i) {
      const std::size_t k = std::size_t(i);
      b->SetTuple3(i, g.Bx_T[k], g.By_T[k], g.Bz_T[k]);
    }
    img->GetPointData()->AddArray(b);
  }
  std::filesystem::create_directories(file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path());
  const std::filesystem::path tmp = file.string() + ".tmp." + std::to_string(::getpid());
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetFileName(tmp.string().c_str());
  writer->SetInputData(img);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw ComputeError("VTK could not write " + file.string());
  }
  std::filesystem::rename(tmp, file);
}

}  // namespace magenc
