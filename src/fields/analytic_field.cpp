#include "fields/analytic_field.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

const std::vector<AnalyticField::NodeTable>& AnalyticField::node_tables() {
  static const std::vector<NodeTable> tables = [] {
    std::vector<NodeTable> all;
    for (int base = kMinNodes; base <= kMaxNodes; base *= 2) {
      for (int n : {base, base + base / 2}) {
        if (n > kMaxNodes) break;
        NodeTable t;
        t.n = n;
        t.cos_phi.resize(n);
        t.sin_phi.resize(n);
        for (int j = 0; j < n; ++j) {  // midpoint nodes phi'_j = (j + 1/2) 2 pi / n
          const double phi = (j + 0.5) * 2.0 * kPi / n;
          t.cos_phi[j] = std::cos(phi);
          t.sin_phi[j] = std::sin(phi);
        }
        all.push_back(std::move(t));
      }
    }
    return all;
  }();
  return tables;
}

AnalyticField::AnalyticField(const Magnet& magnet) : magnet_(magnet), tables_(&node_tables()) {
  magnet_.validate();
  if (!magnet_.is_uniform())
    throw InputError("magnet.pattern = " + pattern_name(magnet_.pattern) +
                     " is not computed here: this field (and the FEM) takes magnet.pattern = uniform only");
  const double el_rad = deg_to_rad(magnet_.magnetization_elevation_deg);
  if (magnet_.magnetization_elevation_deg != 0.0) {
    cos_el_ = std::cos(el_rad);
    sin_el_ = std::sin(el_rad);
  }
  const double alpha_rad = deg_to_rad(magnet_.magnetization_deg);
  cos_alpha_ = std::cos(alpha_rad);
  sin_alpha_ = std::sin(alpha_rad);
  br_inside_T_ = magnet_.remanence_T();
  if (magnet_.is_ring()) {
    Magnet bore = magnet_;
    bore.radius_mm = magnet_.inner_radius_mm;
    bore.inner_radius_mm = 0.0;
    bore_ = std::make_shared<AnalyticField>(bore);
  }
}

std::optional<FieldSource::AxisymmetricParts> AnalyticField::axisymmetric_parts() const {
  AxisymmetricParts parts;
  parts.m = magnet_.remanence_T() / magnet_.br_T;
  for (int k = 0; k < 3; ++k) {
    Magnet mk = magnet_;
    mk.magnetization_deg = k == 1 ? 90.0 : 0.0;
    mk.magnetization_elevation_deg = k == 2 ? 90.0 : 0.0;
    parts.along_axis[static_cast<std::size_t>(k)] = std::make_shared<AnalyticField>(mk);
  }
  return parts;
}

bool AnalyticField::inside_or_on_magnet(const Vec3& p) const { return magnet_.contains_mm(p.x(), p.y(), p.z()); }

const AnalyticField::NodeTable& AnalyticField::table_for(double r_mm, double z_mm) const {
  const double R = magnet_.radius_mm, half = magnet_.top_z_mm();
  // Distance (in z) to the nearer face plane: the integrands (with the rho = 0
  // pole removed beside the magnet) are singular only where rho^2 = -t_i^2.
  const double tmin = std::min(std::abs(z_mm - half), std::abs(z_mm + half));
  if (!(r_mm > 0)) return tables_->front();  // on the axis: integrand ~ constant * cos(phi')
  const double c = (r_mm * r_mm + R * R + tmin * tmin) / (2.0 * r_mm * R);
  const double a = std::acosh(std::max(c, 1.0));
  // The phi' integral cancels to ~R/r of its integrand's size far away: ask for more.
  const double need = kQuadratureExponent + std::max(0.0, std::log(r_mm / R));
  for (const auto& t : *tables_)
    if (t.n * a >= need) return t;
  return tables_->back();
}

int AnalyticField::nodes_at(const Vec3& p) const {
  return table_for(std::hypot(p.x(), p.y()), p.z()).n;
}

namespace {
// I(x, y) = Int_0^{2pi} cos(phi') (x - R cos phi', y - R sin phi') / rho^2 dphi'
// (1/mm), the field of a cos(phi')-charged circle in 2-D (a uniformly
// polarized infinite cylinder): inside (r < R) I = -pi/R x_hat, outside
// I = pi R / r^2 (2 (x_hat . r_hat) r_hat - x_hat).
Eigen::Vector2d two_d_dipole_integral(double x, double y, double R) {
  const double r2 = x * x + y * y;
  if (r2 < R * R) return {-kPi / R, 0.0};
  const double k = kPi * R / r2;
  return {k * (2.0 * x * x / r2 - 1.0), k * (2.0 * x * y / r2)};
}
}  // namespace

