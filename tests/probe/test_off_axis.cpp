// Ring magnets read off the axis (docs/physics.md "Ring magnets and sensors off the axis"): the
// side-shaft point sensor and Bz arrays around the bore, against the reference values and the
// ellipse law; the chip's direction, zero and gain trim ("auto"); refusals.
//
// Tolerances of the reference values: a value agrees with a reference when it lies within half a unit of
// the reference's last printed decimal (the reference is that rounding of the exact number), plus 1e-12.
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <string>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "probe/inplane_ellipse.hpp"

using namespace magenc;

namespace {

Magnet reference_ring() {
  Magnet m;
  m.radius_mm = 16;
  m.inner_radius_mm = 11;
  m.height_mm = 4;
  m.br_T = 1.2;
  return m;
}

// The side-shaft point sensor of the reference: inplane at [18, 0] on the mid-plane (h = -2 mm),
// direction -1, zero 180.
ProbeSetup side_shaft(double center_x_mm = 18.0) {
  ProbeSetup s;
  s.principle = SensorPrinciple::InPlane;
  s.array = ProbeArray::parse("point");
  s.plane_z_mm = 2.0 - 2.0;
  s.magnet_height_mm = 4.0;
  s.steps = 3600;
  s.center_mm = {center_x_mm, 0.0};
  s.orientation.direction = -1;
  s.orientation.zero_deg = 180.0;
  return s;
}

// Within half a unit of the last printed decimal of ref (given as printed, e.g. "0.052257").
void check_ref(double got, const std::string& ref, const std::string& what) {
  const std::size_t dot = ref.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(ref.size() - dot - 1);
  const double half_unit = 0.5 * std::pow(10.0, -decimals);
  INFO(what << ": " << got << " against " << ref << " (+-" << half_unit << ")");
  CHECK(std::abs(got - std::stod(ref)) <= half_unit + 1e-12);
}

}  // namespace

TEST_CASE("side-shaft sensor beside a ring reproduces the reference ellipse (k, c2, c4, pp)",
          "[probe][physics][regression]") {
  const AnalyticField field(reference_ring());
  const AngleErrorResult r = angle_error(field, side_shaft(), Mount{});
  check_ref(inplane_ellipse_k(r), "4.19468", "k");
  check_ref(r.spectrum.c_deg[2], "35.2364", "c2");
  check_ref(r.spectrum.c_deg[4], "10.8350", "c4");
  check_ref(r.spectrum.pp_deg, "75.9024", "pp");
  for (int n : {1, 3, 5, 7}) CHECK(r.spectrum.c_deg[n] < 1e-9);  // even harmonics only
  std::cout << "side-shaft reference: k " << inplane_ellipse_k(r) << ", c2 " << r.spectrum.c_deg[2] << ", c4 "
            << r.spectrum.c_deg[4] << ", pp " << r.spectrum.pp_deg << " deg\n";
}

TEST_CASE("side-shaft sensor after the gain trim: zero on the ideal mount, the reference residuals under offsets",
          "[probe][physics][regression]") {
  const AnalyticField field(reference_ring());
  ProbeSetup s = side_shaft();
  s.chain.gain_mismatch = 3.194679;  // k - 1 as physics.md prints it
  CHECK(angle_error(field, s, Mount{}).spectrum.pp_deg < 1e-5);  // k - 1 printed to 7 digits
  ProbeSetup exact = s;  // the trim by the exact k: nothing left
  exact.chain.gain_mismatch = inplane_ellipse_k(angle_error(field, side_shaft(), Mount{})) - 1.0;
  CHECK(angle_error(field, exact, Mount{}).spectrum.pp_deg < 1e-9);
  // The offsets with gain_mismatch = 3.194679 as the references were taken (a change of g by 5e-7 moves c2
  // by ~1.4e-5 deg, more than half a unit of the references' last digit).
  Mount dx;
  dx.dx_mm = 0.05;
  const Spectrum a = angle_error(field, s, dx).spectrum;
  check_ref(a.c_deg[1], "0.26898", "dx 0.05: c1");
  check_ref(a.c_deg[3], "0.07189", "dx 0.05: c3");
  check_ref(a.pp_deg, "0.48511", "dx 0.05: pp");
  Mount sx;
  sx.sx_mm = 0.2;
  const Spectrum b = angle_error(field, s, sx).spectrum;
  check_ref(b.c_deg[2], "0.67669", "sx 0.2: c2");
  check_ref(b.pp_deg, "1.35342", "sx 0.2: pp");
  Mount dz;
  dz.dz_mm = 0.5;
  const Spectrum c = angle_error(field, s, dz).spectrum;
  check_ref(c.c_deg[2], "0.41162", "dz 0.5: c2");
  check_ref(c.pp_deg, "0.82324", "dz 0.5: pp");
}

