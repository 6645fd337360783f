#include "fields/multipole_field.hpp"

#include <boost/math/quadrature/gauss.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <random>
#include <utility>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {

constexpr int kG = MultipoleField::kNodesPerPanel;

// The 16-point Gauss-Legendre rule on [-1, 1] (Boost.Math): nodes and weights, both halves.
struct GaussRule {
  std::array<double, kG> x{}, w{};
  GaussRule() {
    using Rule = boost::math::quadrature::gauss<double, kG>;
    const auto& a = Rule::abscissa();
    const auto& wt = Rule::weights();
    for (int i = 0; i < kG / 2; ++i) {
      x[i] = -a[i];
      w[i] = wt[i];
      x[kG - 1 - i] = a[i];
      w[kG - 1 - i] = wt[i];
    }
  }
};

const GaussRule& gauss_rule() {
  static const GaussRule rule;
  return rule;
}

// ln(v + sqrt(v^2 + w2)) without cancellation (S = that root).
double log_v_plus_s(double v, double S, double w2) { return v >= 0 ? std::log(v + S) : std::log(w2 / (S - v)); }

double sgn(double a) { return a > 0 ? 1.0 : (a < 0 ? -1.0 : 0.0); }

// [tau/(rho^2 S)]_{tau_1}^{tau_2} without cancellation (the curved face's z' integral).
double g_bracket(double rho2, double t1, double t2, double S1, double S2) {
  const double f1 = 1.0 / (S1 * (S1 + std::abs(t1))), f2 = 1.0 / (S2 * (S2 + std::abs(t2)));
  if (t1 >= 0) return f1 - f2;
  if (t2 <= 0) return f2 - f1;
  return 2.0 / rho2 - f1 - f2;
}

}  // namespace

std::vector<MagnetSector> pattern_sectors(const Magnet& magnet) {
  if (magnet.pattern == MagnetPattern::Radial) return {MagnetSector{0.0, 2 * kPi, 1.0}};
  if (!magnet.is_multipole()) throw InputError("pattern_sectors: magnet.pattern = uniform has no sectors");
  const int n = 2 * magnet.pole_pairs;
  std::mt19937_64 rng(static_cast<std::uint64_t>(magnet.pole_seed));
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> edge_deg(n + 1), amp(n);
  for (int j = 0; j < n; ++j) edge_deg[j] = (-90.0 + 180.0 * j) / magnet.pole_pairs + magnet.pole_edge_sigma_deg * normal(rng);
  edge_deg[n] = edge_deg[0] + 360.0;
  for (int j = 0; j < n; ++j) amp[j] = 1.0 + magnet.pole_amplitude_sigma * normal(rng);
  std::vector<MagnetSector> out(n);
  for (int j = 0; j < n; ++j)
    out[j] = {deg_to_rad(edge_deg[j]), deg_to_rad(edge_deg[j + 1]), (j % 2 == 0 ? 1.0 : -1.0) * amp[j]};
  return out;
}

MultipoleField::MultipoleField(const Magnet& magnet) : MultipoleField(magnet, pattern_sectors(magnet)) {}

MultipoleField::MultipoleField(const Magnet& magnet, std::vector<MagnetSector> sectors)
    : magnet_(magnet), sectors_(std::move(sectors)), axial_(magnet.pattern == MagnetPattern::AxialMultipole) {
  magnet_.validate();
  for (const MagnetSector& s : sectors_)
    if (!(s.phi_b_rad > s.phi_a_rad && s.phi_b_rad - s.phi_a_rad <= 2 * kPi + 1e-12))
      throw InputError("magnet sectors: a sector must span (0, 360] deg");
}

double MultipoleField::singularity_distance(const Vec3& p) const {
  const double r = std::hypot(p.x(), p.y());
  if (r == 0) return 1e300;
  const double h = magnet_.top_z_mm();
  const double dr = std::max({magnet_.inner_radius_mm - r, r - magnet_.radius_mm, 0.0});
  const double dz = std::max(std::abs(p.z()) - h, 0.0);
  const double d2 = dr * dr + dz * dz;
  // acosh(1 + x) = log1p(x + sqrt(x (x + 2))), accurate for small x.
  const double x = d2 / (2.0 * r * magnet_.radius_mm);
  return std::log1p(x + std::sqrt(x * (x + 2.0)));
}

int MultipoleField::panels_for(double a, double b, double phi, double y0) {
  if (y0 > 1e3) return 1;
  const double width = b - a;
  for (int n = 1; n < kMaxPanelsPerSector; n = n < 4 ? n + 1 : n + n / 2) {
    const double hw = 0.5 * width / n;
    // The panel nearest the singularity's real part (phi folded to the sector's neighbourhood).
    const double mid = 0.5 * (a + b);
    const double phi_rep = mid + std::remainder(phi - mid, 2 * kPi);
    const double k = std::clamp(std::floor((phi_rep - a) / (2 * hw)), 0.0, n - 1.0);
    const double c = a + (2 * k + 1) * hw;
    const std::complex<double> z((phi_rep - c) / hw, y0 / hw);
    const std::complex<double> root = std::sqrt(z - 1.0) * std::sqrt(z + 1.0);
    const double rho = std::max(std::abs(z + root), std::abs(z - root));
    if (rho >= kBernsteinRho) return n;
  }
  return kMaxPanelsPerSector;
}

int MultipoleField::nodes_at(const Vec3& p) const {
  const double y0 = singularity_distance(p), phi = std::atan2(p.y(), p.x());
  int n = 0;
  for (const MagnetSector& s : sectors_) n += kG * panels_for(s.phi_a_rad, s.phi_b_rad, phi, y0);
  return n;
}

