// src/report/comparison_run.cpp: the FEM-vs-exact run of real_field and airgap, with
// exact fields standing in for the FEM sources (no solve needed):
//   - a "FEM" source that is the exact field itself differs from it by exactly 0;
//   - a source of another magnet (R = 2.3 mm) differs, and max_abs_difference
//     is the largest row-by-row difference of the compared cases;
//   - a single mount (plan.points) gives the same spectrum as that value in a sweep;
//   - row, fit and compared-case counts and order follow the header.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <unistd.h>

#include "fields/analytic_field.hpp"
#include "report/comparison_run.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "analysis/fem_comparison.hpp"
#include "analysis/sweep.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

ProbeSetup setup_of(const std::string& array) { return test::probe_setup(array, 128); }

Magnet magnet_with_radius(double r_mm) {
  Magnet m;
  m.radius_mm = r_mm;
  return m;
}

struct Fixture {
  AnalyticField exact{Magnet{}};
  std::vector<FemSource> sources{
      {"grid", "same magnet", std::make_shared<const AnalyticField>(Magnet{})},
      {"fem", "other magnet", std::make_shared<const AnalyticField>(magnet_with_radius(2.3))}};
  std::vector<ProbeSetup> setups{setup_of("two"), setup_of("diff4")};
  ComparisonPlan plan;
  Fixture() {
    const Mount base;
    plan.study = "unit";
    plan.fit_coefs = {"c1_deg", "c3_deg"};
    plan.ideal = base;
    plan.sweeps = {{"dx", "dx_mm", linspace(0.0, 0.2, 5), base}, {"sx", "sx_mm", linspace(0.0, 0.2, 5), base}};
    plan.points = {with_offset(base, "dx_mm", 0.1)};
  }
};

}  // namespace

TEST_CASE("run_comparison: counts and order of sweeps, rows, fits and compared cases", "[report][contract]") {
  const Fixture fx;
  const ComparisonRun run = run_comparison(fx.sources, fx.exact, fx.setups, fx.plan);
  REQUIRE(run.arrays.size() == 2);
  for (const auto& a : run.arrays) {
    REQUIRE(a.fem.size() == 2);
    CHECK(a.fem[0].label == "grid");
    CHECK(a.fem[1].label == "fem");
    CHECK(a.exact.label == "exact");
    const auto all = a.all();
    REQUIRE(all.size() == 3);
    CHECK(all.front() == &a.fem[0]);
    CHECK(all.back() == &a.exact);
    for (const SourceRun* sr : all) {
      CHECK(sr->ideal.has_value());
      CHECK(sr->points.size() == 1);
      REQUIRE(sr->sweeps.size() == 2);
      CHECK(sr->sweeps[1].spec.swept == "sx_mm");
      CHECK(sr->sweeps[0].setup.array.name == a.setup.array.name);
    }
  }
  CHECK(run.arrays[1].setup.array.name == "diff4");

  // Spectra rows: 2 arrays x 3 sources x (ideal + 2 sweeps x 5 values); FEM sources first, exact last.
  const auto rows = comparison_spectra_rows(run);
  REQUIRE(rows.size() == 2 * 3 * (1 + 2 * 5));
  const auto extra = [](const SpectrumRow& r, const std::string& name) {
    for (const auto& e : r.extra)
      if (e.first == name) return e.second;
    return std::string("<none>");
  };
  CHECK(extra(rows.front(), "sweep") == "ideal");
  CHECK(extra(rows.front(), "source") == "grid");
  CHECK(extra(rows[1], "sweep") == "dx");
  CHECK(extra(rows[11], "source") == "fem");
  CHECK(extra(rows[32], "source") == "exact");
  CHECK(rows[32].array == "two");
  CHECK(rows[33].array == "diff4");
  CHECK(extra(rows.back(), "sweep") == "sx");
  CHECK(rows.back().mount.sx_mm == Approx(0.2));

  // Fits: 2 arrays x 3 sources x 2 sweeps x 2 coefficients; compared: 2 arrays x 2 FEM sources x (1 + 10).
  CHECK(run.fits.size() == 2 * 3 * 2 * 2);
  REQUIRE(run.compared.size() == 2 * 2 * (1 + 2 * 5));
  CHECK(run.compared.front().sweep == "ideal");
  CHECK(run.compared.front().source == "grid");
  CHECK(run.compared[11].sweep == "ideal");
  CHECK(run.compared[11].source == "fem");

  // Plot inputs: first FEM source and exact per array; every FEM source per array.
  const auto sc = coefficient_cases(run, 1);
  REQUIRE(sc.size() == 4);
  CHECK(sc[0].label == "two grid");
  CHECK(sc[1].label == "two exact");
  CHECK(sc[1].sweep == &run.arrays[0].exact.sweeps[1]);
  const auto dc = difference_cases(run, 0);
  REQUIRE(dc.size() == 4);
  CHECK(dc[3].label == "diff4 fem");
  CHECK(dc[3].value == &run.arrays[1].fem[1].sweeps[0]);
  CHECK(dc[3].exact == &run.arrays[1].exact.sweeps[0]);
}

