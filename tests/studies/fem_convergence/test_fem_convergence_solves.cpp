// run_fem_convergence (studies/fem_convergence/fem_convergence_solves.hpp): its input checks come
// before any solve, and a tiny refinement (P1, two zone edges, no side runs)
// returns errors that fall under refinement at a positive observed rate.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <string>

#include "studies/fem_convergence/fem_convergence_solves.hpp"
#include "core/errors.hpp"
#include "probe/common_keys.hpp"

using namespace magenc;

namespace {
Config tiny_config() {
  Config cfg(merge_schemas(common_keys(), fem::fem_convergence_keys()));
  for (const char* s : {"convergence.h_zone_list=1.0,0.7", "convergence.orders=1", "convergence.faceting_segments=",
                        "convergence.truncation_radii=", "convergence.potential_mu_r=0", "convergence.shaft_mu_r=0",
                        "grid.plane_step_mm=0.25", "mesh.outer_radius_mm=30"})
    cfg.set(s);
  return cfg;
}

// The InputError's text of run_fem_convergence(cfg), and how long it took to come.
std::string input_error(const Config& cfg, double& seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    fem::run_fem_convergence(cfg);
  } catch (const InputError& e) {
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return e.what();
  }
  seconds = 0;
  return "";
}
}  // namespace

TEST_CASE("run_fem_convergence refuses bad input before the first solve", "[studies][bad-input]") {
  double seconds = 0;
  SECTION("one zone edge length") {
    Config cfg = tiny_config();
    cfg.set("convergence.h_zone_list=0.7");
    const std::string what = input_error(cfg, seconds);
    CHECK(what == "convergence.h_zone_list needs at least 2 sizes");
  }
  SECTION("potential_mu_r in (0, 1)") {
    Config cfg = tiny_config();
    cfg.set("convergence.potential_mu_r=0.5");
    const std::string what = input_error(cfg, seconds);
    CHECK(what == "convergence.potential_mu_r = 0.500 must be 0 (skip) or >= 1");
  }
  SECTION("shaft_mu_r in (0, 1)") {
    Config cfg = tiny_config();
    cfg.set("convergence.shaft_mu_r=0.25");
    const std::string what = input_error(cfg, seconds);
    CHECK(what == "convergence.shaft_mu_r = 0.250 must be 0 (skip) or >= 1");
  }
  // No solve ran (a P1 solve of this mesh takes about a second).
  CHECK(seconds < 0.5);
}

TEST_CASE("run_fem_convergence: P1 errors fall from h 1.0 to 0.7 at a positive rate", "[studies][convergence]") {
  const FemConvergenceResult r = fem::run_fem_convergence(tiny_config());
  REQUIRE(r.refinement.size() == 1);
  const auto& s = r.refinement[0];
  CHECK(s.order == 1);
  REQUIRE(s.runs.size() == 2);
  CHECK(s.runs[0].h_zone_mm == 1.0);
  CHECK(s.runs[1].h_magnet_mm == Approx(1.4));  // h_magnet_factor 2
  CHECK(std::isnan(s.runs[0].rate_h));
  CHECK(s.runs[1].dofs > s.runs[0].dofs);
  CAPTURE(s.runs[0].rms_rel, s.runs[1].rms_rel, s.runs[1].rate_h);
  CHECK(s.runs[1].rms_rel < s.runs[0].rms_rel);
  CHECK(s.runs[1].rate_h > 0.3);  // theory for B with P1: 1
  CHECK(s.runs[0].rms_rel < 0.1);
  CHECK(r.faceting.empty());
  CHECK(r.truncation.empty());
  CHECK_FALSE(r.reduced.ran());
  CHECK_FALSE(r.shaft.ran());
  CHECK(r.plane_step_mm == 0.25);
  CHECK(r.plane_z_mm == Approx(4.55));
}