namespace {
// Bulirsch's general complete elliptic integral
//   cel(kc, p, c, s) = Int_0^{pi/2} (c cos^2 t + s sin^2 t) / ((cos^2 t + p sin^2 t) sqrt(cos^2 t + kc^2 sin^2 t)) dt
// (R. Bulirsch, Numer. Math. 13 (1969) 305; the iteration as given by Derby & Olbert, Am. J. Phys. 78
// (2010) 229). Converges quadratically (AGM-like); the stopping test |g - k| <= g*1e-9 leaves a
// relative error ~1e-18. kc != 0 (kc = 0 only on a rim circle of the magnet).
double cel(double kc, double p, double c, double s) {
  constexpr double errtol = 1e-9;
  double k = std::abs(kc), pp = p, cc = c, ss = s, em = 1.0;
  if (p > 0) {
    pp = std::sqrt(p);
    ss = s / pp;
  } else {
    double f = kc * kc;
    double q = 1.0 - f;
    const double g = 1.0 - pp;
    f = f - pp;
    q = q * (ss - c * pp);
    pp = std::sqrt(f / g);
    cc = (c - ss) / g;
    ss = -q / (g * g * pp) + cc * pp;
  }
  double f = cc;
  cc = cc + ss / pp;
  double g = k / pp;
  ss = 2.0 * (ss + f * g);
  pp = g + pp;
  g = em;
  em = k + em;
  double kk = k;
  for (int it = 0; it < 60 && std::abs(g - k) > g * errtol; ++it) {
    k = 2.0 * std::sqrt(kk);
    kk = k * em;
    f = cc;
    cc = cc + ss / pp;
    g = kk / pp;
    ss = 2.0 * (ss + f * g);
    pp = g + pp;
    g = em;
    em = k + em;
  }
  return 0.5 * kPi * (ss + cc * em) / (em * (em + pp));
}
}  // namespace

// Axial magnetization M0 (B0 = Br here; the caller scales by sin(el)). Its
// magnetic charges +-M0 on the top/bottom faces give, outside the magnet, the
// same B as the equivalent surface current K = M0 phi_hat on the curved face
// (an ideal finite solenoid); inside, the current model gives B = mu0 (H + M)
// directly, so this is the total B everywhere (no interior term to add). With
// a = R, b = L/2, z_(+-) = z +- b (Derby & Olbert 2010, eqs. for a finite solenoid):
//   alpha_(+-) = a / sqrt(z_(+-)^2 + (rho + a)^2),  beta_(+-) = z_(+-) / sqrt(z_(+-)^2 + (rho + a)^2),
//   gamma = (a - rho)/(a + rho),  kc_(+-) = sqrt((z_(+-)^2 + (a - rho)^2) / (z_(+-)^2 + (a + rho)^2)),
//   B_rho = (Br/pi) [alpha_+ cel(kc_+, 1, 1, -1) - alpha_- cel(kc_-, 1, 1, -1)]
//   B_z   = (Br/pi) a/(a + rho) [beta_+ cel(kc_+, gamma^2, 1, gamma) - beta_- cel(kc_-, gamma^2, 1, gamma)].
// On the axis (rho = 0: kc = 1, gamma = 1, cel(1,1,1,1) = pi/2, cel(1,1,1,-1) = 0) this is
//   B_z = (Br/2) [z_+/sqrt(z_+^2 + a^2) - z_-/sqrt(z_-^2 + a^2)],  B_rho = 0,
// the textbook on-axis field (tested), and far away a dipole of moment M0 pi a^2 L (tested).
Vec3 AnalyticField::B_axial_closed_form_T(double x, double y, double z) const {
  const double a = magnet_.radius_mm, b = magnet_.top_z_mm();
  const double rho = std::hypot(x, y);
  const double zp = z + b, zm = z - b;
  const double sp = std::sqrt(zp * zp + (rho + a) * (rho + a)), sm = std::sqrt(zm * zm + (rho + a) * (rho + a));
  const double kcp = std::sqrt(zp * zp + (a - rho) * (a - rho)) / sp;
  const double kcm = std::sqrt(zm * zm + (a - rho) * (a - rho)) / sm;
  const double gamma = (a - rho) / (a + rho);
  const double B0 = magnet_.br_T / kPi;
  const double Bz = B0 * a / (a + rho) *
                    (zp / sp * cel(kcp, gamma * gamma, 1.0, gamma) - zm / sm * cel(kcm, gamma * gamma, 1.0, gamma));
  if (!(rho > 0)) return {0.0, 0.0, Bz};
  const double Brho = B0 * (a / sp * cel(kcp, 1.0, 1.0, -1.0) - a / sm * cel(kcm, 1.0, 1.0, -1.0));
  return {Brho * x / rho, Brho * y / rho, Bz};
}

