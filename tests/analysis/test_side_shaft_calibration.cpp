// The side-shaft ellipse under calibration (docs/physics.md "Ring magnets and sensors off the axis"): ogp's
// ellipse fit at the nominal mount finds the gain trim (its gain ratio is 1/k, k = A/B of the in-plane
// field), and its residual keeps the chip's direction and zero, so a backwards-turning, elliptic reading is
// corrected to nothing at the nominal mount and to the trimmed reading's error under an offset.
#include <catch2/catch.hpp>

#include <cmath>

#include "analysis/calibration.hpp"
#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"

using namespace magenc;

namespace {
ProbeSetup side_shaft() {
  ProbeSetup s;
  s.principle = SensorPrinciple::InPlane;
  s.array = ProbeArray::parse("point");
  s.plane_z_mm = 0.0;  // the ring's mid-plane (h = -2 mm, L = 4 mm)
  s.magnet_height_mm = 4.0;
  s.steps = 3600;
  s.center_mm = {18.0, 0.0};
  s.orientation.direction_auto = true;
  s.orientation.zero_auto = true;
  return s;
}
}  // namespace

TEST_CASE("ogp calibration of a side-shaft reading finds the gain trim k - 1 and keeps direction and zero",
          "[analysis][physics][cross-check]") {
  Magnet ring;
  ring.radius_mm = 16;
  ring.inner_radius_mm = 11;
  ring.height_mm = 4;
  ring.br_T = 1.2;
  const AnalyticField field(ring);
  const ProbeSetup raw = resolve_orientation(field, side_shaft());
  ProbeSetup trimmed_auto = side_shaft();
  trimmed_auto.orientation.gain_auto = true;
  const ProbeSetup trimmed = resolve_orientation(field, trimmed_auto);
  const AngleErrorResult nominal = angle_error(field, raw, Mount{});
  REQUIRE(nominal.spectrum.pp_deg > 70);  // the untrimmed ellipse (75.9 deg)
  const Correction ogp = calibrate(CalibrationMethod::parse("ogp"), nominal, raw.principle);
  // Two independent ways to the trim: the channels' first-harmonic ratio and the least-squares ellipse.
  CHECK(1.0 / ogp.ellipse.gain_ratio - 1.0 == Approx(trimmed.chain.gain_mismatch).epsilon(1e-9));
  CHECK(trimmed.chain.gain_mismatch == Approx(3.194679).margin(5e-7));
  CHECK(corrected(ogp, nominal).spectrum.pp_deg < 1e-8);
  Mount dx;
  dx.dx_mm = 0.05;
  const double with_ogp = corrected(ogp, angle_error(field, raw, dx)).spectrum.pp_deg;
  const double with_trim = angle_error(field, trimmed, dx).spectrum.pp_deg;
  INFO("dx 0.05 mm: ogp " << with_ogp << " deg, trim " << with_trim << " deg");
  CHECK(with_ogp == Approx(with_trim).epsilon(1e-6));
  CHECK(with_trim == Approx(0.48511).margin(5e-6));
}
