// The exact field of a ring magnet (magnet.inner_radius_mm = Ri > 0; AnalyticField evaluates it as
// B_cyl(R) - B_cyl(Ri)), checked against references that do not use that superposition:
//   1. an independent quadrature of the ring's own surface charges: M0 cos(el) cos(phi' - beta) on the
//      outer face, -M0 cos(el) cos(phi' - beta) on the bore face (its normal points to the axis), and
//      +-M0 sin(el) on the annular end faces Ri <= rho <= R; nested adaptive Gauss-Kronrod (Boost.Math),
//      B = mu0 H plus mu0 M in the material only, at points in the material, in the bore and outside;
//   2. the on-axis closed form, face by face: a face of radius a carrying +-M0 cos(phi') gives on the axis
//      H_x = -+(M0/4) [(z + L/2)/sqrt(a^2 + (z + L/2)^2) - (z - L/2)/sqrt(a^2 + (z - L/2)^2)];
//      an annular end face (charge +-M0) gives H_z = +-(M0/2) [sign(t) - t/sqrt(R^2 + t^2)] - (same with
//      Ri), t the height above the face, which sums to the axial form below;
//   3. the far field: the dipole of moment M0 pi (R^2 - Ri^2) L;
//   4. the limit Ri -> 0: the difference from the solid cylinder falls like Ri^2 (the bore's dipole), and
//      Ri = 0 is the cylinder exactly;
//   5. bad input: Ri >= R.
#include <catch2/catch.hpp>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_at.hpp"
#include "support/surface_charge_field.hpp"

using magenc::AnalyticField;
using magenc::Magnet;
using magenc::Vec3;

namespace {

constexpr double kPi = magenc::kPi;
using magenc::test::B_by_surface_charges;
using magenc::test::in_material;

double surface_distance(const Magnet& m, const Vec3& x) {
  const double R = m.radius_mm, Ri = m.inner_radius_mm, h = 0.5 * m.height_mm;
  const double r = std::hypot(x.x(), x.y()), az = std::abs(x.z());
  double d = 1e300;
  // Distance to each face (finite segments in the (r, z) half-plane).
  auto seg = [&](double r0, double z0, double r1, double z1) {
    const double dr = r1 - r0, dz = z1 - z0;
    const double t = std::clamp(((r - r0) * dr + (az - z0) * dz) / (dr * dr + dz * dz), 0.0, 1.0);
    d = std::min(d, std::hypot(r - (r0 + t * dr), az - (z0 + t * dz)));
  };
  seg(R, 0, R, h);
  seg(Ri, 0, Ri, h);
  seg(Ri, h, R, h);
  return d;
}

}  // namespace

TEST_CASE("ring field equals an independent surface-charge quadrature in the material, the bore and outside",
          "[fields][physics][cross-check]") {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  int counts[3] = {0, 0, 0};  // material, bore, outside
  for (int k = 0; k < 8; ++k) {
    Magnet m;
    m.radius_mm = 2.0 + 14.0 * u(rng);
    m.inner_radius_mm = (0.2 + 0.7 * u(rng)) * m.radius_mm;
    m.height_mm = 1.0 + 7.0 * u(rng);
    m.br_T = 0.3 + 1.0 * u(rng);
    m.magnetization_deg = -180 + 360 * u(rng);
    m.magnetization_elevation_deg = k == 0 ? 0.0 : (k == 1 ? 90.0 : -90 + 180 * u(rng));
    const AnalyticField field(m);
    const double R = m.radius_mm, Ri = m.inner_radius_mm, h = 0.5 * m.height_mm;
    const double size = std::min({R - Ri, h, Ri});
    std::vector<Vec3> pts;
    for (int want = 0; want < 3; ++want) {
      int got = 0;
      while (got < 2) {
        const double span = want == 2 ? 2.0 : 1.0;
        const Vec3 p(span * R * (2 * u(rng) - 1), span * R * (2 * u(rng) - 1), span * 2 * h * (2 * u(rng) - 1));
        const double r = std::hypot(p.x(), p.y());
        const int where = in_material(m, p) ? 0 : (r < Ri && std::abs(p.z()) < h ? 1 : 2);
        if (where != want || surface_distance(m, p) < 0.1 * size) continue;
        pts.push_back(p);
        ++got;
      }
    }
    Eigen::Matrix3Xd P(3, pts.size());
    for (std::size_t j = 0; j < pts.size(); ++j) P.col(j) = pts[j];
    const Eigen::Matrix3Xd B = magenc::field_at(field, P);
    for (std::size_t j = 0; j < pts.size(); ++j) {
      const Vec3 ref = B_by_surface_charges(m, pts[j]);
      const double err = (Vec3(B.col(j)) - ref).norm();
      INFO("ring R " << R << " Ri " << Ri << " L " << m.height_mm << " beta " << m.magnetization_deg << " el "
                     << m.magnetization_elevation_deg << " point " << pts[j].transpose() << " B " << ref.transpose());
      CHECK(err <= 1e-9 * ref.norm());
      worst = std::max(worst, err / ref.norm());
      counts[j / 2] += 1;
    }
  }
  std::cout << "ring vs surface-charge quadrature: " << counts[0] << " points in the material, " << counts[1]
            << " in the bore, " << counts[2] << " outside; max |dB|/|B| = " << worst << "\n";
}