TEST_CASE("run_comparison: the exact field as a FEM source differs by 0, another magnet does not",
          "[report][cross-check]") {
  const Fixture fx;
  const ComparisonRun run = run_comparison(fx.sources, fx.exact, fx.setups, fx.plan);
  for (const auto& c : run.compared) {
    CAPTURE(c.array, c.sweep, c.x_mm, c.source);
    if (c.source == "grid")
      for (int n = 1; n <= 4; ++n) CHECK(c.value.c_deg[n] == c.exact.c_deg[n]);
  }
  const ArrayComparison& two = run.arrays[0];
  CHECK(max_abs_difference(two.fem[0].sweeps[0], two.exact.sweeps[0], "c1_deg") == 0.0);
  // R = 2.3 mm changes the field at r0 = 2.4 mm: dx gives a different c1 (a few % of ~2.5 deg at 0.1 mm).
  const double d = max_abs_difference(two.fem[1].sweeps[0], two.exact.sweeps[0], "c1_deg");
  CHECK(d > 1e-3);
  double worst = 0;
  for (const auto& c : run.compared)
    if (c.array == "two" && c.source == "fem" && c.sweep == "dx")
      worst = std::max(worst, std::abs(c.value.column("c1_deg") - c.exact.column("c1_deg")));
  CHECK(d == worst);
  // The ideal mount has no error on any exact field.
  CHECK(two.exact.ideal->spectrum.pp_deg < 1e-9);
  CHECK(two.fem[1].ideal->spectrum.pp_deg < 1e-9);

  // The single mount dx = 0.1 mm is the sweep's value at 0.1 mm (index 2 of 0, 0.05, ..., 0.2).
  for (const SourceRun* sr : two.all()) {
    CAPTURE(sr->label);
    CHECK(sr->points[0].spectrum.c_deg[1] == Approx(sr->sweeps[0].rows[2].spectrum.c_deg[1]).epsilon(1e-12));
  }

  // The markdown table: one row per sweep, array and FEM source, and the numbers above.
  const std::string md = max_difference_table(run, "offset", {"c1_deg"});
  CHECK(md.find("max abs diff c1") != std::string::npos);
  CHECK(std::count(md.begin(), md.end(), '\n') == 2 + 2 * 2 * 2);
  CHECK(md.find("| dx | `two` | fem | " + fmt(d, 5) + " |") != std::string::npos);
  CHECK(md.find("| dx | `two` | grid | 0.00000 |") != std::string::npos);
  CHECK(md.find("| sx | `two` | grid | 0.00000 |") != std::string::npos);  // each sweep against its own exact sweep
}

TEST_CASE("max_abs_difference: sweeps of different length are a ComputeError", "[report][bad-input]") {
  const AnalyticField exact{Magnet{}};
  const Mount base;
  const SweepResult a = run_sweep(exact, setup_of("two"), {"dx", "dx_mm", linspace(0.0, 0.1, 3), base});
  const SweepResult b = run_sweep(exact, setup_of("two"), {"dx", "dx_mm", linspace(0.0, 0.1, 4), base});
  CHECK(max_abs_difference(a, a, "c1_deg") == 0.0);
  CHECK_THROWS_AS(max_abs_difference(a, b, "c1_deg"), ComputeError);
}