double AnalyticField::Bz_axial_closed_form_T(double x, double y, double z) const {
  return B_axial_closed_form_T(x, y, z).z();
}

Vec3 AnalyticField::B_axial_closed_form_T(const Vec3& p) const {
  const Vec3 outer = B_axial_closed_form_T(p.x(), p.y(), p.z());
  return bore_ ? Vec3(outer - bore_->B_axial_closed_form_T(p)) : outer;
}

namespace {
// A point at height z against a magnet of radius R and height L: t1, t2 = z -+ L/2 (heights above the
// bottom and top face planes), a_i = |t_i|, t_i^2.
struct SlabPoint {
  double R, L, t1, t2, a1, a2, t1sq, t2sq;
  SlabPoint(double R_mm, double L_mm, double z) : R(R_mm), L(L_mm), t1(z - 0.5 * L_mm), t2(z + 0.5 * L_mm) {
    a1 = std::abs(t1);
    a2 = std::abs(t2);
    t1sq = t1 * t1;
    t2sq = t2 * t2;
  }
};

// One quadrature node (cos phi', sin phi') of the full kernel seen from (x, y): dx, dy from the node on
// the curved face, s_i = sqrt(rho^2 + t_i^2), e_i = s_i + a_i, s12 = s1 + s2, q = 1/(s1 s2 s12 e1 e2).
struct KernelNode {
  double dx, dy, s1, s2, e1, e2, s12, q;
};
[[gnu::always_inline]] inline KernelNode kernel_node(const SlabPoint& p, double x, double y, double c, double s) {
  KernelNode k;
  k.dx = x - p.R * c;
  k.dy = y - p.R * s;
  const double rho2 = k.dx * k.dx + k.dy * k.dy;
  k.s1 = std::sqrt(rho2 + p.t1sq);
  k.s2 = std::sqrt(rho2 + p.t2sq);
  k.e1 = k.s1 + p.a1;
  k.e2 = k.s2 + p.a2;
  k.s12 = k.s1 + k.s2;
  k.q = 1.0 / (k.s1 * k.s2 * k.s12 * k.e1 * k.e2);
  return k;
}
}  // namespace

// The node sums below ask for vectorization with `#pragma omp simd` and get it: clang 14 -O3
// -Rpass=loop-vectorize reports every one vectorized (width 2), and GCC likewise. Under
// UndefinedBehaviorSanitizer (build-san, scripts/san_build.sh, which defines MAGENC_UBSAN) every load and
// the index increment carry a checked branch (null, alignment, pointer-overflow, signed-integer-overflow),
// and a loop with a side exit cannot be vectorized: clang then warns that it could not honour the pragma
// (-Wpass-failed). There the request is dropped instead of left unmet; the sums are the same up to the
// order of additions.
#define MAGENC_PRAGMA(text) _Pragma(#text)
#if defined(MAGENC_UBSAN)
#define MAGENC_NODE_SIMD(...)
#else
#define MAGENC_NODE_SIMD(...) MAGENC_PRAGMA(omp simd __VA_ARGS__)
#endif

