// The distributed path: `mpirun -n 2 solve_field` (fem.solver = petsc-gamg)
// writes the same outputs as the 1-process solve, equal within the solver
// tolerance. mpirun runs as root in CI: --allow-run-as-root --oversubscribe.
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "field_solver/field_io/fem_field.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("magenc_test_mpi_" + std::to_string(::getpid())) / name;
  fs::create_directories(p.parent_path());
  fs::remove_all(p);
  return p;
}

int run(const std::string& prefix, const fs::path& out, const std::string& args) {
  // timeout: a rank left waiting must fail the test, not hang it.
  const std::string cmd = (prefix.empty() ? std::string() : "timeout 600 " + prefix) + std::string(MAGENC_BIN_DIR) + "/solve_field --config " + MAGENC_SOURCE_DIR +
                          "/meshes/coarse.toml --set fem.order=2 --set fem.solver=petsc-gamg --set output.mesh_vtu=true " +
                          args + " --out " + out.string() + " > " + out.string() + ".log 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<double> array_of(const fs::path& vti, const char* name) {
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(vti.c_str());
  reader->Update();
  auto* a = vtkDoubleArray::SafeDownCast(reader->GetOutput()->GetPointData()->GetArray(name));
  std::vector<double> v;
  if (a)
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i) v.push_back(a->GetValue(i));
  return v;
}

nlohmann::json json_of(const fs::path& f) {
  std::ifstream in(f);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("mpirun -n 2 solve_field writes the 1-process outputs within the solver tolerance", "[field_solver][cross-check][cli][mpi][slow]") {
  const std::string mpirun = std::string(MAGENC_MPIEXEC) + " -n 2 --allow-run-as-root --oversubscribe ";
  // The tolerance is tightened to 1e-12 so that the two CG runs (different
  // multigrid hierarchies: the aggregation is per rank) agree to ~1e-10 of B.
  const std::string args = GENERATE(std::string(""), std::string("--set mesh.symmetric=false"));
  CAPTURE(args);
  const fs::path one = scratch("np1"), two = scratch("np2");
  REQUIRE(run("", one, args + " --set fem.tolerance=1e-12") == 0);
  REQUIRE(run(mpirun, two, args + " --set fem.tolerance=1e-12") == 0);
  const auto j1 = json_of(one / "solve.json"), j2 = json_of(two / "solve.json");
  CHECK(j1.at("mpi_ranks") == 1);
  CHECK(j2.at("mpi_ranks") == 2);
  CHECK(j1.at("solved_dofs") == j2.at("solved_dofs"));
  CHECK(j2.at("residual").get<double>() < 1e-12);
  // Multigrid on 2 ranks: still tens of iterations.
  CHECK(j2.at("iterations").get<long>() < 2 * j1.at("iterations").get<long>() + 10);
  for (const char* f : {"plane.vti", "box.vti"}) {
    const auto b1 = array_of(one / f, "B"), b2 = array_of(two / f, "B");
    REQUIRE(b1.size() > 1000);
    REQUIRE(b1.size() == b2.size());
    double peak = 0, diff = 0;
    for (size_t i = 0; i < b1.size(); ++i) {
      peak = std::max(peak, std::abs(b1[i]));
      diff = std::max(diff, std::abs(b1[i] - b2[i]));
    }
    INFO(f << ": max |B(1 rank) - B(2 ranks)| / peak = " << diff / peak);
    // Both residuals < 1e-12; cond(K) ~ 1e5 bounds the difference by ~1e-7
    // of peak; a wrongly gathered or partitioned solution is O(1).
    CHECK(diff / peak < 1e-8);
  }
  // The 2-rank mesh.vtu reads back and evaluates like the 1-rank one.
  const magenc::FemField f1(one), f2(two);
  const magenc::Vec3 p(1.0, 0.5, 4.55);
  CHECK(f2.Bz_T(p) == Approx(f1.Bz_T(p)).margin(1e-10));
}

TEST_CASE("mpirun -n 2 solve_field: bad input is one error, non-zero exit, no output", "[field_solver][bad-input][cli][mpi]") {
  const std::string mpirun = std::string(MAGENC_MPIEXEC) + " -n 2 --allow-run-as-root --oversubscribe ";
  const fs::path out = scratch("bad");
  CHECK(run(mpirun, out, "--set magnet.radius_mm=0") != 0);
  CHECK_FALSE(fs::exists(out));
  const fs::path out2 = scratch("noconv");
  CHECK(run(mpirun, out2, "--set fem.max_iterations=1") != 0);
  CHECK_FALSE(fs::exists(out2));
  // Command-line errors and --help end every rank (no rank left waiting).
  const fs::path out3 = scratch("badflag");
  CHECK(run(mpirun, out3, "--no-such-flag") == 2);
  CHECK_FALSE(fs::exists(out3));
  CHECK(run(mpirun, scratch("help"), "--help") == 0);
}
