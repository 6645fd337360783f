// The sector patterns (magnet.pattern = radial, axial_multipole, radial_multipole; MultipoleField), checked
// against references that share none of its closed forms:
//   1. an independent quadrature of the sectors' own charges (tests/support/surface_charge_field.hpp: every
//      integral by nested adaptive Gauss-Kronrod), with pole errors, rings and disks, above, below, beside
//      and in the bore: 1e-9 relative (|B - B_ref| <= 1e-9 |B_ref|);
//   2. limits where the existing uniform-field code applies: sectors that all carry q = +1 ARE the
//      uniformly magnetized body (the sector seams carry no charge), so axial sectors with all q = +1 equal
//      AnalyticField at elevation 90 deg and a radial pattern's field on the axis equals its closed form
//      there (charged shells and the volume charge -M0/rho on the axis). A p = 1 axial_multipole is NOT a
//      diametric magnet (its M is +-e_z, not e_x), so no limit compares it with the diametric field; its
//      difference from the all-plus body is twice a half-ring's field, which the reference checks instead;
//   3. the checks of docs/physics.md: far above the track Bz decays like exp(-2 pi z / lambda) (lambda the
//      pole-pair length at r0); an ideal ring's field repeats with 360/p and flips with 180/p (so an ideal
//      read sees only orders that are multiples of p); the axis field of an ideal multipole is zero;
//   4. the seeded pole errors: reproducible, and the draws move the edges and amplitudes as stated;
//   5. bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_factory.hpp"
#include "fields/multipole_field.hpp"
#include "probe/common_keys.hpp"
#include "support/surface_charge_field.hpp"

using magenc::Magnet;
using magenc::MagnetPattern;
using magenc::MagnetSector;
using magenc::MultipoleField;
using magenc::Vec3;

namespace {

constexpr double kPi = magenc::kPi;

std::vector<magenc::test::ReferenceSector> reference_sectors(const MultipoleField& f) {
  std::vector<magenc::test::ReferenceSector> out;
  for (const MagnetSector& s : f.sectors()) out.push_back({s.phi_a_rad, s.phi_b_rad, s.q});
  return out;
}

Magnet ring(MagnetPattern pattern, int p, double Ri, double R, double L) {
  Magnet m;
  m.pattern = pattern;
  m.pole_pairs = p;
  m.inner_radius_mm = Ri;
  m.radius_mm = R;
  m.height_mm = L;
  m.br_T = 0.3;
  return m;
}

double rel_diff(const Vec3& a, const Vec3& ref) { return (a - ref).norm() / ref.norm(); }

}  // namespace

TEST_CASE("sector fields equal an independent quadrature of their charges off the surfaces",
          "[fields][physics][cross-check]") {
  struct Case {
    Magnet m;
    std::vector<Vec3> pts;
  };
  std::vector<Case> cases;
  {
    Magnet m = ring(MagnetPattern::AxialMultipole, 4, 3.0, 6.0, 1.5);
    m.pole_edge_sigma_deg = 2.0;
    m.pole_amplitude_sigma = 0.05;
    cases.push_back({m, {{4.5, 0.3, 1.15}, {-3.1, 3.7, -1.4}, {7.2, -1.0, 0.2}, {1.0, 1.5, 0.1}, {0.0, 0.0, 2.0}}});
  }
  cases.push_back({ring(MagnetPattern::AxialMultipole, 3, 0.0, 5.0, 2.0), {{2.0, 1.0, 1.4}, {5.5, -2.5, 0.0}}});
  {
    Magnet m = ring(MagnetPattern::RadialMultipole, 2, 3.0, 6.0, 1.5);
    m.pole_edge_sigma_deg = 3.0;
    m.pole_amplitude_sigma = 0.05;
    cases.push_back({m, {{4.5, 0.3, 1.15}, {7.2, -1.0, 0.2}, {1.0, 1.5, -0.3}, {-2.0, -4.0, 1.6}}});
  }
  cases.push_back({ring(MagnetPattern::RadialMultipole, 1, 0.0, 4.0, 2.0), {{2.0, 1.0, 1.5}, {4.6, 0.5, 0.3}}});
  cases.push_back({ring(MagnetPattern::Radial, 1, 2.0, 5.0, 1.0), {{3.0, 1.0, 0.9}, {0.5, 0.2, 0.1}, {5.5, -1, 0}}});
  cases.push_back({ring(MagnetPattern::Radial, 1, 0.0, 5.0, 1.0), {{3.0, 1.0, 0.9}, {6.0, 1.0, 0.2}}});
  double worst = 0;
  for (const Case& c : cases) {
    const MultipoleField f(c.m);
    const bool axial = c.m.pattern == MagnetPattern::AxialMultipole;
    for (const Vec3& x : c.pts) {
      const Vec3 ref = magenc::test::B_of_sectors_by_charges(c.m, reference_sectors(f), axial, x);
      const double d = rel_diff(f.B_T(x), ref);
      INFO(magenc::pattern_name(c.m.pattern) << " Ri " << c.m.inner_radius_mm << " at " << x.transpose()
                                             << ": B " << f.B_T(x).transpose() << " ref " << ref.transpose());
      CHECK(d <= 1e-9);
      worst = std::max(worst, d);
    }
  }
  std::cout << "sector fields vs the charge quadrature: worst relative difference " << worst << "\n";
}

