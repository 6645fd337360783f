// write_probe_paths_vtp (src/io/probe_paths_vtk.hpp): the .vtp file contract the
// ParaView state probe_paths.pvsm relies on, checked by reading the file back.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include "fields/analytic_field.hpp"
#include "io/probe_paths_vtk.hpp"
#include "core/units.hpp"

namespace fs = std::filesystem;

namespace {

// A synthetic case: K probes at angles 90k deg on a circle of radius r (mm),
// height z; Bz = 0.1*x T so every reading is traceable to its position.
struct Case {
  int M = 12, K = 2;
  double r = 2.4, z = 4.55;
  Eigen::Matrix3Xd pos;
  Eigen::VectorXd bz, theta;
  Case() {
    pos.resize(3, M * K);
    bz.resize(M * K);
    theta.resize(M);
    for (int m = 0; m < M; ++m) {
      theta(m) = 360.0 * m / M;
      for (int k = 0; k < K; ++k) {
        const double a = magenc::deg_to_rad(90.0 * k - theta(m));
        pos.col(m * K + k) << r * std::cos(a), r * std::sin(a), z;
        bz(m * K + k) = 0.1 * pos(0, m * K + k);
      }
    }
  }
};

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("magenc_test_probe_paths_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("probe paths .vtp: one polyline per probe with Bz, theta_deg, probe", "[vtk][probe]") {
  const Case c;
  const fs::path dir = temp_dir();
  const fs::path file = dir / "sub" / "paths_case.vtp";
  magenc::write_probe_paths_vtp(file, c.pos, c.bz, c.K, c.theta);
  REQUIRE(fs::exists(file));
  for (const auto& e : fs::directory_iterator(file.parent_path()))
    CHECK(e.path().filename() == "paths_case.vtp");  // no temp file left behind

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  REQUIRE(poly->GetNumberOfPoints() == c.M * c.K);
  REQUIRE(poly->GetNumberOfLines() == c.K);
  vtkDataArray* bz = poly->GetPointData()->GetArray("Bz");
  vtkDataArray* theta = poly->GetPointData()->GetArray("theta_deg");
  vtkDataArray* probe = poly->GetPointData()->GetArray("probe");
  vtkDataArray* probe_cell = poly->GetCellData()->GetArray("probe");
  REQUIRE(bz);
  REQUIRE(theta);
  REQUIRE(probe);
  REQUIRE(probe_cell);

  // Walk each polyline: its points are probe k in theta order, with the
  // position and reading of input column m*K + k.
  vtkNew<vtkIdList> ids;
  poly->GetLines()->InitTraversal();
  for (int k = 0; k < c.K; ++k) {
    REQUIRE(poly->GetLines()->GetNextCell(ids));
    REQUIRE(ids->GetNumberOfIds() == c.M + 1);  // one full turn: closed loop
    CHECK(ids->GetId(c.M) == ids->GetId(0));
    CHECK(probe_cell->GetTuple1(k) == k);
    for (int m = 0; m < c.M; ++m) {
      const vtkIdType id = ids->GetId(m);
      const int col = m * c.K + k;
      CAPTURE(k, m);
      double p[3];
      poly->GetPoint(id, p);
      CHECK(p[0] == Approx(c.pos(0, col)));
      CHECK(p[1] == Approx(c.pos(1, col)));
      CHECK(p[2] == Approx(c.pos(2, col)));
      CHECK(bz->GetTuple1(id) == Approx(c.bz(col)));
      CHECK(theta->GetTuple1(id) == Approx(c.theta(m)));
      CHECK(probe->GetTuple1(id) == k);
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("probe paths .vtp: a partial turn stays an open polyline", "[vtk][probe]") {
  const Case c;
  const fs::path dir = temp_dir();
  const fs::path file = dir / "half.vtp";
  const Eigen::VectorXd half_theta = 0.5 * c.theta;  // 0..165 deg: not one turn
  magenc::write_probe_paths_vtp(file, c.pos, c.bz, c.K, half_theta);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkNew<vtkIdList> ids;
  reader->GetOutput()->GetLines()->InitTraversal();
  REQUIRE(reader->GetOutput()->GetLines()->GetNextCell(ids));
  CHECK(ids->GetNumberOfIds() == c.M);
  fs::remove_all(dir);
}

TEST_CASE("probe paths .vtp: inconsistent shapes are rejected, nothing written", "[vtk][probe]") {
  const Case c;
  const fs::path dir = temp_dir();
  const fs::path file = dir / "bad.vtp";
  Eigen::VectorXd short_bz = c.bz.head(c.bz.size() - 1);
  CHECK_THROWS_AS(magenc::write_probe_paths_vtp(file, c.pos, short_bz, c.K, c.theta), std::invalid_argument);
  CHECK_THROWS_AS(magenc::write_probe_paths_vtp(file, c.pos, c.bz, 3, c.theta), std::invalid_argument);
  CHECK_THROWS_AS(magenc::write_probe_paths_vtp(file, c.pos, c.bz, 0, c.theta), std::invalid_argument);
  Eigen::VectorXd nan_bz = c.bz;
  nan_bz(3) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(magenc::write_probe_paths_vtp(file, c.pos, nan_bz, c.K, c.theta), std::invalid_argument);
  CHECK_FALSE(fs::exists(file));
  fs::remove_all(dir);
}

TEST_CASE("probe paths .vtp of a mounting case: each point carries the field the pipeline read there",
          "[vtk][probe]") {
  // write_case_probe_paths_vtp pairs probe_paths_mm with angle_error's readings
  // (M x K -> column m*K + k). On the exact field every stored Bz must equal the
  // field at the stored point; a transposed layout would break this.
  const magenc::AnalyticField field(magenc::Magnet{});
  magenc::ProbeSetup setup;
  setup.array = magenc::ProbeArray::parse("diff4");
  setup.steps = 90;
  magenc::Mount mount;
  mount.sx_mm = 0.3;
  mount.dx_mm = 0.2;
  const auto res = magenc::angle_error(field, setup, mount);
  const fs::path file = temp_dir() / "case.vtp";
  magenc::write_case_probe_paths_vtp(file, setup, mount, res);

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  REQUIRE(pd->GetNumberOfLines() == 4);
  REQUIRE(pd->GetNumberOfPoints() == 4 * 90);
  vtkDataArray* bz = pd->GetPointData()->GetArray("Bz");
  REQUIRE(bz != nullptr);
  double worst = 0;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i) {
    double p[3];
    pd->GetPoint(i, p);
    worst = std::max(worst, std::abs(bz->GetTuple1(i) - field.Bz_T(magenc::Vec3(p[0], p[1], p[2]))));
  }
  CHECK(worst < 1e-12);  // T; the same kernel at the same points (float32 points would show ~1e-9)
}