double AnalyticField::Bz_aligned_T(double x, double y, double z) const {
  const SlabPoint p(magnet_.radius_mm, magnet_.height_mm, z);
  const double R = p.R, L = p.L, t1sq = p.t1sq, t2sq = p.t2sq;
  const NodeTable& tab = table_for(std::hypot(x, y), z);
  const double* __restrict cphi = tab.cos_phi.data();
  const double* __restrict sphi = tab.sin_phi.data();
  const int n = tab.n;
  double acc = 0.0;
MAGENC_NODE_SIMD(reduction(+ : acc))
  for (int j = 0; j < n; ++j) {
    const double dx = x - R * cphi[j], dy = y - R * sphi[j];
    const double rho2 = dx * dx + dy * dy;
    const double s1 = std::sqrt(rho2 + t1sq), s2 = std::sqrt(rho2 + t2sq);
    // 1/s1 - 1/s2 = (t2^2 - t1^2)/(s1 s2 (s1 + s2)) = 2 z L/(s1 s2 (s1 + s2))
    acc += cphi[j] / (s1 * s2 * (s1 + s2));
  }
  const double weight = 2.0 * kPi / n;
  return magnet_.br_T * R / (4.0 * kPi) * weight * (2.0 * z * L) * acc;
}

// Full kernel. Per node one division: with e_i = s_i + a_i, s12 = s1 + s2 and
// q = 1/(s1 s2 s12 e1 e2):  1/(s1 s2 s12) = e1 e2 q,  g/L = [(a1 + a2 + s2) s12 + a1 (a1 + a2)] q
// (above/below the slab), gr = -(s1 e1 + s2 e2) s12 q (beside it).
// With kAxial, the same nodes also give the axial part (unit M0 along z) as the field of the
// equivalent surface current K = M0 phi_hat on the curved face (Biot-Savart, z' integrated):
//   B_ax = Br R/(4 pi) Int (cos phi' (1/s1 - 1/s2), sin phi' (1/s1 - 1/s2), (R - x cos phi' - y sin phi') g) dphi'
// (total B, inside too). Beside the magnet the pole part 2/rho^2 of g integrates in closed form:
// Int (R - x cos phi' - y sin phi') 2/rho^2 dphi' = 4 pi/R inside (r < R), 0 outside (the 2-D field of
// a solenoid's current sheet). The integrands are analytic in the same strip as the diametric ones.
template <bool kAxial>
void AnalyticField::B_aligned_parts_T(double x, double y, double z, Vec3& Bd, Vec3& Bax) const {
  const SlabPoint p(magnet_.radius_mm, magnet_.height_mm, z);
  const double R = p.R, L = p.L, a1 = p.a1, a2 = p.a2;
  const NodeTable& tab = table_for(std::hypot(x, y), z);
  const double* __restrict cphi = tab.cos_phi.data();
  const double* __restrict sphi = tab.sin_phi.data();
  const int n = tab.n;
  double acc_x = 0.0, acc_y = 0.0, acc_z = 0.0, acc_zs = 0.0, acc_ax = 0.0;
  if (p.t1 * p.t2 >= 0) {
    // Above or below the magnet's slab: g = L*N/D without cancellation.
    const double a12 = a1 + a2, a1a12 = a1 * (a1 + a2);
MAGENC_NODE_SIMD(reduction(+ : acc_x, acc_y, acc_z, acc_zs, acc_ax))
    for (int j = 0; j < n; ++j) {
      const auto [dx, dy, s1, s2, e1, e2, s12, q] = kernel_node(p, x, y, cphi[j], sphi[j]);
      const double g = ((a12 + s2) * s12 + a1a12) * q;  // times L below
      const double kz = e1 * e2 * q;                      // 1/(s1 s2 (s1 + s2))
      acc_x += cphi[j] * dx * g;
      acc_y += cphi[j] * dy * g;
      acc_z += cphi[j] * kz;
      if constexpr (kAxial) {
        acc_zs += sphi[j] * kz;
        acc_ax += (R - x * cphi[j] - y * sphi[j]) * g;
      }
    }
    acc_x *= L;
    acc_y *= L;
    acc_ax *= L;
  } else {
    // Beside the magnet (|z| < L/2): g = (a1/s1 + a2/s2)/rho^2 has a pole at
    // rho = 0 (the curved face). Split g = 2/rho^2 + gr with the regular part
    // gr = -[1/(s1 (s1 + a1)) + 1/(s2 (s2 + a2))]; the pole part integrates in
    // closed form (2-D field of a cos-charged circle, see two_d_dipole_integral).
MAGENC_NODE_SIMD(reduction(+ : acc_x, acc_y, acc_z, acc_zs, acc_ax))
    for (int j = 0; j < n; ++j) {
      const auto [dx, dy, s1, s2, e1, e2, s12, q] = kernel_node(p, x, y, cphi[j], sphi[j]);
      const double gr = -(s1 * e1 + s2 * e2) * s12 * q;
      const double kz = e1 * e2 * q;
      acc_x += cphi[j] * dx * gr;
      acc_y += cphi[j] * dy * gr;
      acc_z += cphi[j] * kz;
      if constexpr (kAxial) {
        acc_zs += sphi[j] * kz;
        acc_ax += (R - x * cphi[j] - y * sphi[j]) * gr;
      }
    }
    const double weight = 2.0 * kPi / n;
    const Eigen::Vector2d I = two_d_dipole_integral(x, y, R);
    acc_x += 2.0 * I.x() / weight;  // the sums below are multiplied by the weight
    acc_y += 2.0 * I.y() / weight;
    if constexpr (kAxial)
      if (x * x + y * y < R * R) acc_ax += 2.0 * (2.0 * kPi / R) / weight;
  }
  const double pref = magnet_.br_T * R / (4.0 * kPi) * (2.0 * kPi / n);
  Bd = {pref * acc_x, pref * acc_y, pref * (2.0 * z * L) * acc_z};
  if constexpr (kAxial) Bax = {pref * (2.0 * z * L) * acc_z, pref * (2.0 * z * L) * acc_zs, pref * acc_ax};
}

