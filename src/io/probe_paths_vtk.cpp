#include "io/probe_paths_vtk.hpp"

#include <unistd.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include "core/errors.hpp"

namespace fs = std::filesystem;

namespace magenc {

void write_probe_paths_vtp(const fs::path& file, const Eigen::Matrix3Xd& positions_mm,
                           const Eigen::VectorXd& Bz_T, int probes_K, const Eigen::VectorXd& theta_deg) {
  // 1. Check the shapes: 3 x (M*K) positions, M*K readings, M angles.
  const Eigen::Index M = theta_deg.size();
  const Eigen::Index K = probes_K;
  const std::string where = "write_probe_paths_vtp(" + file.string() + "): ";
  if (K < 1) throw std::invalid_argument(where + "probes_K must be >= 1, got " + std::to_string(K));
  if (M < 1) throw std::invalid_argument(where + "theta_deg is empty");
  if (positions_mm.cols() != M * K)
    throw std::invalid_argument(where + "positions_mm has " + std::to_string(positions_mm.cols()) +
                                " columns, expected M*K = " + std::to_string(M * K));
  if (Bz_T.size() != M * K)
    throw std::invalid_argument(where + "Bz_T has " + std::to_string(Bz_T.size()) +
                                " entries, expected M*K = " + std::to_string(M * K));
  if (!positions_mm.allFinite() || !Bz_T.allFinite() || !theta_deg.allFinite())
    throw std::invalid_argument(where + "non-finite position, Bz or theta");

  // 2. Points and arrays, probe-major (point k*M + m = probe k at step m).
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(M * K);
  vtkNew<vtkDoubleArray> bz;
  bz->SetName("Bz");
  bz->SetNumberOfValues(M * K);
  vtkNew<vtkDoubleArray> theta;
  theta->SetName("theta_deg");
  theta->SetNumberOfValues(M * K);
  vtkNew<vtkIntArray> probe_pt;
  probe_pt->SetName("probe");
  probe_pt->SetNumberOfValues(M * K);
  for (Eigen::Index k = 0; k < K; ++k) {
    for (Eigen::Index m = 0; m < M; ++m) {
      const Eigen::Index col = m * K + k;   // input layout
      const vtkIdType id = k * M + m;       // output layout
      points->SetPoint(id, positions_mm(0, col), positions_mm(1, col), positions_mm(2, col));
      bz->SetValue(id, Bz_T(col));
      theta->SetValue(id, theta_deg(m));
      probe_pt->SetValue(id, static_cast<int>(k));
    }
  }

  // 3. One polyline per probe; closed (first point repeated at the end) when
  //    the angles are uniform steps over exactly one turn.
  bool full_turn = M >= 3;
  if (full_turn) {
    const double step = theta_deg(1) - theta_deg(0);
    for (Eigen::Index m = 1; m < M && full_turn; ++m)
      full_turn = std::abs(theta_deg(m) - theta_deg(m - 1) - step) <= 1e-9 * 360.0;
    full_turn = full_turn && std::abs(M * step - 360.0) <= 1e-9 * 360.0;
  }
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> probe_cell;
  probe_cell->SetName("probe");
  for (Eigen::Index k = 0; k < K; ++k) {
    lines->InsertNextCell(static_cast<vtkIdType>(full_turn ? M + 1 : M));
    for (Eigen::Index m = 0; m < M; ++m) lines->InsertCellPoint(k * M + m);
    if (full_turn) lines->InsertCellPoint(k * M);
    probe_cell->InsertNextValue(static_cast<int>(k));
  }

  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetLines(lines);
  poly->GetPointData()->AddArray(bz);
  poly->GetPointData()->AddArray(theta);
  poly->GetPointData()->AddArray(probe_pt);
  poly->GetPointData()->SetActiveScalars("Bz");
  poly->GetCellData()->AddArray(probe_cell);

  // 4. Write under a temporary name in the target directory, then rename.
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  const fs::path tmp = fs::path(file.string() + ".tmp." + std::to_string(::getpid()));
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetFileName(tmp.string().c_str());
  writer->SetInputData(poly);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  const int ok = writer->Write();
  std::error_code ec;
  if (ok != 1 || writer->GetErrorCode() != 0) {
    fs::remove(tmp, ec);
    throw ComputeError(where + "VTK could not write " + tmp.string());
  }
  fs::rename(tmp, file, ec);
  if (ec) {
    std::error_code ec2;
    fs::remove(tmp, ec2);
    throw ComputeError(where + "cannot rename " + tmp.string() + ": " + ec.message());
  }
}

void write_case_probe_paths_vtp(const std::filesystem::path& file, const ProbeSetup& setup, const Mount& mount,
                                const AngleErrorResult& result) {
  // probe_B_T is M x K; the file wants column m*K + k, as probe_paths_mm lays out positions.
  const Eigen::Index M = result.probe_B_T.rows(), K = result.probe_B_T.cols();
  Eigen::VectorXd bz(M * K);
  for (Eigen::Index m = 0; m < M; ++m)
    for (Eigen::Index k = 0; k < K; ++k) bz(m * K + k) = result.probe_B_T(m, k);
  write_probe_paths_vtp(file, probe_paths_mm(setup, mount), bz, static_cast<int>(K), result.theta_deg);
}

}  // namespace magenc
