// src/analysis/sweep.cpp and the summary helpers of src/report/study_output.cpp.
#include <catch2/catch.hpp>

#include <cmath>

#include "fields/analytic_field.hpp"
#include "core/errors.hpp"
#include "report/study_output.hpp"
#include "analysis/sweep.hpp"
#include "core/units.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {
ProbeSetup two_setup(int steps = 720) { return test::probe_setup("two", steps); }
}  // namespace

TEST_CASE("linspace hits grid values exactly", "[analysis][closed-form]") {
  const auto v = linspace(0.0, 0.5, 26);
  REQUIRE(v.size() == 26);
  CHECK(v.front() == 0.0);
  CHECK(v.back() == 0.5);
  CHECK(v[5] == 0.1);
  CHECK_THROWS_AS(linspace(0, 1, 1), InputError);
}

TEST_CASE("with_offset sets exactly one offset", "[analysis]") {
  Mount base;
  base.dx_mm = 0.05;
  const Mount m = with_offset(base, "dz_mm", -0.3);
  CHECK(m.dz_mm == -0.3);
  CHECK(m.dx_mm == 0.05);
  CHECK(with_offset(base, "dx_mm", 0.2).dx_mm == 0.2);
  CHECK_THROWS_AS(with_offset(base, "r0_mm", 1), InputError);
  CHECK_THROWS_AS(with_offset(base, "tilt", 1), InputError);
  CHECK_THROWS_AS(check_coef_names({"c3_deg", "c9_deg"}, "sweep.coefs"), InputError);
  CHECK_NOTHROW(check_coef_names({"a0_deg", "b8_deg", "pp_deg"}, "sweep.coefs"));
}

TEST_CASE("sweep of sx on the linear field: rows, fit and first-order slope", "[analysis][closed-form]") {
  const LinearField field;
  const ProbeSetup setup = two_setup();
  const SweepResult s = run_sweep(field, setup, {"sx", "sx_mm", linspace(0, 0.2, 11), Mount{}});
  REQUIRE(s.rows.size() == 11);
  CHECK(s.rows[3].mount.sx_mm == Approx(0.06));
  CHECK(s.rows[3].extra.at(0).second == "sx");
  // Each row equals a direct pipeline run.
  Mount m;
  m.sx_mm = 0.06;
  CHECK(s.rows[3].spectrum.c_deg[2] == Approx(error_spectrum(field, setup, m).c_deg[2]).epsilon(1e-12));
  const auto fits = fit_sweep(s, "test", {"a0_deg", "c2_deg"});
  REQUIRE(fits.size() == 2);
  // First order in sx of atan2 for `two`: a0 = sx/(2 r0) rad.
  CHECK(fits[0].p[2] == Approx(rad_to_deg(1.0 / (2 * setup.r0_mm))).epsilon(1e-3));
  CHECK(std::abs(fits[0].p[3]) < 1e-3);
  CHECK(find_fit(fits, s, "c2_deg") == &fits[1]);
  CHECK(find_fit(fits, s, "c3_deg") == nullptr);
  // The cubic reproduces the computed points closely over this short range.
  const auto c2 = s.column("c2_deg");
  for (std::size_t i = 0; i < c2.size(); ++i) CHECK(eval_cubic(fits[1].p, s.spec.values_mm[i]) == Approx(c2[i]).margin(1e-4));
}

TEST_CASE("r0 sweeps change the probe radius, not the mount", "[analysis]") {
  const LinearField field;
  Mount base;
  base.sx_mm = 0.1;
  const SweepResult s = run_sweep(field, two_setup(), {"r0", "r0_mm", {2.0, 3.0}, base});
  CHECK(s.rows[0].r0_mm == 2.0);
  CHECK(s.rows[1].mount.sx_mm == 0.1);
  // a0 ~ sx/(2 r0): smaller at the larger radius.
  CHECK(std::abs(s.rows[1].spectrum.a0_deg) < std::abs(s.rows[0].spectrum.a0_deg));
}

TEST_CASE("summary helpers", "[analysis]") {
  CHECK(fmt(-0.0001, 3) == "0.000");
  CHECK(fmt(1.23456, 2) == "1.23");
  CHECK(fmt_auto(0.0, 4) == "0");
  CHECK(fmt_auto(0.01234, 4) == "0.0123");
  CHECK(fmt_auto(3.1e-6, 4) == "3.1e-06");
  Spectrum s;
  s.c_deg[1] = 2.5;
  s.c_deg[3] = 0.9;
  s.c_deg[4] = 0.01;
  s.c_deg[6] = 1e-5;
  const auto h = dominant_harmonics(s, 1e-4, 0.01, 4);
  REQUIRE(h.size() == 2);  // c4 = 0.01 < 0.01 * 2.5
  CHECK(h[0].n == 1);
  CHECK(h[1].n == 3);
  CHECK(harmonics_text(h, 2) == "c1 2.50, c3 0.90");
  Spectrum z;
  z.c_deg[8] = 2e-7;
  CHECK(harmonics_text(dominant_harmonics(z, 1e-4, 0.01, 4), z, 4) == "none (largest c8 = 2.0e-07)");
  CHECK(md_table({"a", "b"}, {{"1", "2"}}) == "| a | b |\n| --- | ---: |\n| 1 | 2 |\n");
}