Vec3 AnalyticField::B_aligned_T(double x, double y, double z) const {
  Vec3 Bd, unused;
  B_aligned_parts_T<false>(x, y, z, Bd, unused);
  return Bd;
}

// Bz only, diametric and axial parts (elevation != 0): the nodes of the full kernel, z parts only.
void AnalyticField::Bz_aligned_parts_T(double x, double y, double z, double& bz_d, double& bz_ax) const {
  const SlabPoint p(magnet_.radius_mm, magnet_.height_mm, z);
  const double R = p.R, L = p.L, a1 = p.a1, a2 = p.a2;
  const NodeTable& tab = table_for(std::hypot(x, y), z);
  const double* __restrict cphi = tab.cos_phi.data();
  const double* __restrict sphi = tab.sin_phi.data();
  const int n = tab.n;
  double acc_z = 0.0, acc_ax = 0.0;
  if (p.t1 * p.t2 >= 0) {
    const double a12 = a1 + a2, a1a12 = a1 * (a1 + a2);
MAGENC_NODE_SIMD(reduction(+ : acc_z, acc_ax))
    for (int j = 0; j < n; ++j) {
      const auto [dx, dy, s1, s2, e1, e2, s12, q] = kernel_node(p, x, y, cphi[j], sphi[j]);
      acc_z += cphi[j] * e1 * e2 * q;
      acc_ax += (R - x * cphi[j] - y * sphi[j]) * ((a12 + s2) * s12 + a1a12) * q;
    }
    acc_ax *= L;
  } else {
MAGENC_NODE_SIMD(reduction(+ : acc_z, acc_ax))
    for (int j = 0; j < n; ++j) {
      const auto [dx, dy, s1, s2, e1, e2, s12, q] = kernel_node(p, x, y, cphi[j], sphi[j]);
      acc_z += cphi[j] * e1 * e2 * q;
      acc_ax -= (R - x * cphi[j] - y * sphi[j]) * (s1 * e1 + s2 * e2) * s12 * q;
    }
    if (x * x + y * y < R * R) acc_ax += 2.0 * (2.0 * kPi / R) / (2.0 * kPi / n);
  }
  const double pref = magnet_.br_T * R / (4.0 * kPi) * (2.0 * kPi / n);
  bz_d = pref * (2.0 * z * L) * acc_z;
  bz_ax = pref * acc_ax;
}

bool AnalyticField::in_far_field(const Vec3& p) const {
  const double a = std::max(magnet_.radius_mm, magnet_.top_z_mm());
  return std::hypot(p.x(), p.y(), p.z()) > kFarFieldRadius * a;
}

