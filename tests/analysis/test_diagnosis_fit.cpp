// diagnose's fit (src/analysis/diagnosis_fit): round trip on noiseless synthetic curves (exact field),
// sigma proportional to the noise, non-identifiable parameters reported, the default free set, the
// per-curve override syntax.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "analysis/diagnosis_fit.hpp"
#include "core/errors.hpp"
#include "fields/analytic_field.hpp"
#include "fields/magnet.hpp"

using namespace magenc;

namespace {

ModelState default_state(const std::string& array = "two") {
  ModelState s;
  s.setup.array = ProbeArray::parse(array);
  s.setup.r0_mm = 2.4;
  s.setup.plane_z_mm = 4.55;
  return s;
}

// Table values with some entries set: {"sx", 0.05}, ...
std::vector<double> values_with(const ModelState& base, std::initializer_list<std::pair<const char*, double>> set) {
  std::vector<double> v;
  for (const auto& p : fit_parameters()) v.push_back(p.get(base));
  for (const auto& [n, x] : set) v[fit_parameter_index(n)] = x;
  return v;
}

// A synthetic measured curve: model at `truth` + zero offset + scaled noise, at n non-uniform angles.
CurveInput synthetic(const FieldSource& field, const ModelState& base, const std::vector<double>& truth,
                     double zero_deg, int n, double noise_deg, unsigned seed = 7) {
  CurveInput c{{}, base, {}};
  c.curve.path = "synthetic";
  c.curve.format = "error_deg";
  c.curve.theta_deg.resize(n);
  c.curve.row.resize(n);
  for (int i = 0; i < n; ++i) {
    c.curve.theta_deg[i] = 360.0 * (i + 0.3 * std::sin(1.7 * i)) / n + 0.5;  // non-uniform, inside [0, 360)
    c.curve.row[i] = i + 2;
  }
  c.curve.error_deg = model_curve_deg(field, c, truth);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < n; ++i) c.curve.error_deg[i] += zero_deg + noise_deg * g(rng);
  return c;
}

const ParamValue& param(const DiagnosisResult& r, const std::string& json) {
  for (const auto& p : r.params)
    if (p.json_name == json) return p;
  FAIL("no parameter " << json);
  return r.params.front();
}

}  // namespace

TEST_CASE("diagnose: noiseless round trip recovers the offsets to high precision", "[analysis][cross-check]") {
  const AnalyticField field{Magnet{}};
  const ModelState base = default_state("two");
  const auto truth = values_with(base, {{"sx", 0.04}, {"sy", -0.03}, {"dx", 0.05}, {"dy", -0.02}});
  const std::vector<CurveInput> curves{synthetic(field, base, truth, 0.25, 120, 0.0)};
  DiagnosisOptions o;
  o.free = {"sx", "sy", "dx", "dy"};
  o.starts = 3;
  const DiagnosisResult r = diagnose_curves(field, curves, o);
  CAPTURE(r.residual_rms_deg, r.start_costs);
  CHECK(r.residual_rms_deg < 1e-8);
  CHECK(param(r, "sx_mm").value == Approx(0.04).margin(1e-8));
  CHECK(param(r, "sy_mm").value == Approx(-0.03).margin(1e-8));
  CHECK(param(r, "dx_mm").value == Approx(0.05).margin(1e-8));
  CHECK(param(r, "dy_mm").value == Approx(-0.02).margin(1e-8));
  CHECK(param(r, "zero_offset_deg").value == Approx(0.25).margin(1e-8));
  CHECK(param(r, "dz_mm").free == false);
  CHECK(r.not_identifiable.empty());
}

