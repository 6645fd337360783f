#include "field_solver/field_io/vtk_io.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "core/vtk_messages.hpp"

namespace magenc::fem {
namespace {

vtkSmartPointer<vtkDoubleArray> vector_array(const char* name, const Eigen::Matrix3Xd& v) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(v.cols());
  for (Eigen::Index i = 0; i < v.cols(); ++i) a->SetTuple3(i, v(0, i), v(1, i), v(2, i));
  return a;
}

// Appended raw binary (no base64 encoding); zlib blocks only when asked.
void set_format(vtkXMLWriter* w, bool compress) {
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();
  if (compress) w->SetCompressorTypeToZLib();
  else w->SetCompressorTypeToNone();
}

}  // namespace

void write_solution_vtu(const std::filesystem::path& path, const FeSolution& sol, const Eigen::Matrix3Xd& B_cell,
                        bool compress) {
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(sol.points_mm.cols());
  for (Eigen::Index i = 0; i < sol.points_mm.cols(); ++i) pts->SetPoint(i, sol.points_mm(0, i), sol.points_mm(1, i), sol.points_mm(2, i));
  grid->SetPoints(pts);
  const int nd = static_cast<int>(sol.cell_dofs.rows());
  const int type = sol.order == 1 ? VTK_TETRA : VTK_QUADRATIC_TETRA;
  grid->Allocate(sol.num_cells());
  vtkIdType ids[10];
  for (int c = 0; c < sol.num_cells(); ++c) {
    for (int k = 0; k < nd; ++k) ids[k] = sol.cell_dofs(k, c);
    grid->InsertNextCell(type, nd, ids);
  }
  vtkNew<vtkDoubleArray> psi;
  psi->SetName("psi");
  psi->SetNumberOfTuples(sol.psi_Tmm.size());
  for (Eigen::Index i = 0; i < sol.psi_Tmm.size(); ++i) psi->SetValue(i, sol.psi_Tmm[i]);
  grid->GetPointData()->AddArray(psi);
  grid->GetCellData()->AddArray(vector_array("B", B_cell));
  vtkNew<vtkIntArray> region;
  region->SetName("region");
  region->SetNumberOfTuples(sol.num_cells());
  vtkNew<vtkDoubleArray> mu;
  mu->SetName("mu_r");
  mu->SetNumberOfTuples(sol.num_cells());
  for (int c = 0; c < sol.num_cells(); ++c) {
    region->SetValue(c, sol.region[c]);
    mu->SetValue(c, sol.mu_r[c]);
  }
  grid->GetCellData()->AddArray(region);
  grid->GetCellData()->AddArray(mu);
  grid->GetCellData()->AddArray(vector_array("Br", sol.br_T));
  vtkNew<vtkIntArray> rec;  // field data: 1 when B is evaluated from the recovered gradient
  rec->SetName("gradient_recovery");
  rec->InsertNextValue(sol.grad_recovered.cols() > 0 ? 1 : 0);
  grid->GetFieldData()->AddArray(rec);
  if (sol.source) {  // reduced potential: psi is phi; the source magnet rebuilds H_s on reading
    const Magnet& m = sol.source->magnet();
    vtkNew<vtkDoubleArray> src;
    // radius_mm, height_mm, br_T, magnetization_deg, magnetization_elevation_deg[, inner_radius_mm of a ring]
    src->SetName("reduced_potential_source");
    for (double v : {m.radius_mm, m.height_mm, m.br_T, m.magnetization_deg, m.magnetization_elevation_deg})
      src->InsertNextValue(v);
    if (m.is_ring()) src->InsertNextValue(m.inner_radius_mm);
    grid->GetFieldData()->AddArray(src);
  }
  if (sol.split()) {  // split potential: which cells hold the total potential, phi_s on the interface
    vtkNew<vtkIntArray> total;
    total->SetName("total_potential");
    total->SetNumberOfTuples(sol.num_cells());
    for (int c = 0; c < sol.num_cells(); ++c) total->SetValue(c, sol.cell_total[static_cast<size_t>(c)]);
    grid->GetCellData()->AddArray(total);
    vtkNew<vtkDoubleArray> phi_s;
    phi_s->SetName("interface_phi_s");
    phi_s->SetNumberOfTuples(sol.interface_phi_s_Tmm.size());
    for (Eigen::Index i = 0; i < sol.interface_phi_s_Tmm.size(); ++i) phi_s->SetValue(i, sol.interface_phi_s_Tmm[i]);
    grid->GetPointData()->AddArray(phi_s);
  }
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(grid);
  set_format(w, compress);
  if (w->Write() != 1) throw ComputeError("cannot write " + path.string());
}