TEST_CASE("a 32-pole-pair ring at the read gap equals the independent quadrature",
          "[fields][physics][cross-check]") {
  const Magnet m = ring(MagnetPattern::AxialMultipole, 32, 11.0, 15.0, 1.5);
  const MultipoleField f(m);
  for (const Vec3& x : {Vec3(13.0, 0.0, 1.15), Vec3(13.0 * std::cos(0.03), 13.0 * std::sin(0.03), 1.15)}) {
    const Vec3 ref = magenc::test::B_of_sectors_by_charges(m, reference_sectors(f), true, x);
    CHECK(rel_diff(f.B_T(x), ref) <= 1e-9);
    // The cost: 64 sectors of 16 nodes, a few more panels only in the sectors near the point.
    CHECK(f.nodes_at(x) <= 64 * MultipoleField::kNodesPerPanel + 8 * MultipoleField::kNodesPerPanel);
  }
}

TEST_CASE("axial sectors that all carry +1 are the uniformly axial magnet of AnalyticField",
          "[fields][physics][cross-check]") {
  for (const double Ri : {0.0, 2.5}) {
    Magnet m = ring(MagnetPattern::AxialMultipole, 3, Ri, 5.0, 2.0);
    std::vector<MagnetSector> all_plus = magenc::pattern_sectors(m);
    for (MagnetSector& s : all_plus) s.q = 1.0;
    const MultipoleField sectors(m, all_plus);
    Magnet u = m;
    u.pattern = MagnetPattern::Uniform;
    u.magnetization_elevation_deg = 90.0;
    const magenc::AnalyticField uniform(u);
    for (const Vec3& x : {Vec3(1.0, 0.5, 1.3), Vec3(5.5, 2.0, 0.4), Vec3(0.0, 0.0, -2.5), Vec3(3.0, -3.0, 3.0)})
      CHECK(rel_diff(sectors.B_T(x), uniform.B_T(x)) <= 1e-10);
  }
}

TEST_CASE("a radial ring's axis field equals its closed form", "[fields][physics][cross-check]") {
  for (const double Ri : {0.0, 2.0}) {
    const Magnet m = ring(MagnetPattern::Radial, 1, Ri, 5.0, 1.0);
    const MultipoleField f(m);
    const double R = m.radius_mm, h = 0.5 * m.height_mm;
    for (const double z : {0.8, 1.5, -2.0}) {
      const double t1 = z - h, t2 = z + h;
      // Shells of radius a with charge +-M0: Hz = (a/2)(1/S1 - 1/S2); the volume -M0/rho:
      // -1/2 [asinh(rho/|t1|) - asinh(rho/|t2|)]_{Ri}^{R}.
      auto shell = [&](double a) { return 0.5 * a * (1 / std::hypot(a, t1) - 1 / std::hypot(a, t2)); };
      auto vol = [&](double a) { return 0.5 * (std::asinh(a / std::abs(t1)) - std::asinh(a / std::abs(t2))); };
      const double Hz = shell(R) - shell(Ri) - (vol(R) - vol(Ri));
      const Vec3 B = f.B_T(Vec3(0, 0, z));
      CHECK(std::abs(B.z() - m.br_T * Hz) <= 1e-12 * m.br_T);
      CHECK(std::abs(B.x()) + std::abs(B.y()) <= 1e-14);
    }
  }
}

TEST_CASE("far above a multipole track Bz decays like exp(-2 pi z / lambda)", "[fields][physics]") {
  const Magnet m = ring(MagnetPattern::AxialMultipole, 32, 11.0, 15.0, 1.5);
  const MultipoleField f(m);
  const double r0 = 13.0, lambda = 2 * kPi * r0 / m.pole_pairs;
  // ln Bz between gaps 1.0 and 2.5 mm on the pole centre; the third spatial harmonic adds exp(-2 k z)/3
  // ~ 2e-3 relative at 1 mm and the finite width of the ring (4 mm, 1.6 lambda) bends the law by
  // O(lambda / width)^2 e^{-...}: the slope is held to 2 %.
  const double z1 = m.top_z_mm() + 1.0, z2 = m.top_z_mm() + 2.5;
  const double slope = std::log(f.B_T(Vec3(r0, 0, z1)).z() / f.B_T(Vec3(r0, 0, z2)).z()) / (z2 - z1);
  std::cout << "decay rate " << slope << " /mm, 2 pi / lambda = " << 2 * kPi / lambda << " /mm\n";
  CHECK(std::abs(slope / (2 * kPi / lambda) - 1) <= 0.02);
}