TEST_CASE("diagnose: sigma scales with the noise and covers the truth", "[analysis][physics]") {
  const AnalyticField field{Magnet{}};
  const ModelState base = default_state("two");
  const auto truth = values_with(base, {{"sx", 0.03}, {"dx", -0.04}});
  DiagnosisOptions o;
  o.free = {"sx", "sy", "dx", "dy"};
  o.starts = 2;
  const DiagnosisResult r1 = diagnose_curves(field, {synthetic(field, base, truth, 0.0, 200, 0.01)}, o);
  const DiagnosisResult r2 = diagnose_curves(field, {synthetic(field, base, truth, 0.0, 200, 0.02)}, o);
  for (const char* n : {"sx_mm", "sy_mm", "dx_mm", "dy_mm"}) {
    CAPTURE(n, param(r1, n).sigma, param(r2, n).sigma);
    REQUIRE(std::isfinite(param(r1, n).sigma));
    CHECK(param(r2, n).sigma / param(r1, n).sigma == Approx(2.0).epsilon(0.02));
    CHECK(std::abs(param(r1, n).value - truth[fit_parameter_index(n)]) < 4 * param(r1, n).sigma);
  }
  // The residual RMS estimates the noise (N = 200, 5 variables).
  CHECK(r1.residual_rms_deg == Approx(0.01).epsilon(0.15));
}

TEST_CASE("diagnose: a parameter with no effect at this point is reported, not given a sigma", "[analysis]") {
  const AnalyticField field{Magnet{}};
  const ModelState base = default_state("two");
  // Ideal mount: dz changes nothing to first order (a common scale cancels in atan2).
  const auto truth = values_with(base, {});
  const std::vector<CurveInput> curves{synthetic(field, base, truth, 0.0, 90, 0.001)};
  DiagnosisOptions o;
  o.free = {"sx", "dz"};
  o.starts = 1;
  const DiagnosisResult r = diagnose_curves(field, curves, o);
  REQUIRE(r.not_identifiable.size() == 1);
  CHECK(r.not_identifiable[0] == "dz_mm");
  CHECK(std::isinf(param(r, "dz_mm").sigma));
  CHECK(std::isfinite(param(r, "sx_mm").sigma));
  // At the ideal mount itself dz has no first-order effect: the default free set evaluated there
  // (nominal_shift 0) leaves dz out and says why.
  std::string note;
  o.nominal_shift = 0.0;
  const auto def = default_free_set(field, curves, o, &note);
  CHECK(std::find(def.begin(), def.end(), "dz") == def.end());
  CHECK(std::find(def.begin(), def.end(), "sx") != def.end());
  CHECK(std::find(def.begin(), def.end(), "dx") != def.end());
  CHECK_THAT(note, Catch::Contains("dz_mm: left out, it barely moves the curve"));
}

TEST_CASE("diagnose: linear field, dy has no effect and is confounded, multi-start finds the minimum",
          "[analysis][closed-form]") {
  const LinearField field;
  const ModelState base = default_state("two");
  const auto truth = values_with(base, {{"dx", 0.05}});
  const std::vector<CurveInput> curves{synthetic(field, base, truth, 0.0, 90, 0.0)};
  DiagnosisOptions o;
  o.free = {"dx", "dy"};
  o.starts = 4;
  const DiagnosisResult r = diagnose_curves(field, curves, o);
  CHECK(param(r, "dx_mm").value == Approx(0.05).margin(1e-7));
  REQUIRE(r.not_identifiable == std::vector<std::string>{"dy_mm"});
  REQUIRE(r.confounded.size() == 1);
  CHECK_THAT(r.confounded[0].text, Catch::Contains("dy_mm"));
}

TEST_CASE("diagnose: --curve-set syntax", "[analysis][bad-input]") {
  auto [c, o] = parse_curve_set("2:mount.dz_mm+=0.5", 2);
  CHECK(c == 1);
  CHECK(o.add);
  CHECK(o.value == 0.5);
  CHECK(fit_parameters()[o.param].json_name == "dz_mm");
  auto [c2, o2] = parse_curve_set("1:sx=-0.1", 2);
  CHECK(c2 == 0);
  CHECK_FALSE(o2.add);
  CHECK(o2.value == -0.1);
  CHECK_THROWS_AS(parse_curve_set("3:dz=0.1", 2), InputError);
  CHECK_THROWS_AS(parse_curve_set("1:foo=0.1", 2), InputError);
  CHECK_THROWS_AS(parse_curve_set("1:dz=abc", 2), InputError);
  CHECK_THROWS_AS(parse_curve_set("dz=1", 2), InputError);
}