TEST_CASE("bore arrays above a ring reproduce the reference values (ring:4, ring:8, diff4)",
          "[probe][physics][regression]") {
  const AnalyticField field(reference_ring());
  auto bore = [&](const std::string& array, Mount mount) {
    ProbeSetup s;
    s.array = ProbeArray::parse(array);
    s.r0_mm = 13.5;
    s.plane_z_mm = 2.0 + 1.0;
    s.magnet_height_mm = 4.0;
    s.steps = 3600;
    return angle_error(field, s, mount).spectrum;
  };
  Mount sx;
  sx.sx_mm = 0.1;
  Mount dx;
  dx.dx_mm = 0.1;
  const Spectrum r4 = bore("ring:4", sx), r8 = bore("ring:8", sx), d4 = bore("diff4", dx);
  check_ref(r4.c_deg[2], "0.052257", "ring:4 sx 0.1: c2");
  check_ref(r4.pp_deg, "0.104514", "ring:4 sx 0.1: pp");
  check_ref(r8.c_deg[2], "0.011466", "ring:8 sx 0.1: c2");
  check_ref(r8.pp_deg, "0.022932", "ring:8 sx 0.1: pp");
  check_ref(d4.c_deg[4], "0.063700", "diff4 dx 0.1: c4");
  check_ref(d4.pp_deg, "0.127401", "diff4 dx 0.1: pp");
  // Below the ring (mirror image): Bz is odd in z, the zero moves by 180 deg and nothing else changes.
  ProbeSetup below;
  below.array = ProbeArray::parse("ring:8");
  below.r0_mm = 13.5;
  below.plane_z_mm = -3.0;
  below.magnet_height_mm = 4.0;
  below.orientation.zero_deg = 180.0;
  const Spectrum mirrored = angle_error(field, below, sx).spectrum;
  CHECK(mirrored.c_deg[2] == Approx(r8.c_deg[2]).epsilon(1e-9));
  CHECK(std::abs(mirrored.a0_deg - bore("ring:8", sx).a0_deg) < 1e-9);
}

TEST_CASE("the ellipse law: c2 = q rad, c4 = q^2/2 rad, no odd harmonics, peak atan((k-1)/(2 sqrt k)), across k",
          "[probe][physics][closed-form]") {
  const AnalyticField field(reference_ring());
  std::cout << "ellipse law (ring R 16, Ri 11, L 4; inplane point on the mid-plane):\n";
  double last_k = 1e9;
  for (double x : {16.5, 18.0, 21.0, 26.0, 40.0}) {
    const AngleErrorResult r = angle_error(field, side_shaft(x), Mount{});
    const double k = inplane_ellipse_k(r), q = (k - 1) / (k + 1);
    const double peak_deg = rad_to_deg(std::atan((k - 1) / (2 * std::sqrt(k))));
    INFO("centre x " << x << " mm: k " << k);
    CHECK(k < last_k);  // the ellipse flattens towards the ring
    last_k = k;
    CHECK(r.spectrum.c_deg[2] == Approx(rad_to_deg(q)).epsilon(1e-9));
    CHECK(r.spectrum.c_deg[4] == Approx(rad_to_deg(q * q / 2)).epsilon(1e-9));
    CHECK(r.spectrum.c_deg[6] == Approx(rad_to_deg(q * q * q / 3)).epsilon(1e-8));
    for (int n : {1, 3, 5, 7}) CHECK(r.spectrum.c_deg[n] < 1e-9);
    // The sampled maximum lies within 0.05 deg of the true peak's angle: its value is short of the peak by
    // at most (1/2) eps'' (0.05 deg)^2 < 1e-4 deg for these curves.
    CHECK(std::abs(0.5 * r.spectrum.pp_deg - peak_deg) < 1e-4);
    std::cout << "  x " << x << " mm: k " << k << ", q " << q << ", c2 " << r.spectrum.c_deg[2] << " deg (q rad "
              << rad_to_deg(q) << "), pp/2 " << 0.5 * r.spectrum.pp_deg << " deg (peak formula " << peak_deg << ")\n";
  }
}