FeSolution read_solution_vtu(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError("FE mesh file " + path.string() +
                     " does not exist (solve_field writes it only when asked: --set output.mesh_vtu=true)");
  const VtkMessageCapture vtk_messages;  // VTK's multi-line messages become the one-line error below
  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(path.c_str());
  {
    // An ascii .vtu is parsed with strtod, which raises FE_OVERFLOW for values such as 1e999:
    // input parsing, untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    r->Update();
  }
  vtkUnstructuredGrid* grid = r->GetOutput();
  if (r->GetErrorCode() != 0 || vtk_messages.error())
    throw InputError(path.string() + ": could not be read as a VTK unstructured grid (truncated or corrupt: " +
                     vtk_messages.first_message() + ")");
  if (!grid || grid->GetNumberOfCells() == 0) throw InputError(path.string() + ": no cells (not a solve_field mesh.vtu)");
  auto* psi = vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("psi"));
  auto* region = vtkIntArray::SafeDownCast(grid->GetCellData()->GetArray("region"));
  auto* mu = vtkDoubleArray::SafeDownCast(grid->GetCellData()->GetArray("mu_r"));
  auto* br = vtkDoubleArray::SafeDownCast(grid->GetCellData()->GetArray("Br"));
  if (!psi || !region || !mu || !br)
    throw InputError(path.string() + ": missing array psi, region, mu_r or Br (not a solve_field mesh.vtu)");
  if (psi->GetNumberOfTuples() != grid->GetNumberOfPoints() || region->GetNumberOfTuples() != grid->GetNumberOfCells() ||
      mu->GetNumberOfTuples() != grid->GetNumberOfCells() || br->GetNumberOfTuples() != grid->GetNumberOfCells() ||
      br->GetNumberOfComponents() != 3)
    throw InputError(path.string() + ": arrays psi, region, mu_r, Br do not match the points and cells");
  FeSolution s;
  const int type = grid->GetCellType(0);
  if (type == VTK_TETRA) s.order = 1;
  else if (type == VTK_QUADRATIC_TETRA) s.order = 2;
  else throw InputError(path.string() + ": cells are neither VTK_TETRA nor VTK_QUADRATIC_TETRA");
  const vtkIdType np = grid->GetNumberOfPoints(), nc = grid->GetNumberOfCells();
  s.points_mm.resize(3, np);
  s.psi_Tmm.resize(np);
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    grid->GetPoint(i, p);
    s.points_mm.col(i) = Eigen::Vector3d(p[0], p[1], p[2]);
    s.psi_Tmm[i] = psi->GetValue(i);
  }
  const int nd = s.order == 1 ? 4 : 10;
  s.cell_dofs.resize(nd, nc);
  s.region.resize(nc);
  s.mu_r.resize(nc);
  s.br_T.resize(3, nc);
  for (vtkIdType c = 0; c < nc; ++c) {
    if (grid->GetCellType(c) != type) throw InputError(path.string() + ": mixed cell types");
    vtkIdType n;
    const vtkIdType* ids;
    grid->GetCellPoints(c, n, ids);
    if (n != nd) throw InputError(path.string() + ": cell with unexpected node count");
    for (int k = 0; k < nd; ++k) {
      if (ids[k] < 0 || ids[k] >= np) throw InputError(path.string() + ": a cell refers to a point that does not exist");
      s.cell_dofs(k, c) = static_cast<int>(ids[k]);
    }
    s.region[c] = region->GetValue(c);
    s.mu_r[c] = mu->GetValue(c);
    double b[3];
    br->GetTuple(c, b);
    s.br_T.col(c) = Eigen::Vector3d(b[0], b[1], b[2]);
  }
  if (!s.psi_Tmm.allFinite()) throw InputError(path.string() + ": psi contains NaN");
  auto* rec = vtkIntArray::SafeDownCast(grid->GetFieldData()->GetArray("gradient_recovery"));
  if (auto* src = vtkDoubleArray::SafeDownCast(grid->GetFieldData()->GetArray("reduced_potential_source"))) {
    const vtkIdType n = src->GetNumberOfTuples();
    if (n != 5 && n != 6)
      throw InputError(path.string() + ": reduced_potential_source must have 5 values (6 for a ring)");
    Magnet m;
    m.radius_mm = src->GetValue(0);
    m.height_mm = src->GetValue(1);
    m.br_T = src->GetValue(2);
    m.magnetization_deg = src->GetValue(3);
    m.magnetization_elevation_deg = src->GetValue(4);
    if (n == 6) m.inner_radius_mm = src->GetValue(5);
    m.mu_r = 1.0;
    try {
      s.source = std::make_shared<AnalyticField>(m);
    } catch (const InputError& e) {
      throw InputError(path.string() + ": reduced_potential_source: " + e.what());
    }
  }
  auto* total = vtkIntArray::SafeDownCast(grid->GetCellData()->GetArray("total_potential"));
  auto* phi_s = vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("interface_phi_s"));
  if (total || phi_s) {
    if (!total || !phi_s || !s.source || total->GetNumberOfTuples() != nc || phi_s->GetNumberOfTuples() != np)
      throw InputError(path.string() + ": split potential: total_potential (per cell), interface_phi_s (per point) and "
                       "reduced_potential_source must all be present and match the cells and points");
    s.cell_total.resize(static_cast<size_t>(nc));
    s.interface_phi_s_Tmm.resize(np);
    for (vtkIdType c = 0; c < nc; ++c) s.cell_total[static_cast<size_t>(c)] = total->GetValue(c) != 0;
    for (vtkIdType i = 0; i < np; ++i) s.interface_phi_s_Tmm[i] = phi_s->GetValue(i);
    if (!s.interface_phi_s_Tmm.allFinite()) throw InputError(path.string() + ": interface_phi_s contains NaN");
  }
  if (rec && rec->GetNumberOfTuples() > 0 && rec->GetValue(0) == 1) s.recover_gradient();
  return s;
}

}  // namespace magenc::fem
