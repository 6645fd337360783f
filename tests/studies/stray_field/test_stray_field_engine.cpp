// Stray-field immunity (studies/stray_field/stray_field_engine.hpp) on the exact field, coarse grids:
//  * the worst direction of a uniform field on `two` is z and its c1 is docs/physics.md's 1.774 deg per mT;
//  * the tolerated field brackets the threshold: worst pp at the reported field <= threshold < worst pp
//    0.2 % above it;
//  * closed form for the one-spot principles in a small in-plane field b against the magnet's b0 at the
//    spot: the field direction turns by up to b/b0 (rad), pp = 2 b/b0, so pp <= t (deg) holds up to
//    b = b0 (t/2) pi/180 (to first order in b/b0, checked to 1 %);
//  * differential arrays do not see a homogeneous field at all, on a tilted die too (every probe of the
//    die reads the same n.B_stray, and the weights of each channel sum to zero);
//  * the conductor cases: along y the in-plane spot sees nothing, along z an untilted bz die sees nothing;
//  * the parallel directions give the numbers of one thread, bit for bit.
#include <catch2/catch.hpp>

#include <cmath>
#include <omp.h>

#include "studies/stray_field/stray_field_engine.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

const AnalyticField& exact_field() {
  static const AnalyticField f{Magnet{}};
  return f;
}

StrayFieldOptions coarse(std::vector<std::string> sensors) {
  StrayFieldOptions o;
  o.sensors = std::move(sensors);
  o.polar_points = 7;
  o.azimuth_points = 8;
  o.curve_points = 7;
  o.curve_min_mT = 0.01;
  o.curve_max_mT = 10;
  o.levels_kA_per_m = {1.0};
  o.wire_distances_mm = {10};
  o.wire_currents_A = {100};
  o.steps = 180;
  return o;
}

}  // namespace

TEST_CASE("stray_field analysis: worst direction, tolerated field and closed forms", "[studies][physics]") {
  const ProbeSetup base = test::probe_setup("two", 180);
  const StrayFieldOptions opt = coarse({"two", "diff4", "inplane", "xmr"});
  const StrayFieldResult r = run_stray_field(exact_field(), base, Mount{}, opt);
  REQUIRE(r.sensors.size() == 4);
  std::vector<Eigen::Vector3d> dirs;
  std::vector<double> pol, az;
  opt.directions(dirs, pol, az);
  REQUIRE(dirs.size() == 5 * 8 + 2);
  const auto& two = r.sensors[0];
  // 1 kA/m on `two`: worst along +-z, c1 = 1.774 deg/mT x 1.2566 mT (linear: 1 mT gives 1.774).
  CHECK(std::abs(two.levels[0].worst_dir.z()) == Approx(1.0));  // +z and -z tie
  CHECK(two.levels[0].c1_deg == Approx(1.774 * kmT_per_kA_per_m).epsilon(2e-3));
  for (const auto& s : r.sensors) {
    CAPTURE(s.label);
    REQUIRE(s.tolerated.size() == 2);
    for (const auto& t : s.tolerated) {
      CAPTURE(t.threshold_deg);
      if (s.label == "diff4") {
        CHECK(t.beyond);  // no direction of any magnitude up to search_max moves it
        continue;
      }
      REQUIRE_FALSE(t.beyond);
      REQUIRE(t.field_mT > 0);
      const ProbeSetup setup = [&] {
        ProbeSetup p = base;
        if (s.label != "two") {
          p.principle = parse_principle(s.label);
          p.array = ProbeArray::parse("point");
        }
        return p;
      }();
      CHECK(worst_over_directions(exact_field(), setup, Mount{}, t.field_mT, dirs).pp_deg <= t.threshold_deg);
      CHECK(worst_over_directions(exact_field(), setup, Mount{}, t.field_mT * 1.002, dirs).pp_deg > t.threshold_deg);
    }
  }
  // One-spot closed form: b0 = |(Bx, By)| at the spot on the ideal mount.
  const double b0_mT = 1e3 * std::abs(exact_field().B_T(Vec3(0, 0, 4.55)).x());
  for (std::size_t i : {std::size_t{2}, std::size_t{3}}) {
    CAPTURE(r.sensors[i].label);
    CHECK(r.sensors[i].tolerated[0].field_mT == Approx(b0_mT * 0.05 * kPi / 180).epsilon(0.01));
  }
  // Conductors: along y at the die's height its field is normal to the die (the spot sees nothing),
  // along z it lies in the die plane (an untilted bz die reads nothing).
  for (const auto& w : r.sensors[2].wires)
    if (w.orientation == "along y") CHECK(w.pp_deg < 1e-10);
  for (const auto& w : r.sensors[0].wires) {
    if (w.orientation == "along z") CHECK(w.pp_deg < 1e-10);
    else CHECK(w.pp_deg > 1.0);
    CHECK(w.field_mT == Approx(0.2 * 100 / 10));  // 0.2 mT mm/A x 100 A / 10 mm
  }
  // The direction maps: `two` is worst at the poles, indifferent at the equator (Bx, By unread).
  CHECK(r.sensors[0].map_pp_deg(0, 0) > 1.0);
  CHECK(r.sensors[0].map_pp_deg(3, 2) < 1e-10);
}

