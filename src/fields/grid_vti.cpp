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

#include <cmath>
#include <system_error>
#include <unistd.h>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "fields/grid_field.hpp"

namespace magenc {

GridData read_grid_vti(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError("grid file " + name + " does not exist or is not a file (expected a .vti written by solve_field)");
  vtkNew<vtkXMLImageDataReader> reader;
  if (!reader->CanReadFile(name.c_str()))
    throw InputError("grid file " + name + " is not VTK XML image data (.vti)");
  reader->SetFileName(name.c_str());
  {
    // An ascii .vti is parsed with strtod, which raises FE_OVERFLOW for values such as 1e999: bad
    // input, which the reader's error code or GridData::validate (finite values) turns into an
    // InputError, so the read itself is untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    reader->Update();
  }
  vtkImageData* img = reader->GetOutput();
  if (reader->GetErrorCode() != 0 || img == nullptr || img->GetNumberOfPoints() == 0)
    throw InputError("grid file " + name + " could not be read as VTK image data (empty or corrupt)");

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