Vec3 AnalyticField::multipole_B_T(const Vec3& p) const {
  // B = Br/(4 pi) grad(m . grad Phi), Phi(x) = Int_V dV'/|x - x'| = q0/r + q2 P2(cos theta)/r^3 + O(a^4/r^5)
  // (only even l: the body is symmetric about z = 0), q0 = V, q2 = Int (z'^2 - rho'^2/2) dV'. Since
  // P2(cos theta)/r^3 = (1/2) d^2/dz^2 (1/r), the l = 2 term is (q2/2) times the contraction of the fourth
  // derivative tensor of 1/r. Written in n = x/r and powers of 1/r, so nothing overflows at any finite r.
  const double R = magnet_.radius_mm, Ri = magnet_.inner_radius_mm, L = magnet_.height_mm;
  const double r = std::hypot(p.x(), p.y(), p.z()), inv = 1.0 / r;
  const Vec3 n = p * inv;
  const Vec3 m = br_inside_T_ / magnet_.br_T;  // unit magnetization direction
  const double V = kPi * (R * R - Ri * Ri) * L;
  const double q2 = V * L * L / 12.0 - kPi * L * (R * R * R * R - Ri * Ri * Ri * Ri) / 4.0;
  const double mn = m.dot(n), nz = n.z(), mz = m.z();
  const double inv3 = inv * inv * inv, inv5 = inv3 * inv * inv;
  const Vec3 dipole = (3.0 * mn * n - m) * (V * inv3);
  const Vec3 ez = Vec3::UnitZ();
  const Vec3 quad = 105.0 * mn * nz * nz * n - 15.0 * (nz * nz * m + 2.0 * mn * nz * ez + 2.0 * mz * nz * n + mn * n) +
                    3.0 * (m + 2.0 * mz * ez);
  return magnet_.br_T / (4.0 * kPi) * (dipole + (0.5 * q2 * inv5) * quad);
}

Vec3 AnalyticField::B_T(const Vec3& p) const {
  if (in_far_field(p)) return multipole_B_T(p);
  if (!bore_) return cylinder_B_T(p);
  return cylinder_B_T(p) - bore_->cylinder_B_T(p);
}

double AnalyticField::Bz_T(const Vec3& p) const {
  if (in_far_field(p)) return multipole_B_T(p).z();
  if (!bore_) return cylinder_Bz_T(p);
  return cylinder_Bz_T(p) - bore_->cylinder_Bz_T(p);
}

Vec3 AnalyticField::cylinder_B_T(const Vec3& p) const {
  // Rotate the point into the frame where M0 is along +x, evaluate, rotate back.
  const double xa = cos_alpha_ * p.x() + sin_alpha_ * p.y();
  const double ya = -sin_alpha_ * p.x() + cos_alpha_ * p.y();
  Vec3 Ba, Bax;
  if (sin_el_ == 0.0) {
    B_aligned_parts_T<false>(xa, ya, p.z(), Ba, Bax);
  } else {
    // Elevation: diametric part scaled by cos(el), axial part (total B already) by sin(el);
    // both are vectors of the aligned frame, rotated back together.
    B_aligned_parts_T<true>(xa, ya, p.z(), Ba, Bax);
    Ba = cos_el_ * Ba + sin_el_ * Bax;
  }
  Vec3 B(cos_alpha_ * Ba.x() - sin_alpha_ * Ba.y(), sin_alpha_ * Ba.x() + cos_alpha_ * Ba.y(), Ba.z());
  if (std::hypot(p.x(), p.y()) < magnet_.radius_mm && std::abs(p.z()) < magnet_.top_z_mm()) {
    B.x() += br_inside_T_.x();  // B = mu0 (H + M0) inside (diametric part; the axial part is total B)
    B.y() += br_inside_T_.y();
  }
  return B;
}

double AnalyticField::cylinder_Bz_T(const Vec3& p) const {
  const double xa = cos_alpha_ * p.x() + sin_alpha_ * p.y();
  const double ya = -sin_alpha_ * p.x() + cos_alpha_ * p.y();
  if (sin_el_ == 0.0) return Bz_aligned_T(xa, ya, p.z());
  double bz_d = 0, bz_ax = 0;
  Bz_aligned_parts_T(xa, ya, p.z(), bz_d, bz_ax);
  return cos_el_ * bz_d + sin_el_ * bz_ax;
}

Eigen::Matrix3Xd AnalyticField::B_T(const Eigen::Matrix3Xd& p_mm) const {
  Eigen::Matrix3Xd out(3, p_mm.cols());
  const Eigen::Index n = p_mm.cols();
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < n; ++i) out.col(i) = B_T(Vec3(p_mm.col(i)));
  return out;
}

Eigen::VectorXd AnalyticField::Bz_T(const Eigen::Matrix3Xd& p_mm) const {
  Eigen::VectorXd out(p_mm.cols());
  const Eigen::Index n = p_mm.cols();
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < n; ++i) out[i] = Bz_T(Vec3(p_mm.col(i)));
  return out;
}

}  // namespace magenc
