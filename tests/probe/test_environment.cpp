// Stray fields and temperature (docs/physics.md "Environment: stray fields and temperature"):
// docs/physics.md's reference values, the conductor's field against a Biot-Savart quadrature over a
// long finite segment, linearity of the error in small stray fields, a uniform Bz stray field on
// `two` as channel offsets, the Br(T) scaling of readings and of offset/amplitude, the material
// library, the field window at the temperature, and bad input.
//
// Closed forms used below:
//  * `two` reads Bz at beta = 0 (cos channel) and 90 deg (sin channel); a uniform Bz stray field b adds
//    b to both probes, i.e. it is exactly the channel offsets oc = os = b of the signal chain.
//  * Br(T) scales the magnet's field: every reading of the ideal mount at T is (1 + tc (T - 20)) times
//    the reading at 20 C (to rounding); with an offset o the error depends on o / A only, so a run at T
//    equals a run at 20 C with the offset o / (1 + tc (T - 20)).
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <string>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "probe/environment.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

const AnalyticField& exact_field() {
  static const AnalyticField f{Magnet{}};
  return f;
}

ProbeSetup setup_for(const std::string& array, SensorPrinciple p = SensorPrinciple::Bz, int steps = 3600) {
  ProbeSetup s = test::probe_setup(array, steps);
  s.principle = p;
  return s;
}

ProbeSetup point_setup(SensorPrinciple p, int steps = 3600) { return setup_for("point", p, steps); }

double c1(const ProbeSetup& s, const Mount& m = Mount{}) { return angle_error(exact_field(), s, m).spectrum.c_deg[1]; }

bool one_line(const std::string& s) { return s.find('\n') == std::string::npos; }

}  // namespace

TEST_CASE("stray fields: docs/physics.md reference values", "[probe][physics][regression]") {
  SECTION("uniform Bz 1 mT") {
    ProbeSetup two = setup_for("two"), diff4 = setup_for("diff4");
    two.env.stray.uniform_mT = {0, 0, 1};
    diff4.env.stray.uniform_mT = {0, 0, 1};
    CHECK(c1(two) == Approx(1.774).margin(0.0005));
    const AngleErrorResult d = angle_error(exact_field(), diff4, Mount{});
    CHECK(d.eps_deg.cwiseAbs().maxCoeff() < 1e-10);  // the differences cancel a homogeneous field exactly
  }
  SECTION("uniform Bx 5 mT on the inplane point") {
    ProbeSetup s = point_setup(SensorPrinciple::InPlane);
    s.env.stray.uniform_mT = {5, 0, 0};
    CHECK(c1(s) == Approx(5.632).margin(0.0005));
  }
  SECTION("100 A along y through (10, 0, 4.55) mm") {
    StrayField wire;
    wire.wire_current_A = 100;
    wire.wire_point_mm = {10, 0, 4.55};
    wire.wire_direction = {0, 1, 0};
    ProbeSetup two = setup_for("two"), diff4 = setup_for("diff4"), inplane = point_setup(SensorPrinciple::InPlane);
    two.env.stray = diff4.env.stray = inplane.env.stray = wire;
    CHECK(c1(diff4) == Approx(0.639).margin(0.0005));
    CHECK(c1(two) == Approx(4.147).margin(0.0005));
    // The conductor's field is along z at the die (normal to it): the in-plane spot sees nothing.
    CHECK(angle_error(exact_field(), inplane, Mount{}).eps_deg.cwiseAbs().maxCoeff() < 1e-10);
  }
}

