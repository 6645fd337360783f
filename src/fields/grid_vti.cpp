// .vti input/output of GridData (VTK XML image data): the one .vti reader and
// writer of magenc (solve_field's plane.vti and box.vti, table_to_vti, grid: sources).
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
#include <optional>
#include <system_error>
#include <unistd.h>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "fields/grid.hpp"
#include "core/vtk_messages.hpp"

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
  // Data arrays: ascii, or raw appended data whose block headers fit the declared extent and the file.
  // VTK trusts those headers: a header that claims 2^32 blocks makes it allocate gigabytes (found by
  // fuzz_vti: a mangled header_type attribute), so each one is checked here before VTK reads it.
  const auto vtkfile = xml.find("<VTKFile");
  const std::string file_tag = vtkfile == std::string::npos ? "" : xml.substr(vtkfile, xml.find('>', vtkfile) - vtkfile);
  const auto attr = [](const std::string& tag, const std::string& name) -> std::optional<std::string> {
    const auto a = tag.find(" " + name + "=\"");
    if (a == std::string::npos) return std::nullopt;
    const auto b = a + name.size() + 3;
    const auto e = tag.find('"', b);
    if (e == std::string::npos) return std::nullopt;
    return tag.substr(b, e - b);
  };
  const std::string header_type = attr(file_tag, "header_type").value_or("UInt32");
  if (header_type != "UInt32" && header_type != "UInt64")
    throw InputError(bad + "header_type '" + header_type + "': allowed UInt32 or UInt64");
  const int hw = header_type == "UInt64" ? 8 : 4;
  const bool compressed = attr(file_tag, "compressor").has_value();
  long long data_start = -1;
  std::string encoding;
  if (appended != std::string::npos) {
    const std::string app_tag = head.substr(appended, head.find('>', appended) - appended);
    encoding = attr(app_tag, "encoding").value_or("");
    if (encoding != "raw" && encoding != "base64")
      throw InputError(bad + "appended data encoding '" + encoding + "': allowed raw or base64");
    const auto underscore = head.find('_', appended + app_tag.size());
    if (underscore == std::string::npos) throw InputError(bad + "truncated appended data");
    data_start = static_cast<long long>(underscore) + 1;
  }
  // The first n bytes of the data at file position `at` (base64: decoded from 4 ceil(n / 3) characters).
  const auto bytes_at = [&](long long at, unsigned long long n) {
    const bool b64 = encoding == "base64";
    const unsigned long long chars = b64 ? 4 * ((n + 2) / 3) : n;
    if (at < 0 || static_cast<unsigned long long>(at) + chars > static_cast<unsigned long long>(size))
      throw InputError(bad + "truncated (a data block header lies beyond the end)");
    std::string raw(chars, '\0');
    in.clear();
    in.seekg(at);
    in.read(raw.data(), static_cast<std::streamsize>(chars));
    if (!b64) return raw;
    std::string out;
    unsigned int acc = 0;
    int bits = 0;
    for (char c : raw) {
      int v = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52
              : c == '+' ? 62 : c == '/' ? 63 : -1;
      if (v < 0) break;  // '=' padding or the end of this block
      acc = (acc << 6) | unsigned(v);
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        out.push_back(char((acc >> bits) & 0xff));
      }
    }
    if (out.size() < n) throw InputError(bad + "corrupted base64 data block header");
    return out;
  };
  const auto word = [&](const std::string& b, unsigned long long i) {
    unsigned long long v = 0;
    for (int k = hw - 1; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(b[i * hw + unsigned(k)]);
    return v;  // little endian (byte_order checked below)
  };
  const auto read_uint = [&](long long at) { return word(bytes_at(at, hw), 0); };
  if (attr(file_tag, "byte_order").value_or("LittleEndian") != "LittleEndian")
    throw InputError(bad + "byte_order must be LittleEndian");
  for (auto p = xml.find("<DataArray", img); p != std::string::npos; p = xml.find("<DataArray", p + 1)) {
    const std::string tag = xml.substr(p, xml.find('>', p) - p);
    const std::string format = attr(tag, "format").value_or("");
    if (format == "ascii") continue;
    if (format != "appended" || data_start < 0)
      throw InputError(bad + "DataArray format '" + format + "': allowed ascii or raw appended data");
    const std::string type = attr(tag, "type").value_or("");
    const int type_size = type == "Float64" || type == "Int64" || type == "UInt64" ? 8
                          : type == "Float32" || type == "Int32" || type == "UInt32" ? 4
                          : type == "Int16" || type == "UInt16" ? 2
                          : type == "Int8" || type == "UInt8" ? 1 : 0;
    if (type_size == 0) throw InputError(bad + "DataArray type '" + type + "' is not supported");
    const long long comps = std::atoll(attr(tag, "NumberOfComponents").value_or("1").c_str());
    const long long offset = std::atoll(attr(tag, "offset").value_or("-1").c_str());
    if (comps < 1 || comps > 9 || offset < 0) throw InputError(bad + "DataArray NumberOfComponents or offset invalid");
    const unsigned long long expected = static_cast<unsigned long long>(nodes) * comps * type_size;
    const long long at = data_start + offset;
    if (!compressed) {
      if (read_uint(at) != expected || (encoding == "raw" && at + hw + static_cast<long long>(expected) > size))
        throw InputError(bad + "a data array's size does not match the WholeExtent (or the file is truncated)");
      continue;
    }
    const std::string h3 = bytes_at(at, 3ULL * hw);
    const unsigned long long blocks = word(h3, 0), block = word(h3, 1), last = word(h3, 2);
    const unsigned long long total = blocks == 0 ? 0 : (last == 0 ? blocks * block : (blocks - 1) * block + last);
    if (blocks > static_cast<unsigned long long>(size) / hw || block == 0 || last > block || total != expected)
      throw InputError(bad + "a compressed data array's block header does not match the WholeExtent");
    const std::string h = bytes_at(at, (3 + blocks) * hw);
    unsigned long long stored = 0;
    for (unsigned long long b = 0; b < blocks; ++b) stored += word(h, 3 + b);
    if (encoding == "raw" && at + static_cast<long long>((3 + blocks) * hw + stored) > size)
      throw InputError(bad + "truncated (compressed data runs past the end of the file)");
  }
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

void write_grid_vti(const std::filesystem::path& file, const GridData& g, const VtiFormat& format) {
  g.validate();
  vtkNew<vtkImageData> img;
  img->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  img->SetOrigin(g.origin_mm.x(), g.origin_mm.y(), g.origin_mm.z());
  img->SetSpacing(g.spacing_mm.x(), g.spacing_mm.y(), g.is_plane() ? 1.0 : g.spacing_mm.z());
  const vtkIdType n = vtkIdType(g.nodes());
  if (format.with_bz) {
    vtkNew<vtkDoubleArray> bz;
    bz->SetName("Bz");
    bz->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i) bz->SetValue(i, g.Bz_T[std::size_t(i)]);
    img->GetPointData()->AddArray(bz);
  }
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
  writer->SetEncodeAppendedData(format.base64 ? 1 : 0);
  if (format.compress) writer->SetCompressorTypeToZLib();
  else writer->SetCompressorTypeToNone();
  if (writer->Write() != 1) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw ComputeError("VTK could not write " + file.string());
  }
  std::filesystem::rename(tmp, file);
}

}  // namespace magenc
