// The temperature sweep (studies/temperature/temperature_sweep.hpp) on the exact field, coarse:
//  * at 20 C each curve is the pipeline without environment (same numbers);
//  * without offsets and air-gap drift the error does not change with T (a ratio of channels) while the
//    field extremes scale with Br(T)/Br exactly;
//  * with offsets, c1 at T is c1 at 20 C with offsets/(Br(T)/Br) (docs/physics.md: oc 0.5 mT on `two`,
//    0.627 deg at 20 C, 0.713 deg with Br 12 % lower);
//  * the box p99 mount's pp at 20 C lies within the samples' range and near their 99th percentile.
#include <catch2/catch.hpp>

#include <cmath>

#include "studies/temperature/temperature_sweep.hpp"
#include "fields/analytic_field.hpp"
#include "probe/common_keys.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {
const AnalyticField& exact_field() {
  static const AnalyticField f{Magnet{}};
  return f;
}
TemperatureOptions coarse(std::vector<std::string> sensors) {
  TemperatureOptions o;
  o.sensors = std::move(sensors);
  o.temperature_min_C = -40;
  o.temperature_max_C = 120;
  o.temperature_step_K = 80;  // -40, 40, 120
  o.samples = 50;
  o.steps = 360;
  return o;
}
}  // namespace

TEST_CASE("temperature sweep: Br(T) alone cancels, offsets grow relative to the amplitude", "[studies][physics]") {
  TemperatureOptions opt = coarse({"two", "inplane"});
  opt.temperature_min_C = -40;
  opt.temperature_max_C = 120;
  opt.temperature_step_K = 20;  // includes 20 C and 120 C
  Mount m;
  m.sx_mm = 0.05;
  m.dx_mm = 0.03;
  const ProbeSetup base = test::probe_setup("two", 360);
  const TemperatureResult r = run_temperature_sweep(exact_field(), base, m, opt);
  REQUIRE(r.curves.size() == 4);  // per sensor: mount, box p99
  for (const auto& c : r.curves) {
    CAPTURE(c.sensor, c.mount_label);
    REQUIRE(c.points.size() == 9);
    const TemperaturePoint& p20 = c.points[3];
    REQUIRE(p20.temperature_C == 20);
    for (const auto& p : c.points) {
      CHECK(std::abs(p.spectrum.pp_deg - p20.spectrum.pp_deg) < 1e-9);  // Br alone cancels
      CHECK(p.field_min_mT == Approx(p.br_scale * p20.field_min_mT).epsilon(1e-12));
    }
  }
  // p20 equals the pipeline without any environment.
  CHECK(r.curves[0].points[3].spectrum.pp_deg == angle_error(exact_field(), base, m).spectrum.pp_deg);
  // The p99 sample: within the samples, pp at 20 C near the percentile.
  CHECK(r.curves[1].points[3].spectrum.pp_deg == Approx(r.p99_pp_deg[0]).epsilon(0.1));

  // Offsets: docs/physics.md reference, oc 0.5 mT on `two`, ideal mount: 0.627 at 20 C, 0.713 at 120 C.
  ProbeSetup oc = base;
  oc.chain.offset_cos_mT = 0.5;
  TemperatureOptions two = opt;
  two.sensors = {"two"};
  const TemperatureResult t = run_temperature_sweep(exact_field(), oc, Mount{}, two);
  CHECK(t.curves[0].points[3].spectrum.c_deg[1] == Approx(0.627).margin(0.0005));
  CHECK(t.curves[0].points[8].spectrum.c_deg[1] == Approx(0.713).margin(0.0005));
}

TEST_CASE("temperature sweep: bad options are refused", "[studies][bad-input]") {
  Config cfg(merge_schemas(common_keys(), TemperatureOptions::keys()));
  cfg.set("study.temperature_min_C=100");
  cfg.set("study.temperature_max_C=0");
  CHECK_THROWS_WITH(TemperatureOptions::from_config(cfg), Catch::Contains("study.temperature_min_C"));
  TemperatureOptions opt = coarse({"xmr"});
  CHECK_THROWS_WITH(run_temperature_sweep(exact_field(), test::probe_setup("two", 64), Mount{}, opt),
                    Catch::Contains("study.sensors"));
}