TEST_CASE("direction, zero and gain trim 'auto' find -1, 180 deg and k - 1 on the nominal mount",
          "[probe][physics][closed-form]") {
  const AnalyticField field(reference_ring());
  const double k = inplane_ellipse_k(angle_error(field, side_shaft(), Mount{}));
  ProbeSetup s = side_shaft();
  s.orientation = ChipOrientation{};
  s.orientation.direction_auto = true;
  s.orientation.zero_auto = true;
  s.orientation.gain_auto = true;
  const ProbeSetup resolved = resolve_orientation(field, s);
  CHECK(resolved.orientation.direction == -1);
  CHECK(std::abs(wrap_deg(resolved.orientation.zero_deg - 180.0)) < 1e-9);
  CHECK(resolved.chain.gain_mismatch == Approx(k - 1).epsilon(1e-12));
  CHECK(!resolved.orientation.any_auto());
  // angle_error resolves by itself; the mount's offsets do not enter the resolution.
  Mount dx;
  dx.dx_mm = 0.05;
  const Spectrum a = angle_error(field, s, dx).spectrum;
  check_ref(a.c_deg[1], "0.26898", "auto, dx 0.05: c1");
  check_ref(a.pp_deg, "0.48511", "auto, dx 0.05: pp");
  // On the axis the defaults are what auto finds: direction 1 and (with the default magnet) zero 0.
  ProbeSetup axis;
  axis.array = ProbeArray::parse("two");
  axis.orientation.direction_auto = true;
  axis.orientation.zero_auto = true;
  const AnalyticField cyl{Magnet{}};
  const ProbeSetup on_axis = resolve_orientation(cyl, axis);
  CHECK(on_axis.orientation.direction == 1);
  CHECK(std::abs(on_axis.orientation.zero_deg) < 1e-9);
}

TEST_CASE("a sensing point in the ring's material, a bad direction or zero are refused, naming the keys",
          "[probe][bad-input]") {
  auto refused = [](const std::vector<std::string>& sets, const std::string& key) {
    Config cfg(common_keys());
    for (const auto& a : sets) cfg.set(a);
    try {
      (void)sensor_setup_from_config(cfg, cfg.str("sensor.array"));
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string what = e.what();
      INFO(what);
      CHECK(what.find(key) != std::string::npos);
      CHECK(what.find('\n') == std::string::npos);
    }
  };
  const std::vector<std::string> ring{"magnet.radius_mm=16", "magnet.inner_radius_mm=11", "magnet.height_mm=4"};
  auto with = [&](std::vector<std::string> v, const std::string& a) {
    v.push_back(a);
    return v;
  };
  refused(with(with(with(ring, "sensor.principle=inplane"), "sensor.center_mm=[13, 0]"), "sensor.plane_height_mm=-2"),
          "sensor.center_mm");
  refused(with(with(ring, "sensor.r0_mm=13"), "sensor.plane_height_mm=-1"), "sensor.plane_height_mm");
  CHECK_THROWS_AS([] {
    Config cfg(common_keys());
    cfg.set("sensor.direction=2");
  }(), InputError);
  refused({"sensor.center_mm=[1, 2, 3]"}, "sensor.center_mm");
  refused({"sensor.zero_deg=abc"}, "sensor.zero_deg");
  refused({"sensor.zero_deg=400"}, "sensor.zero_deg");
  // In the bore, beside the material or above it: accepted.
  Config ok(common_keys());
  for (const auto& a : with(with(ring, "sensor.r0_mm=9"), "sensor.plane_height_mm=-2")) ok.set(a);
  ok.set("sensor.direction=auto");
  ok.set("sensor.zero_deg=auto");
  const ProbeSetup s = sensor_setup_from_config(ok, "two");
  CHECK(s.orientation.direction_auto);
  CHECK(s.orientation.zero_auto);
  Config toml(common_keys());
  toml.load_toml_string("[sensor]\ndirection = -1\nzero_deg = 180\ncenter_mm = [18, 0]\n");
  const ChipOrientation o = ChipOrientation::from_config(toml);
  // config.toml echoes list keys as text: it reads back.
  Config echoed(common_keys());
  echoed.load_toml_string(toml.to_toml());
  CHECK(echoed.reals("sensor.center_mm") == std::vector<double>{18.0, 0.0});
  CHECK(echoed.str("sensor.direction") == "-1");
  CHECK(o.direction == -1);
  CHECK(o.zero_deg == 180.0);
}