TEST_CASE("diagnose: at r0 = 2.4 mm sx and sy differ only in DC, which the free zero offset absorbs, "
          "one curve cannot separate them, two air gaps can",
          "[analysis][physics]") {
  const AnalyticField field{Magnet{}};
  const ModelState base = default_state("two");
  const auto truth = values_with(base, {{"sx", 0.05}, {"gain", 0.01}});
  DiagnosisOptions o;
  o.free = {"sx", "sy", "gain"};
  o.starts = 3;
  CurveInput a = synthetic(field, base, truth, 0.1, 180, 0.005, 3);
  // One curve (exact field, r0 = 2.4 mm near the peak of Bz(r)): sx and sy give the same 2nd harmonic
  // and differ in DC only, which the free zero offset takes: the report names the three.
  const DiagnosisResult one = diagnose_curves(field, {a}, o);
  CAPTURE(one.not_identifiable, one.condition);
  REQUIRE_FALSE(one.not_identifiable.empty());
  CHECK(std::find(one.not_identifiable.begin(), one.not_identifiable.end(), "sx_mm") != one.not_identifiable.end());
  REQUIRE_FALSE(one.confounded.empty());
  CHECK_THAT(one.confounded[0].text, Catch::Contains("sx_mm") && Catch::Contains("sy_mm") &&
                                         Catch::Contains("zero_offset_deg") && Catch::Contains("load DC"));
  CHECK(std::isfinite(param(one, "gain_mismatch").sigma));
  // A second curve with the air gap 0.5 mm larger (known shift) and its own zero offset: the offsets'
  // harmonics change with the gap, so the joint fit separates sx, sy, the gain and both zero offsets.
  CurveInput b = synthetic(field, base, values_with(base, {{"sx", 0.05}, {"gain", 0.01}, {"dz", 0.5}}), -0.2, 180, 0.005, 4);
  b.overrides.push_back(parse_curve_set("2:dz+=0.5", 2).second);
  const DiagnosisResult two = diagnose_curves(field, {a, b}, o);
  CAPTURE(two.not_identifiable, two.condition);
  CHECK(two.not_identifiable.empty());
  CHECK(param(two, "sx_mm").value == Approx(0.05).margin(4 * param(two, "sx_mm").sigma));
  CHECK(param(two, "sy_mm").value == Approx(0.0).margin(4 * param(two, "sy_mm").sigma));
  CHECK(param(two, "gain_mismatch").value == Approx(0.01).margin(4 * param(two, "gain_mismatch").sigma));
  CHECK(param(two, "sx_mm").sigma < 0.005);
  CHECK(param(two, "zero_offset_deg_2").value == Approx(-0.2).margin(0.05));
}

TEST_CASE("diagnose: default free set of `two` at the ideal mount is what docs/physics.md predicts", "[analysis][physics]") {
  // sx, sy (DC + 2nd harmonic), dx, dy (1st + 3rd); sensor tilt, gain and phase are combinations of sx, sy
  // and the zero offset; dz has no first-order effect; of magnet tilt and channel offsets (1st harmonic)
  // only as many as the 1st/3rd-harmonic content leaves room for.
  const AnalyticField field{Magnet{}};
  const ModelState base = default_state("two");
  const std::vector<CurveInput> curves{synthetic(field, base, values_with(base, {}), 0.0, 180, 0.0)};
  std::string note;
  const auto def = default_free_set(field, curves, DiagnosisOptions{}, &note);
  CAPTURE(def, note);
  for (const char* n : {"sx", "sy", "dx", "dy"}) CHECK(std::find(def.begin(), def.end(), n) != def.end());
  for (const char* n : {"dz", "tilt_x", "tilt_y", "gain", "phase"}) CHECK(std::find(def.begin(), def.end(), n) == def.end());
  CHECK_THAT(note, Catch::Contains("gain_mismatch: left out"));
}

