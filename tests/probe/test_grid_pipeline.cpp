// Grid sources in the probe pipeline: the factory's grid: path (--interp),
// a synthetic plane.vti of the exact field reproducing the exact spectra,
// the nearest-neighbour 4th harmonic and its disappearance, error_spectrum's
// grid: CLI path and its out-of-region error.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "fields/analytic_field.hpp"
#include "core/errors.hpp"
#include "fields/field_factory.hpp"
#include "studies/harmonic_provenance/provenance.hpp"
#include "probe/common_keys.hpp"
#include "support/spectrum_compare.hpp"
#include "support/study_test_util.hpp"

using namespace magenc;

namespace {
std::filesystem::path scratch() {
  auto d = std::filesystem::temp_directory_path() / ("magenc_test_gridpipe_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}
}  // namespace

TEST_CASE("exact field sampled on a plane grid reproduces the exact spectra", "[probe][cross-check]") {
  const Config cfg(common_keys());
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  const auto dir = scratch();
  // h = 0.05 mm plane over [-3.5, 3.5] mm, as solve_field's default spacing.
  write_grid_vti(dir / "plane.vti", sample_grid(exact, Vec3(-3.5, -3.5, zs), Vec3(0.05, 0.05, 0.05), {141, 141, 1}, true));
  for (const std::string array : {"two", "diff4"}) {
    ProbeSetup setup;
    setup.array = ProbeArray::parse(array);
    setup.plane_z_mm = zs;
    FieldOptions opts;
    opts.interp = Interp::Cubic;
    const auto grid = make_field_source("grid:" + (dir / "plane.vti").string(), cfg, opts);
    CHECK(grid->name() == "grid");
    test::compare_spectra_per_eccentricity(exact, *grid, setup, 0.1, [&](const std::string& off, const Spectrum& se,
                                                                         const Spectrum& sg) {
      for (int n = 1; n <= 4; ++n) {
        CAPTURE(array, off, n, se.c_deg[n], sg.c_deg[n]);
        CHECK(std::abs(sg.c_deg[n] - se.c_deg[n]) <= std::max(0.02 * se.c_deg[n], 0.002));
        CHECK(std::abs(sg.c_deg[n] - se.c_deg[n]) < 1e-5);  // cubic at h = 0.05: far inside the acceptance
      }
    });
  }
  // A dz on a plane grid names box.vti.
  try {
    make_field_source("grid:" + (dir / "plane.vti").string(), cfg)->Bz_T(Vec3(2.4, 0, zs + 0.1));
    FAIL("no error off the plane");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("box.vti") != std::string::npos);
  }
  CHECK_THROWS_AS(make_field_source("grid:" + (dir / "missing.vti").string(), cfg), InputError);
  CHECK_THROWS_AS(make_field_source("grid:", cfg), InputError);
  CHECK_THROWS_AS(make_field_source("fem:/nonexistent", cfg), InputError);  // fem: is field_solver's (open_field_source)
  std::filesystem::remove_all(dir);
}

TEST_CASE("nearest-neighbour lookup makes a spurious 4th harmonic that better interpolation removes", "[probe][physics]") {
  const Config cfg(common_keys());
  const AnalyticField exact(Magnet::from_config(cfg));
  ProbeSetup setup;
  setup.array = ProbeArray::parse("two");
  setup.plane_z_mm = sensing_plane_z_mm(cfg);
  setup.steps = 3600;
  const auto rows = grid_sampling_scan(exact, setup, {{"ideal", Mount{}}}, {0.1, 0.05},
                                       {Interp::Nearest, Interp::Linear, Interp::Cubic}, 3.0);
  auto c4 = [&](double h, const std::string& mode) {
    for (const auto& r : rows)
      if (r.h_mm == h && r.interp == mode) return r.sampled.c_deg[4];
    return -1.0;
  };
  CAPTURE(c4(0.1, "nearest"), c4(0.05, "nearest"), c4(0.1, "linear"), c4(0.05, "linear"), c4(0.1, "cubic"),
          c4(0.05, "cubic"));
  CHECK(rows.front().exact.pp_deg < 1e-9);          // exact: no error at all
  CHECK(c4(0.1, "nearest") > 1e-3);                  // the study's artefact
  CHECK(c4(0.05, "cubic") < 1e-3 * c4(0.1, "nearest"));
  CHECK(c4(0.05, "cubic") < c4(0.1, "cubic"));       // vanishes under refinement
  CHECK(c4(0.05, "linear") < c4(0.1, "linear"));
}

TEST_CASE("error_spectrum --field grid: runs and refuses points outside the grid", "[probe][bad-input][cli]") {
  const Config cfg(common_keys());
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  const auto dir = scratch();
  write_grid_vti(dir / "plane.vti", sample_grid(exact, Vec3(-3, -3, zs), Vec3(0.05, 0.05, 0.05), {121, 121, 1}));
  const std::string bin = std::string(MAGENC_BIN_DIR) + "/error_spectrum";
  const std::string grid = " --field grid:" + (dir / "plane.vti").string();
  auto run = [&](const std::string& args, const std::string& out) {
    return std::system((bin + args + " --out " + (dir / out).string() + " 2> " + (dir / "err.txt").string()).c_str());
  };
  REQUIRE(run(grid + " --interp linear --dx 0.1", "grid.csv") == 0);
  REQUIRE(run(" --field analytic --dx 0.1", "exact.csv") == 0);
  // c1_deg of the first row of an error_spectrum CSV (throws when missing: the test fails).
  auto c1 = [&](const std::string& f) { return std::stod(test::read_csv(dir / f).at(0).at("c1_deg")); };
  CHECK(c1("grid.csv") == Approx(c1("exact.csv")).epsilon(1e-3));
  CHECK(run(grid + " --dx 0.1 --r0 3.5", "bad.csv") != 0);
  std::ifstream err(dir / "err.txt");
  const std::string msg((std::istreambuf_iterator<char>(err)), {});
  CHECK(msg.find("outside the sampled region") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "bad.csv"));
  std::filesystem::remove_all(dir);
}