TEST_CASE("ring field on its axis equals the face-by-face closed form, in the bore and beyond the faces",
          "[fields][physics][closed-form]") {
  Magnet m;
  m.radius_mm = 16;
  m.inner_radius_mm = 11;
  m.height_mm = 4;
  m.br_T = 1.2;
  const double R = m.radius_mm, Ri = m.inner_radius_mm, h = 0.5 * m.height_mm;
  auto shell = [&](double a, double z) { return (z + h) / std::hypot(a, z + h) - (z - h) / std::hypot(a, z - h); };
  double worst = 0;
  for (double beta : {0.0, 63.0}) {
    m.magnetization_deg = beta;
    m.magnetization_elevation_deg = 0;
    const AnalyticField field(m);
    for (double z : {-30.0, -3.0, -1.0, 0.0, 0.5, 1.99, 2.5, 12.0}) {
      // Outer face +M0 cos, bore face -M0 cos: B along M = -Br/4 shell(R) + Br/4 shell(Ri); no mu0 M on the axis.
      const double Bm = -0.25 * m.br_T * shell(R, z) + 0.25 * m.br_T * shell(Ri, z);
      const Vec3 expect(Bm * std::cos(beta * kPi / 180), Bm * std::sin(beta * kPi / 180), 0.0);
      const Vec3 B = magenc::field_at(field, Eigen::Vector3d(0, 0, z)).col(0);
      INFO("diametric beta " << beta << " z " << z << " B " << B.transpose() << " expected " << expect.transpose());
      CHECK((B - expect).norm() <= 1e-13 * m.br_T);
      worst = std::max(worst, (B - expect).norm() / std::abs(Bm));
    }
  }
  m.magnetization_elevation_deg = 90;
  const AnalyticField axial(m);
  for (double z : {-30.0, -3.0, -1.0, 0.0, 0.5, 2.5, 12.0}) {
    // Annular end faces: t = z -+ h above each face, H_z = (M0/2) sum_faces +-[t/sqrt(Ri^2+t^2) - t/sqrt(R^2+t^2)].
    auto face = [&](double t) { return t / std::hypot(Ri, t) - t / std::hypot(R, t); };
    const double Bz = 0.5 * m.br_T * (face(z - h) - face(z + h));
    const Vec3 B = magenc::field_at(axial, Eigen::Vector3d(0, 0, z)).col(0);
    INFO("axial z " << z << " Bz " << B.z() << " expected " << Bz);
    CHECK(std::abs(B.z() - Bz) <= 1e-13 * m.br_T);
    CHECK(std::hypot(B.x(), B.y()) <= 1e-13 * m.br_T);
    worst = std::max(worst, std::abs(B.z() - Bz) / std::abs(Bz));
  }
  std::cout << "ring on its axis: max relative difference from the closed form = " << worst << "\n";
}