TEST_CASE("diagnose fits the one-spot principles: AMR relative offsets round trip, mT offsets do not apply",
          "[analysis][cross-check]") {
  const AnalyticField field{Magnet{}};
  ModelState base = default_state("point");
  base.setup.principle = SensorPrinciple::Amr;
  // Truth: a static eccentricity and a relative cos-channel offset (AMR: c2 of o/2 rad beside sx's c2).
  const auto truth = values_with(base, {{"dx", 0.05}, {"offset_cos_rel", 0.004}, {"offset_sin_rel", -0.002}});
  const CurveInput c = synthetic(field, base, truth, 0.0, 180, 0.0);
  DiagnosisOptions o;
  o.free = {"offset_cos_rel", "offset_sin_rel", "offset_cos"};
  o.starts = 1;
  const DiagnosisResult r = diagnose_curves(field, {c}, o);
  CHECK(param(r, "offset_cos_rel").value == Approx(0.004).margin(1e-7));
  CHECK(param(r, "offset_sin_rel").value == Approx(-0.002).margin(1e-7));
  CHECK(r.residual_rms_deg < 1e-6);
  // offset_cos (mT) has no effect on amr: reported, not fitted into a value.
  CHECK(std::find(r.not_identifiable.begin(), r.not_identifiable.end(), "offset_cos_mT") != r.not_identifiable.end());
  // The default free set on inplane never contains the relative offsets (they do not apply there).
  ModelState ip = default_state("point");
  ip.setup.principle = SensorPrinciple::InPlane;
  const CurveInput ci = synthetic(field, ip, values_with(ip, {{"offset_cos", 0.5}}), 0.0, 180, 0.0);
  DiagnosisOptions od;
  const auto set = default_free_set(field, {ci}, od, nullptr);
  CHECK(std::find(set.begin(), set.end(), "offset_cos_rel") == set.end());
  CHECK(std::find(set.begin(), set.end(), "offset_cos") != set.end());
}

TEST_CASE("diagnose: a fit says whether it converged and whether it explains the curve", "[analysis][bad-input]") {
  const AnalyticField field{Magnet{}};
  const ModelState base = default_state("two");
  DiagnosisOptions o;
  o.free = {"sx", "sy", "dx", "dy"};
  o.starts = 2;
  // A curve the model makes (plus noise): converged, explained, nothing to report.
  const auto truth = values_with(base, {{"sx", 0.03}, {"dx", -0.04}});
  const DiagnosisResult good = diagnose_curves(field, {synthetic(field, base, truth, 0.1, 200, 0.005)}, o);
  CHECK(good.converged);
  CHECK(good.explained_fraction > 0.99);
  CHECK(good.unexplained.empty());
  // Noise alone (a well-mounted encoder): nothing to explain, and still no failure: the residual is noise,
  // 8 harmonics of 200 samples hold about 16 / 200 of its power.
  const DiagnosisResult noise = diagnose_curves(field, {synthetic(field, base, values_with(base, {}), 0.0, 200, 0.01)}, o);
  CAPTURE(noise.explained_fraction, noise.residual_harmonic_share);
  CHECK(noise.residual_harmonic_share < 0.25);
  CHECK(noise.unexplained.empty());
  // A 0.5 deg 7th harmonic (no mounting offset of `two` makes one): explained less than half, the residual
  // all harmonics: the fit is no diagnosis.
  CurveInput seventh = synthetic(field, base, values_with(base, {}), 0.0, 200, 0.001);
  for (Eigen::Index i = 0; i < seventh.curve.error_deg.size(); ++i)
    seventh.curve.error_deg[i] += 0.5 * std::sin(7 * seventh.curve.theta_deg[i] * M_PI / 180);
  const DiagnosisResult bad = diagnose_curves(field, {seventh}, o);
  CAPTURE(bad.explained_fraction, bad.residual_harmonic_share, bad.unexplained);
  CHECK(bad.explained_fraction < 0.1);
  CHECK(bad.residual_harmonic_share > 0.9);
  CHECK(bad.unexplained.find("diagnose: the fit leaves a residual RMS of ") == 0);
  CHECK(bad.unexplained.find("in harmonics 1..8") != std::string::npos);
  CHECK(bad.unexplained.find('\n') == std::string::npos);
  // An optimizer stopped at its iteration cap says so.
  DiagnosisOptions capped = o;
  capped.max_iterations = 1;
  capped.starts = 1;
  const DiagnosisResult stopped = diagnose_curves(field, {synthetic(field, base, truth, 0.1, 200, 0.005)}, capped);
  CHECK_FALSE(stopped.converged);
  CHECK(stopped.termination.find("iterations") != std::string::npos);
}
