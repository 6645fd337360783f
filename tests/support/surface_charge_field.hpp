// An independent reference for the exact field: B of a uniformly polarized cylinder or ring (Magnet,
// inner_radius_mm = Ri >= 0) from its magnetic surface charges sigma = M.n: M0 cos(el) cos(phi' - beta) on
// the outer face, the opposite on the bore face (its normal points to the axis), +-M0 sin(el) on the end
// faces Ri <= rho <= R; H = 1/(4 pi) Int sigma (x - x')/|x - x'|^3 dA by nested adaptive Gauss-Kronrod
// (Boost.Math, 61 points), B = mu0 H plus mu0 M in the material. It shares no code with the field.
#pragma once
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/units.hpp"
#include "fields/field_source.hpp"
#include "fields/magnet.hpp"

namespace magenc::test {

// Gauss-Kronrod settings of the reference: the error estimate |K61 - G30| is far larger than the true
// error of K61 on these analytic integrands, so a modest requested tolerance gives a reference good to
// rounding (measured: with 1e-10 instead, the largest difference of test_field_at.cpp changed only in its
// third digit, 6.38e-16 Br against 6.41e-16 Br). A tolerance near 1e-14 is not reachable by the estimate
// in double precision and only drives the recursion to its depth limit.
inline constexpr double kQuadratureTolerance = 1e-12;
inline constexpr unsigned kQuadratureMaxDepth = 15;

// Adaptive Gauss-Kronrod on [a, b] split at the interior breakpoints given (sorted, duplicates ignored).
template <class F>
double integrate(F f, double a, double b, std::vector<double> breaks) {
  using GK = boost::math::quadrature::gauss_kronrod<double, 61>;
  breaks.push_back(a);
  breaks.push_back(b);
  std::sort(breaks.begin(), breaks.end());
  double sum = 0;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const double lo = std::max(a, breaks[i]), hi = std::min(b, breaks[i + 1]);
    if (hi - lo > 1e-14 * (b - a)) sum += GK::integrate(f, lo, hi, kQuadratureMaxDepth, kQuadratureTolerance);
  }
  return sum;
}

// Inside the magnet's material (the bore of a ring is not).
inline bool in_material(const Magnet& m, const Vec3& x) {
  const double r = std::hypot(x.x(), x.y());
  return r < m.radius_mm && (m.inner_radius_mm == 0 || r > m.inner_radius_mm) && std::abs(x.z()) < 0.5 * m.height_mm;
}

// B (T) of the magnet at x by its surface charges.
inline Vec3 B_by_surface_charges(const Magnet& m, const Vec3& x) {
  const double R = m.radius_mm, Ri = m.inner_radius_mm, h = 0.5 * m.height_mm;
  const double beta = m.magnetization_deg * kPi / 180, el = m.magnetization_elevation_deg * kPi / 180;
  const double r = std::hypot(x.x(), x.y()), phi_p = std::atan2(x.y(), x.x());
  // phi' breaks at the point's azimuth and opposite to it, folded into [0, 2 pi].
  auto fold = [](double a) { return std::fmod(a + 4 * kPi, 2 * kPi); };
  const std::vector<double> phi_breaks{fold(phi_p), fold(phi_p + kPi)};
  Vec3 H = Vec3::Zero();
  for (int c = 0; c < 3; ++c) {
    // Curved faces (outer +, bore -): x' = (a cos phi', a sin phi', z'), dA = a dphi' dz'.
    for (const auto& [a, sign] : {std::pair<double, double>{R, 1.0}, {Ri, -1.0}}) {
      if (a == 0) continue;
      auto curved = [&, a = a, sign = sign](double phi) {
        const double sig = sign * std::cos(el) * std::cos(phi - beta);
        const double cx = a * std::cos(phi), cy = a * std::sin(phi);
        auto inner = [&](double zp) {
          const Vec3 d(x.x() - cx, x.y() - cy, x.z() - zp);
          return d[c] / std::pow(d.squaredNorm(), 1.5);
        };
        return sig * a * integrate(inner, -h, h, {x.z()});
      };
      if (std::cos(el) != 0) H[c] += integrate(curved, 0, 2 * kPi, phi_breaks);
    }
    // End faces z' = +-h: x' = (rho cos phi', rho sin phi', +-h), dA = rho drho dphi', sigma = +-sin(el).
    for (int s : {1, -1}) {
      auto face = [&](double phi) {
        const double cp = std::cos(phi), sp = std::sin(phi);
        auto inner = [&](double rho) {
          const Vec3 d(x.x() - rho * cp, x.y() - rho * sp, x.z() - s * h);
          return rho * d[c] / std::pow(d.squaredNorm(), 1.5);
        };
        return s * std::sin(el) * integrate(inner, Ri, R, {r});
      };
      if (std::sin(el) != 0) H[c] += integrate(face, 0, 2 * kPi, phi_breaks);
    }
  }
  Vec3 B = m.br_T / (4 * kPi) * H;  // mu0 H with mu0 M0 = Br
  if (in_material(m, x))
    B += m.br_T * Vec3(std::cos(el) * std::cos(beta), std::cos(el) * std::sin(beta), std::sin(el));
  return B;
}

}  // namespace magenc::test