TEST_CASE("stray_field analysis: diff4 ignores a homogeneous field on a tilted die too", "[studies][physics]") {
  Mount m;
  m.tilt_x_deg = 2.0;
  const StrayFieldOptions opt = coarse({"diff4"});
  const StrayFieldResult r = run_stray_field(exact_field(), test::probe_setup("two", 180), m, opt);
  // The tilted die reads n.B: the same for every probe of a homogeneous field, so it cancels in the
  // differences; only the tilt's own error is left.
  REQUIRE(r.sensors.size() == 1);
  REQUIRE(r.sensors[0].base_pp_deg > 1e-3);
  CHECK(r.sensors[0].levels[0].pp_deg == Approx(r.sensors[0].base_pp_deg).margin(1e-9));
}

TEST_CASE("stray_field analysis: one thread and two give the same numbers", "[studies][determinism]") {
  // The directions and the direction map run in parallel; the worst direction is picked in the directions'
  // order afterwards, so the thread count cannot change a result, not even its last bit.
  const ProbeSetup base = test::probe_setup("two", 180);
  const StrayFieldOptions opt = coarse({"two", "xmr"});
  Mount m;
  m.sx_mm = 0.1;
  m.dy_mm = -0.05;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const StrayFieldResult one = run_stray_field(exact_field(), base, m, opt);
  omp_set_num_threads(2);
  const StrayFieldResult two = run_stray_field(exact_field(), base, m, opt);
  omp_set_num_threads(threads);
  REQUIRE(one.sensors.size() == two.sensors.size());
  for (std::size_t k = 0; k < one.sensors.size(); ++k) {
    const auto& a = one.sensors[k];
    const auto& b = two.sensors[k];
    CAPTURE(a.label);
    REQUIRE(a.curve.size() == b.curve.size());
    for (std::size_t i = 0; i < a.curve.size(); ++i) {
      CHECK(a.curve[i].pp_deg == b.curve[i].pp_deg);
      CHECK(a.curve[i].c1_deg == b.curve[i].c1_deg);
      CHECK(a.curve[i].max_c1_deg == b.curve[i].max_c1_deg);
      CHECK((a.curve[i].worst_dir.array() == b.curve[i].worst_dir.array()).all());
    }
    REQUIRE(a.tolerated.size() == b.tolerated.size());
    for (std::size_t i = 0; i < a.tolerated.size(); ++i) CHECK(a.tolerated[i].field_mT == b.tolerated[i].field_mT);
    CHECK((a.map_pp_deg.array() == b.map_pp_deg.array()).all());
  }
}