TEST_CASE("conductor field: the closed form against a Biot-Savart sum over a long finite segment",
          "[probe][physics][cross-check]") {
  // B = (mu0 / 4 pi) I int dl x (p - l) / |p - l|^3 over the segment l = a + t u, t in [-T, T], by
  // Gauss-Legendre in the substitution t = d tan(s) (which makes the integrand smooth). A segment of
  // half-length T misses the tails, a relative part (d/T)^2 / 2 of the infinite conductor's field:
  // with T = 1e4 d that is 5e-9; 200 nodes make the quadrature error far smaller. Tolerance 1e-7.
  const double I_A = 37.5;
  const Eigen::Vector3d a(1.0, -2.0, 3.0);
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 2, -0.5), Eigen::Vector3d(0, 0, 1)}) {
    const Eigen::Vector3d u = dir.normalized();
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(2.4, 0, 4.55), Eigen::Vector3d(-7, 3, 0.2)}) {
      const Eigen::Vector3d r = p - a;
      const Eigen::Vector3d foot = a + u.dot(r) * u;  // the point of the line nearest p
      const double d = (p - foot).norm();
      const double s_max = std::atan(1e4);
      std::vector<double> x, w;
      gauss_legendre(200, x, w);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double s = s_max * x[i];
        const double t = d * std::tan(s), dt_ds = d / (std::cos(s) * std::cos(s));
        const Eigen::Vector3d l = foot + t * u;
        const Eigen::Vector3d q = p - l;
        sum += w[i] * s_max * dt_ds * u.cross(q) / std::pow(q.norm(), 3);
      }
      const Eigen::Vector3d biot_savart_mT = 0.1 * I_A * sum;  // mu0 / 4 pi = 0.1 mT mm / A
      StrayField st;
      st.wire_current_A = I_A;
      st.wire_point_mm = a;
      st.wire_direction = dir;
      const Eigen::Vector3d closed = st.B_mT(p);
      CAPTURE(dir.transpose(), p.transpose(), closed.transpose(), biot_savart_mT.transpose());
      CHECK((closed - biot_savart_mT).norm() < 1e-7 * closed.norm());
      CHECK(std::abs(closed.norm() - 0.2 * I_A / d) < 1e-12 * closed.norm());  // |B| = mu0 I / (2 pi d)
      CHECK(std::abs(closed.dot(u)) < 1e-12 * closed.norm());                  // no part along the wire
    }
  }
}

TEST_CASE("stray fields: the error is linear in a small stray field", "[probe][physics]") {
  // eps(2 b) = 2 eps(b) + O(b^2): with |b| = 0.01 mT against an amplitude near 50 mT the quadratic
  // remainder is about (b/A) of the linear part, 2e-4 of it; checked at 2e-3 of max|eps(b)|.
  const Eigen::Vector3d dir = Eigen::Vector3d(1, -2, 3).normalized();
  struct Case {
    std::string array;
    SensorPrinciple p;
  };
  for (const Case& c : {Case{"two", SensorPrinciple::Bz}, Case{"diff4", SensorPrinciple::Bz},
                        Case{"ring:8", SensorPrinciple::Bz}, Case{"point", SensorPrinciple::InPlane},
                        Case{"point", SensorPrinciple::Xmr}, Case{"point", SensorPrinciple::Amr}}) {
    CAPTURE(c.array, principle_name(c.p));
    Mount m;
    m.sx_mm = 0.05;  // a mount with its own error, so the stray field's part rides on a non-zero curve
    ProbeSetup s = setup_for(c.array, c.p, 720);
    const Eigen::VectorXd e0 = angle_error(exact_field(), s, m).eps_deg;
    for (bool wire : {false, true}) {
      CAPTURE(wire);
      auto eps_at = [&](double scale) {
        ProbeSetup t = s;
        if (wire) {
          t.env.stray.wire_current_A = 2.0 * scale;  // 2 A at 10 mm: 0.04 mT, a gradient across the die
          t.env.stray.wire_point_mm = {0, 10, 4.0};
          t.env.stray.wire_direction = {1, 0.3, 0.2};
        } else {
          t.env.stray.uniform_mT = 0.01 * scale * dir;
        }
        return Eigen::VectorXd(angle_error(exact_field(), t, m).eps_deg - e0);
      };
      const Eigen::VectorXd e1 = eps_at(1.0), e2 = eps_at(2.0);
      if (!wire && (c.array == "diff4" || c.array == "ring:8")) {  // their weights cancel a homogeneous field
        CHECK(e1.cwiseAbs().maxCoeff() < 1e-10);
        continue;
      }
      REQUIRE(e1.cwiseAbs().maxCoeff() > 1e-4);  // the stray field does something
      CHECK((e2 - 2.0 * e1).cwiseAbs().maxCoeff() < 2e-3 * e1.cwiseAbs().maxCoeff());
    }
  }
}