namespace magenc::test {

// An independent reference for the sector patterns (magnet.pattern = radial, axial_multipole,
// radial_multipole): B (T) of sectors phi_a <= phi' < phi_b with signed amplitudes q, magnetized q M0 e_z
// (axial) or q M0 e_rho, from their charges: +-q M0 on the end faces (axial); +q M0 on the outer curved face,
// -q M0 on the bore's, and the volume charge -q M0 / rho' (radial). Every integral (phi', rho', z') by the
// nested adaptive Gauss-Kronrod above, none in closed form; B = mu0 H plus mu0 M in the material.
struct ReferenceSector {
  double phi_a_rad, phi_b_rad, q;
};

inline Vec3 B_of_sectors_by_charges(const Magnet& m, const std::vector<ReferenceSector>& sectors, bool axial,
                                    const Vec3& x) {
  const double R = m.radius_mm, Ri = m.inner_radius_mm, h = 0.5 * m.height_mm;
  const double r = std::hypot(x.x(), x.y()), phi_p = std::atan2(x.y(), x.x());
  Vec3 H = Vec3::Zero();
  for (const ReferenceSector& sec : sectors) {
    // The point's azimuth folded into the sector (a break where the integrand peaks).
    const double phi_in = sec.phi_a_rad + std::fmod(phi_p - sec.phi_a_rad + 8 * kPi, 2 * kPi);
    const std::vector<double> phi_breaks{phi_in};
    for (int c = 0; c < 3; ++c) {
      if (axial) {
        for (int s : {1, -1}) {
          auto face = [&](double phi) {
            const double cp = std::cos(phi), sp = std::sin(phi);
            auto inner = [&](double rho) {
              const Vec3 d(x.x() - rho * cp, x.y() - rho * sp, x.z() - s * h);
              return rho * d[c] / std::pow(d.squaredNorm(), 1.5);
            };
            return s * sec.q * integrate(inner, Ri, R, {r});
          };
          H[c] += integrate(face, sec.phi_a_rad, sec.phi_b_rad, phi_breaks);
        }
        continue;
      }
      for (const auto& [a, sign] : {std::pair<double, double>{R, 1.0}, {Ri, -1.0}}) {
        if (a == 0) continue;
        auto curved = [&, a = a, sign = sign](double phi) {
          const double cx = a * std::cos(phi), cy = a * std::sin(phi);
          auto inner = [&](double zp) {
            const Vec3 d(x.x() - cx, x.y() - cy, x.z() - zp);
            return d[c] / std::pow(d.squaredNorm(), 1.5);
          };
          return sign * sec.q * a * integrate(inner, -h, h, {x.z()});
        };
        H[c] += integrate(curved, sec.phi_a_rad, sec.phi_b_rad, phi_breaks);
      }
      auto volume = [&](double phi) {
        const double cp = std::cos(phi), sp = std::sin(phi);
        auto mid = [&](double rho) {
          auto inner = [&](double zp) {
            const Vec3 d(x.x() - rho * cp, x.y() - rho * sp, x.z() - zp);
            return d[c] / std::pow(d.squaredNorm(), 1.5);
          };
          return integrate(inner, -h, h, {x.z()});  // charge -q M0 / rho times the Jacobian rho
        };
        return -sec.q * integrate(mid, Ri, R, {r});
      };
      H[c] += integrate(volume, sec.phi_a_rad, sec.phi_b_rad, phi_breaks);
    }
  }
  Vec3 B = m.br_T / (4 * kPi) * H;
  if (in_material(m, x))
    for (const ReferenceSector& sec : sectors)
      if (std::fmod(phi_p - sec.phi_a_rad + 8 * kPi, 2 * kPi) < sec.phi_b_rad - sec.phi_a_rad)
        B += m.br_T * sec.q * (axial ? Vec3::UnitZ() : Vec3(x.x() / r, x.y() / r, 0.0));
  return B;
}

}  // namespace magenc::test