template <bool kFull>
void MultipoleField::add_axial_node(const Vec3& p, double c, double s, double wq, Vec3& H) const {
  const double u = p.x() * c + p.y() * s, pp = -p.x() * s + p.y() * c;
  const double h = magnet_.top_z_mm();
  for (const double face : {1.0, -1.0}) {
    const double t = p.z() - face * h, w2 = pp * pp + t * t;
    double K = 0, J = 0;
    for (const double end : {1.0, -1.0}) {
      const double v = (end > 0 ? magnet_.radius_mm : magnet_.inner_radius_mm) - u;
      const double D = std::sqrt(v * v + w2);
      K += end * (u * v - w2) / (w2 * D);
      if constexpr (kFull) J += end * (log_v_plus_s(v, D, w2) - (v + u) / D);
    }
    const double f = face * wq;
    if constexpr (kFull) {
      H.x() += f * (-s * pp * K - c * J);
      H.y() += f * (c * pp * K - s * J);
    }
    H.z() += f * t * K;
  }
}

void MultipoleField::add_radial_node(const Vec3& p, double c, double s, double wq, Vec3& H) const {
  const double u = p.x() * c + p.y() * s, pp = -p.x() * s + p.y() * c;
  const double h = magnet_.top_z_mm(), t1 = p.z() - h, t2 = p.z() + h;
  const double sp = pp >= 0 ? 1.0 : -1.0;
  // Curved faces: +q at R, -q at Ri (a disk has none).
  for (const double face : {1.0, -1.0}) {
    const double a = face > 0 ? magnet_.radius_mm : magnet_.inner_radius_mm;
    if (a == 0) continue;
    const double va = a - u, rho2 = va * va + pp * pp;
    const double S1 = std::sqrt(rho2 + t1 * t1), S2 = std::sqrt(rho2 + t2 * t2);
    const double g = g_bracket(rho2, t1, t2, S1, S2), f = face * wq * a;
    H.x() += f * (-s * pp - va * c) * g;
    H.y() += f * (c * pp - va * s) * g;
    H.z() += f * (1.0 / S1 - 1.0 / S2);
  }
  // The volume charge -q M0 / rho' (times rho' drho').
  const double w21 = pp * pp + t1 * t1, w22 = pp * pp + t2 * t2, dsg = sgn(t2) - sgn(t1);
  double Pz = 0, P = 0, Q = 0;
  for (const double end : {1.0, -1.0}) {
    const double v = (end > 0 ? magnet_.radius_mm : magnet_.inner_radius_mm) - u;
    const double rho2 = v * v + pp * pp;
    const double S1 = std::sqrt(rho2 + t1 * t1), S2 = std::sqrt(rho2 + t2 * t2);
    Pz += end * (log_v_plus_s(v, S1, w21) - log_v_plus_s(v, S2, w22));
    P += end * sp *
         (sgn(t2) * std::atan2(std::abs(t2) * v, std::abs(pp) * S2) -
          sgn(t1) * std::atan2(std::abs(t1) * v, std::abs(pp) * S1));
    double q = -sgn(t2) * std::log(S2 + std::abs(t2)) + sgn(t1) * std::log(S1 + std::abs(t1));
    if (dsg != 0) q += dsg * 0.5 * std::log(rho2);
    Q += end * q;
  }
  H.x() -= wq * (-s * P - c * Q);
  H.y() -= wq * (c * P - s * Q);
  H.z() -= wq * Pz;
}

Vec3 MultipoleField::remanence_at_T(const Vec3& p) const {
  if (!magnet_.contains_mm(p.x(), p.y(), p.z())) return Vec3::Zero();
  const double phi = std::atan2(p.y(), p.x());
  for (const MagnetSector& s : sectors_) {
    const double rel = std::fmod(phi - s.phi_a_rad + 8 * kPi, 2 * kPi);
    if (rel < s.phi_b_rad - s.phi_a_rad) {
      if (axial_) return magnet_.br_T * s.q * Vec3::UnitZ();
      const double r = std::hypot(p.x(), p.y());
      if (r == 0) return Vec3::Zero();
      return magnet_.br_T * s.q * Vec3(p.x() / r, p.y() / r, 0.0);
    }
  }
  return Vec3::Zero();
}

template <bool kFull>
Vec3 MultipoleField::H_sum(const Vec3& p) const {
  const GaussRule& rule = gauss_rule();
  const double y0 = singularity_distance(p), phi = std::atan2(p.y(), p.x());
  Vec3 H = Vec3::Zero();
  for (const MagnetSector& sec : sectors_) {
    const int n = panels_for(sec.phi_a_rad, sec.phi_b_rad, phi, y0);
    const double hw = 0.5 * (sec.phi_b_rad - sec.phi_a_rad) / n;
    for (int k = 0; k < n; ++k) {
      const double c0 = sec.phi_a_rad + (2 * k + 1) * hw;
      for (int i = 0; i < kG; ++i) {
        const double ph = c0 + hw * rule.x[i], wq = hw * rule.w[i] * sec.q;
        const double c = std::cos(ph), s = std::sin(ph);
        if (axial_)
          add_axial_node<kFull>(p, c, s, wq, H);
        else
          add_radial_node(p, c, s, wq, H);
      }
    }
  }
  return H;
}

Vec3 MultipoleField::B_T(const Vec3& p) const { return magnet_.br_T / (4 * kPi) * H_sum<true>(p) + remanence_at_T(p); }

double MultipoleField::Bz_T(const Vec3& p) const {
  return magnet_.br_T / (4 * kPi) * H_sum<false>(p).z() + remanence_at_T(p).z();
}

}  // namespace magenc