TEST_CASE("ring field far away is the dipole of the ring's volume", "[fields][physics][closed-form]") {
  Magnet m;
  m.radius_mm = 16;
  m.inner_radius_mm = 11;
  m.height_mm = 4;
  m.br_T = 1.2;
  m.magnetization_deg = 30;
  m.magnetization_elevation_deg = 20;
  const AnalyticField field(m);
  const double V = kPi * (m.radius_mm * m.radius_mm - m.inner_radius_mm * m.inner_radius_mm) * m.height_mm;
  const Vec3 pol = m.remanence_T();
  // A centred ring has no quadrupole: the difference from the dipole is the octupole's, relative
  // c (R/r)^2 with c of order one. Shown: c is the same constant at 50, 100 and 200 R (to 1 %), so the
  // difference is that term and nothing else, and the field tends to the dipole.
  std::vector<double> c;
  for (double dist : {50.0 * 16, 100.0 * 16, 200.0 * 16}) {
    const Vec3 rhat = Vec3(0.3, -0.5, 0.8).normalized(), x = dist * rhat;
    const Vec3 dipole = V / (4 * kPi * dist * dist * dist) * (3 * pol.dot(rhat) * rhat - pol);
    const double rel = (field.B_T(x) - dipole).norm() / dipole.norm();
    c.push_back(rel * std::pow(dist / 16.0, 2));
    INFO("r = " << dist << " mm: relative difference " << rel << ", c = " << c.back());
    CHECK(c.back() < 2.0);
  }
  CHECK(c[1] == Approx(c[0]).epsilon(0.01));
  CHECK(c[2] == Approx(c[1]).epsilon(0.01));
  std::cout << "ring far field: |B - B_dipole|/|B_dipole| = c (R/r)^2 with c = " << c[0] << ", " << c[1] << ", "
            << c[2] << " at 50, 100, 200 R\n";
}

TEST_CASE("ring field tends to the cylinder's as the bore closes, and Ri = 0 is the cylinder",
          "[fields][physics][closed-form]") {
  Magnet cyl;
  cyl.radius_mm = 4;
  cyl.height_mm = 3;
  cyl.magnetization_deg = 20;
  cyl.magnetization_elevation_deg = 15;
  const AnalyticField solid(cyl);
  const std::vector<Vec3> pts{{0.5, 0.3, 2.2}, {5.0, -1.0, 0.4}, {2.0, 2.0, 0.1}, {0.0, 0.0, 4.0}};
  Magnet zero = cyl;
  zero.inner_radius_mm = 0.0;
  const AnalyticField same(zero);
  for (const Vec3& p : pts) CHECK((same.B_T(p) - solid.B_T(p)).norm() == 0.0);
  std::vector<double> diffs;
  for (double ri : {1e-2, 1e-3}) {
    Magnet ring = cyl;
    ring.inner_radius_mm = ri;
    const AnalyticField f(ring);
    double worst = 0;
    for (const Vec3& p : pts) worst = std::max(worst, (f.B_T(p) - solid.B_T(p)).norm());
    diffs.push_back(worst);
  }
  INFO("max |B_ring - B_cyl| at Ri 1e-2, 1e-3 mm: " << diffs[0] << ", " << diffs[1] << " T");
  // The missing bore is a dipole of volume pi Ri^2 L: its field falls by 100 when Ri falls by 10.
  CHECK(diffs[0] < 1e-4 * cyl.br_T);
  CHECK(diffs[1] / diffs[0] == Approx(0.01).epsilon(0.02));
}

TEST_CASE("a ring whose inner radius reaches the outer one is refused, naming both keys",
          "[fields][bad-input]") {
  for (double ri : {4.0, 5.0, -1.0}) {
    Magnet m;
    m.radius_mm = 4;
    m.inner_radius_mm = ri;
    try {
      m.validate();
      FAIL("accepted Ri = " << ri);
    } catch (const magenc::InputError& e) {
      const std::string what = e.what();
      CHECK(what.find("magnet.inner_radius_mm") != std::string::npos);
      CHECK(what.find("magnet.radius_mm") != std::string::npos);
      CHECK(what.find('\n') == std::string::npos);
    }
  }
  Magnet ring;
  ring.radius_mm = 4;
  ring.inner_radius_mm = 2;
  const AnalyticField f(ring);
  // The bore face is a surface too: field_at refuses it; the bore's inside is air.
  CHECK_THROWS_AS(magenc::field_at(f, Eigen::Vector3d(2.0, 0.0, 0.0)), magenc::InputError);
  CHECK(!f.inside_or_on_magnet(Vec3(1.0, 0.0, 0.0)));
  CHECK(f.inside_or_on_magnet(Vec3(3.0, 0.0, 0.0)));
}