TEST_CASE("an ideal multipole repeats with 360/p, flips with 180/p and is zero on the axis", "[fields][physics]") {
  for (const auto pattern : {MagnetPattern::AxialMultipole, MagnetPattern::RadialMultipole}) {
    const Magnet m = ring(pattern, 5, 3.0, 6.0, 1.5);
    const MultipoleField f(m);
    const double pitch = 2 * kPi / m.pole_pairs;
    for (const double phi : {0.1, 0.37, 1.0}) {
      auto at = [&](double a) { return Vec3(4.7 * std::cos(a), 4.7 * std::sin(a), 1.3); };
      auto rotated = [&](const Vec3& B, double a) {
        return Vec3(std::cos(a) * B.x() - std::sin(a) * B.y(), std::sin(a) * B.x() + std::cos(a) * B.y(), B.z());
      };
      const Vec3 B0 = f.B_T(at(phi));
      CHECK((f.B_T(at(phi + pitch)) - rotated(B0, pitch)).norm() <= 1e-12 * B0.norm());
      CHECK((f.B_T(at(phi + pitch / 2)) + rotated(B0, pitch / 2)).norm() <= 1e-12 * B0.norm());
    }
    CHECK(f.B_T(Vec3(0, 0, 1.5)).norm() <= 1e-14);
  }
}

TEST_CASE("pole errors are seeded: same seed same field, edges and amplitudes as drawn", "[fields][regression]") {
  Magnet m = ring(MagnetPattern::AxialMultipole, 8, 3.0, 6.0, 1.5);
  const auto ideal = magenc::pattern_sectors(m);
  m.pole_edge_sigma_deg = 0.5;
  m.pole_amplitude_sigma = 0.02;
  const auto a = magenc::pattern_sectors(m), b = magenc::pattern_sectors(m);
  m.pole_seed = 2;
  const auto c = magenc::pattern_sectors(m);
  REQUIRE(a.size() == 16);
  double edge_rms = 0, amp_rms = 0, seed_diff = 0;
  for (std::size_t j = 0; j < a.size(); ++j) {
    CHECK(a[j].phi_a_rad == b[j].phi_a_rad);
    CHECK(a[j].q == b[j].q);
    CHECK(a[j].phi_b_rad == (j + 1 < a.size() ? a[j + 1].phi_a_rad : a[0].phi_a_rad + 2 * kPi));
    CHECK(a[j].q * ideal[j].q > 0);
    edge_rms += std::pow(magenc::rad_to_deg(a[j].phi_a_rad - ideal[j].phi_a_rad), 2);
    amp_rms += std::pow(std::abs(a[j].q) - 1, 2);
    seed_diff += std::abs(a[j].q - c[j].q);
  }
  CHECK(std::sqrt(edge_rms / 16) > 0.2);
  CHECK(std::sqrt(edge_rms / 16) < 1.0);
  CHECK(std::sqrt(amp_rms / 16) > 0.008);
  CHECK(std::sqrt(amp_rms / 16) < 0.04);
  CHECK(seed_diff > 0);
}

TEST_CASE("multipole patterns: bad input is one line naming the keys", "[fields][bad-input]") {
  magenc::Config cfg(magenc::common_keys());
  cfg.set("magnet.inner_radius_mm=11");
  cfg.set("magnet.radius_mm=15");
  cfg.set("magnet.pattern=axial_multipole");
  cfg.set("magnet.pole_pairs=0");
  CHECK_THROWS_WITH(Magnet::from_config(cfg), Catch::Contains("magnet.pole_pairs = 0"));
  cfg.set("magnet.pole_pairs=32");
  REQUIRE_NOTHROW(Magnet::from_config(cfg));
  CHECK(magenc::make_field_source("analytic", cfg)->B_T(Vec3(13, 0, 1.15)).norm() > 0.01);
  cfg.set("magnet.magnetization_deg=30");
  CHECK_THROWS_WITH(Magnet::from_config(cfg), Catch::Contains("magnet.magnetization_deg"));
  cfg.set("magnet.magnetization_deg=0");
  CHECK_THROWS_WITH(cfg.set("magnet.pattern=dipole"), Catch::Contains("magnet.pattern"));
  const Magnet m = ring(MagnetPattern::RadialMultipole, 4, 3.0, 6.0, 1.5);
  CHECK_THROWS_AS(magenc::AnalyticField(m), magenc::InputError);
}

TEST_CASE("Bz alone equals the z component of the full field", "[fields][regression]") {
  for (const auto pattern : {MagnetPattern::AxialMultipole, MagnetPattern::RadialMultipole, MagnetPattern::Radial}) {
    const MultipoleField f(ring(pattern, 4, 3.0, 6.0, 1.5));
    for (const Vec3& x : {Vec3(4.5, 0.3, 1.15), Vec3(7.0, -2.0, 0.3), Vec3(4.0, 1.0, 0.5)})
      CHECK(f.Bz_T(x) == f.B_T(x).z());
  }
}