TEST_CASE("stray fields: uniform Bz on two is the channel offsets oc = os = Bz", "[probe][cross-check]") {
  for (double b_mT : {0.3, -2.0}) {
    Mount m;
    m.dx_mm = 0.07;
    m.sy_mm = -0.04;
    ProbeSetup stray = setup_for("two", SensorPrinciple::Bz, 720), offsets = stray;
    stray.env.stray.uniform_mT = {0.4, -0.7, b_mT};  // Bx, By are not read by an untilted bz die
    offsets.chain.offset_cos_mT = offsets.chain.offset_sin_mT = b_mT;
    const AngleErrorResult a = angle_error(exact_field(), stray, m), b = angle_error(exact_field(), offsets, m);
    CHECK((a.eps_deg - b.eps_deg).cwiseAbs().maxCoeff() < 1e-12);
    // The linear source (Bz only) takes a stray field too.
    const LinearField lin(10.0);
    const AngleErrorResult la = angle_error(lin, stray, m), lb = angle_error(lin, offsets, m);
    CHECK((la.eps_deg - lb.eps_deg).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("stray fields: a tilted die reads the stray field along its own axes", "[probe][physics]") {
  // A uniform field along x seen by a bz die tilted by a about y: n = (sin a, 0, cos a), each probe
  // reads Bx sin a; the same as offsets oc = os = Bx sin a on an untilted-stray run of the same mount.
  Mount m;
  m.tilt_y_deg = 3.0;
  ProbeSetup stray = setup_for("two", SensorPrinciple::Bz, 720), offsets = stray;
  stray.env.stray.uniform_mT = {2.0, 0, 0};
  offsets.chain.offset_cos_mT = offsets.chain.offset_sin_mT = 2.0 * std::sin(3.0 * kPi / 180.0);
  const AngleErrorResult a = angle_error(exact_field(), stray, m), b = angle_error(exact_field(), offsets, m);
  CHECK((a.eps_deg - b.eps_deg).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("stray fields: bad input is one line naming the key", "[probe][bad-input]") {
  const Mount m;
  auto refuses = [&](const ProbeSetup& s, const std::string& key) {
    try {
      angle_error(exact_field(), s, m);
      FAIL("accepted " << key);
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CAPTURE(msg);
      CHECK(msg.find(key) != std::string::npos);
      CHECK(msg.find("allowed") != std::string::npos);
      CHECK(one_line(msg));
    }
  };
  ProbeSetup s = setup_for("two", SensorPrinciple::Bz, 64);
  ProbeSetup t = s;
  t.env.stray.uniform_mT = {0, std::nan(""), 0};
  refuses(t, "stray.uniform_mT");
  t = s;
  t.env.stray.uniform_mT = {0, 0, INFINITY};
  refuses(t, "stray.uniform_mT");
  t = s;
  t.env.stray.wire_current_A = 1;
  t.env.stray.wire_direction = {0, 0, 0};
  refuses(t, "stray.wire_direction");
  t = s;
  t.env.stray.wire_current_A = 1;
  t.env.stray.wire_point_mm = {0, std::nan(""), 0};
  refuses(t, "stray.wire_point_mm");
  t = s;
  t.env.stray.wire_current_A = std::nan("");
  refuses(t, "stray.wire_current_A");
  // A conductor through probe 1 of `two` (beta = 90 deg: (0, 2.4, 4.55)), and one within 1e-7 mm of it.
  for (double miss_mm : {0.0, 1e-7}) {
    t = s;
    t.env.stray.wire_current_A = 10;
    t.env.stray.wire_point_mm = {miss_mm, 2.4, 4.55};
    t.env.stray.wire_direction = {0, 0, 1};
    refuses(t, "stray.wire_point_mm");
  }
  // ... but not 1e-3 mm away.
  t.env.stray.wire_point_mm = {1e-3, 2.4, 4.55};
  CHECK_NOTHROW(angle_error(exact_field(), t, m));
  // Config: a vector needs three elements; NaN and out-of-range values are refused when set.
  Config cfg(common_keys());
  try {
    cfg.set("stray.uniform_mT=[1, 2]");
    sensor_setup_from_config(cfg, "two");
    FAIL("two elements accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("stray.uniform_mT") != std::string::npos);
    CHECK(one_line(e.what()));
  }
  Config c2(common_keys());
  CHECK_THROWS_AS(c2.set("stray.wire_direction=[0, nan, 1]"), InputError);
  CHECK_THROWS_AS(c2.set("stray.uniform_mT=[0, 0, 1e9]"), InputError);
}

TEST_CASE("temperature: docs/physics.md reference values of offsets under Br(T)", "[probe][physics][regression]") {
  ProbeSetup s = setup_for("two");
  s.chain.offset_cos_mT = 0.5;
  CHECK(c1(s) == Approx(0.627).margin(0.0005));  // 20 C: the default environment
  s.env.temperature_C = 120;                     // -0.0012/K over 100 K: Br 12 % lower
  REQUIRE(s.env.br_scale() == Approx(0.88).epsilon(1e-14));
  CHECK(c1(s) == Approx(0.713).margin(0.0005));
}

TEST_CASE("temperature: readings scale with Br(T), offset/amplitude follows", "[probe][closed-form]") {
  Mount m;
  m.sx_mm = 0.08;
  m.dy_mm = -0.05;
  for (const std::string array : {"two", "diff4", "point"}) {
    CAPTURE(array);
    const SensorPrinciple p = array == "point" ? SensorPrinciple::InPlane : SensorPrinciple::Bz;
    ProbeSetup cold = setup_for(array, p, 720), ref = cold;
    cold.env.temperature_C = -40;
    cold.env.br_tc_per_K = -0.002;  // hard ferrite: Br 12 % higher at -40 C
    const double k = cold.env.br_scale();
    REQUIRE(k == Approx(1.12));
    const AngleErrorResult a = angle_error(exact_field(), cold, m), b = angle_error(exact_field(), ref, m);
    CHECK((a.probe_B_T - k * b.probe_B_T).cwiseAbs().maxCoeff() < 1e-14);
    CHECK(a.field_max_mT == Approx(k * b.field_max_mT).epsilon(1e-13));
    CHECK((a.eps_deg - b.eps_deg).cwiseAbs().maxCoeff() < 1e-11);  // a ratio does not see Br alone
    // With offsets: the run at T equals the run at 20 C with offsets / k.
    cold.chain.offset_cos_mT = 0.3;
    cold.chain.offset_sin_mT = -0.2;
    ref.chain.offset_cos_mT = 0.3 / k;
    ref.chain.offset_sin_mT = -0.2 / k;
    const AngleErrorResult c = angle_error(exact_field(), cold, m), d = angle_error(exact_field(), ref, m);
    CHECK((c.eps_deg - d.eps_deg).cwiseAbs().maxCoeff() < 1e-11);
  }
}

TEST_CASE("temperature: offset drift and air-gap drift", "[probe][closed-form]") {
  Mount m;
  m.dx_mm = 0.05;
  // Offset drift: 5 uT/K over 80 K is 0.4 mT on the cos channel; with tc = 0 the readings keep Br.
  ProbeSetup hot = setup_for("two", SensorPrinciple::Bz, 720), ref = hot;
  hot.env.temperature_C = 100;
  hot.env.br_tc_per_K = 0;
  hot.env.offset_cos_tc_uT_per_K = 5;
  hot.env.offset_sin_tc_uT_per_K = -2.5;
  ref.chain.offset_cos_mT = 0.4;
  ref.chain.offset_sin_mT = -0.2;
  CHECK((angle_error(exact_field(), hot, m).eps_deg - angle_error(exact_field(), ref, m).eps_deg)
            .cwiseAbs()
            .maxCoeff() < 1e-12);
  // Air gap: 2 um/K over 80 K is dz + 0.16 mm.
  ProbeSetup gap = setup_for("diff4", SensorPrinciple::Bz, 720), gref = gap;
  gap.env.temperature_C = 100;
  gap.env.br_tc_per_K = 0;
  gap.env.dz_tc_um_per_K = 2;
  Mount m2 = m;
  m2.dz_mm += 0.16;
  const AngleErrorResult a = angle_error(exact_field(), gap, m), b = angle_error(exact_field(), gref, m2);
  CHECK((a.eps_deg - b.eps_deg).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((a.probe_B_T - b.probe_B_T).cwiseAbs().maxCoeff() < 1e-15);
  // xmr/amr have relative offsets: an offset drift in uT/K is refused, one line.
  ProbeSetup x = point_setup(SensorPrinciple::Xmr, 64);
  x.env.offset_sin_tc_uT_per_K = 1;
  try {
    angle_error(exact_field(), x, Mount{});
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("sensor.offset_sin_tc_uT_per_K") != std::string::npos);
    CHECK(one_line(e.what()));
  }
}

TEST_CASE("temperature: the field window is checked at the temperature", "[probe][physics]") {
  ProbeSetup s = setup_for("two", SensorPrinciple::Bz, 360);
  const AngleErrorResult r20 = angle_error(exact_field(), s, Mount{});
  s.window.min_mT = 0.95 * r20.field_min_mT;  // 5 % margin at 20 C
  s.window.max_mT = 1.05 * r20.field_max_mT;
  CHECK(angle_error(exact_field(), s, Mount{}).in_window);
  s.env.temperature_C = 150;  // NdFeB: Br 15.6 % lower
  const AngleErrorResult hot = angle_error(exact_field(), s, Mount{});
  CHECK(hot.field_min_mT == Approx(0.844 * r20.field_min_mT).epsilon(1e-12));
  CHECK_FALSE(hot.in_window);
  s.env.temperature_C = -40;  // 7.2 % higher
  CHECK_FALSE(angle_error(exact_field(), s, Mount{}).in_window);
}

TEST_CASE("temperature: keys, material library and neutral defaults", "[probe][contract]") {
  Config cfg(common_keys());
  const ProbeSetup def = sensor_setup_from_config(cfg, "two");
  CHECK(def.env.neutral());
  CHECK(def.env.temperature_C == 20);
  CHECK(def.env.br_tc_per_K == -0.0012);
  // Neutral defaults leave the pipeline as it was: at 20 C any coefficient gives identical numbers.
  ProbeSetup s = setup_for("diff4", SensorPrinciple::Bz, 720), t = s;
  t.env.br_tc_per_K = -0.002;
  t.env.offset_cos_tc_uT_per_K = 3;
  t.env.dz_tc_um_per_K = 4;
  Mount m;
  m.sx_mm = 0.1;
  const AngleErrorResult a = angle_error(exact_field(), s, m), b = angle_error(exact_field(), t, m);
  CHECK((a.eps_deg - b.eps_deg).cwiseAbs().maxCoeff() == 0.0);
  CHECK((a.probe_B_T - b.probe_B_T).cwiseAbs().maxCoeff() == 0.0);
  // Materials: each has a coefficient and a named source; magnet.material sets the coefficient unless
  // magnet.br_tc_per_K is changed from its default.
  REQUIRE(magnet_materials().size() == 4);
  for (const auto& mat : magnet_materials()) {
    CAPTURE(mat.name);
    CHECK(mat.br_tc_per_K < 0);
    CHECK(mat.br_tc_per_K > -0.003);
    CHECK(mat.source.size() > 20);
    Config c(common_keys());
    c.set("magnet.material=" + mat.name);
    CHECK(Environment::from_config(c).br_tc_per_K == mat.br_tc_per_K);
    c.set("magnet.br_tc_per_K=-0.0005");
    CHECK(Environment::from_config(c).br_tc_per_K == -0.0005);
  }
  CHECK(magnet_material("smco").br_tc_per_K == -0.00035);
  CHECK_THROWS_AS(Config(common_keys()).set("magnet.material=alnico"), InputError);
  Config hot(common_keys());
  hot.set("environment.temperature_C=150");
  CHECK(sensor_setup_from_config(hot, "two").env.br_scale() == Approx(0.844));
  // Br(T) <= 0 is refused.
  ProbeSetup bad = setup_for("two", SensorPrinciple::Bz, 64);
  bad.env.br_tc_per_K = -0.01;
  bad.env.temperature_C = 200;
  try {
    angle_error(exact_field(), bad, Mount{});
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("magnet.br_tc_per_K") != std::string::npos);
    CHECK(one_line(e.what()));
  }
}
