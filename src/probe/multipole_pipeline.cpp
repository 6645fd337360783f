#include "probe/multipole_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "core/vector_math.hpp"
#include "probe/trig_interpolation.hpp"

namespace magenc {

namespace {
constexpr double kEnvelopeTol = 1e-8;  // the envelopes' neglected orders, relative to A_1
constexpr int kMaxEnvelopeOrder = 200;
constexpr double kHarmonicTol = 1e-9;  // harmonics below this of A_1 at the sample's height are skipped

// GCC on x86-64 builds the kernel below twice, for AVX2 and for the baseline (the same operations, no FMA:
// the same sums), and picks one at load time, as core/vector_math.cpp does.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define MAGENC_MP_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MAGENC_MP_CLONES
#endif

// One probe's geometry at the M coarse angles theta_j (vectors over j): q = P - e^{i theta_j} d, rho = |q|,
// the scaled radius v = (rho - r0) / reach, its Chebyshev values t[i][j], and e^{i chi} = q conj(P) / (rho |P|).
// Returns the largest |v|.
struct ProbeAngles {
  int M = 0, nr = 0;
  const double *zr = nullptr, *zi = nullptr;  // e^{i theta_j}
  double* rho = nullptr;                       // (M) and the others below: scratch of the caller
  double *ur = nullptr, *ui = nullptr;         // e^{i chi}
  double* t = nullptr;                         // nr x M
};
MAGENC_MP_CLONES double probe_geometry(const ProbeAngles& g, double Px, double Py, double dx, double dy, double r0,
                                       double reach) {
  const int M = g.M;
  const double Pabs = std::sqrt(Px * Px + Py * Py);
  double vmax = 0;
  for (int j = 0; j < M; ++j) {
    const double qx = Px - (g.zr[j] * dx - g.zi[j] * dy), qy = Py - (g.zr[j] * dy + g.zi[j] * dx);
    const double rho = std::sqrt(qx * qx + qy * qy);
    const double inv = 1.0 / (rho * Pabs);
    g.ur[j] = (qx * Px + qy * Py) * inv;
    g.ui[j] = (qy * Px - qx * Py) * inv;
    const double v = (rho - r0) / reach;
    g.rho[j] = v;
    vmax = std::max(vmax, std::abs(v));
  }
  for (int j = 0; j < M; ++j) g.t[j] = 1.0;
  if (g.nr > 1)
    for (int j = 0; j < M; ++j) g.t[M + j] = g.rho[j];
  for (int i = 2; i < g.nr; ++i)
    for (int j = 0; j < M; ++j) g.t[i * M + j] = 2.0 * g.rho[j] * g.t[(i - 1) * M + j] - g.t[(i - 2) * M + j];
  return vmax;
}

// Four coarse angles at once (GCC/Clang vector extension: one AVX2 register, two SSE2 registers), in memory
// at double alignment (core/vector_math.cpp does the same).
typedef double v4d __attribute__((vector_size(32)));
typedef double v4d_mem __attribute__((vector_size(32), aligned(8), may_alias));

// One ring's harmonics (columns c0 .. c0 + nc - 1 of ct, om, U, V) for one probe, four coarse angles per
// step (g.M a multiple of 4): ph = (e^{i chi})^p, then per harmonic n = 1, 3, ..: A = sum_i ct[i][c] t[i] (the
// amplitude at the probe's radius), E = A ph, U[c] += om E, V[c] += omc conj(E), ph *= e^{2 i p chi}. U, V:
// per column the real parts (M), then the imaginary ones (M).
MAGENC_MP_CLONES void ring_envelopes(const ProbeAngles& g, int p, std::size_t cols, std::size_t c0, std::size_t nc,
                                     const double* ct, const double* om, double* U, double* V) {
  const int M = g.M;
  for (int j0 = 0; j0 < M; j0 += 4) {
    const v4d ur = *reinterpret_cast<const v4d_mem*>(g.ur + j0), ui = *reinterpret_cast<const v4d_mem*>(g.ui + j0);
    v4d br = ur, bi = ui, pr = {1.0, 1.0, 1.0, 1.0}, pi = {0.0, 0.0, 0.0, 0.0};
    for (int e = p;;) {  // (pr, pi) = u^p by binary powering
      if (e & 1) {
        const v4d x = pr * br - pi * bi;
        pi = pr * bi + pi * br;
        pr = x;
      }
      e >>= 1;
      if (!e) break;
      const v4d x = br * br - bi * bi;
      bi = 2.0 * br * bi;
      br = x;
    }
    br = pr * pr - pi * pi;  // e^{2 i p chi}
    bi = 2.0 * pr * pi;
    for (std::size_t l = 0; l < nc; ++l) {
      const std::size_t c = c0 + l;
      v4d A = ct[c] * *reinterpret_cast<const v4d_mem*>(g.t + j0);
      for (int i = 1; i < g.nr; ++i) A += ct[std::size_t(i) * cols + c] * *reinterpret_cast<const v4d_mem*>(g.t + i * M + j0);
      const double o0 = om[c], o1 = om[cols + c], o2 = om[2 * cols + c], o3 = om[3 * cols + c];
      const v4d er = A * pr, ei = A * pi;
      v4d_mem* Ur = reinterpret_cast<v4d_mem*>(U + 2 * c * std::size_t(M) + std::size_t(j0));
      v4d_mem* Ui = reinterpret_cast<v4d_mem*>(U + (2 * c + 1) * std::size_t(M) + std::size_t(j0));
      v4d_mem* Vr = reinterpret_cast<v4d_mem*>(V + 2 * c * std::size_t(M) + std::size_t(j0));
      v4d_mem* Vi = reinterpret_cast<v4d_mem*>(V + (2 * c + 1) * std::size_t(M) + std::size_t(j0));
      *Ur += o0 * er - o1 * ei;
      *Ui += o0 * ei + o1 * er;
      *Vr += o2 * er + o3 * ei;
      *Vi += o3 * er - o2 * ei;
      const v4d x = pr * br - pi * bi;
      pi = pr * bi + pi * br;
      pr = x;
    }
  }
}

std::complex<double> power(std::complex<double> u, int e) {
  std::complex<double> r(1.0, 0.0);
  while (e > 0) {
    if (e & 1) r *= u;
    u *= u;
    e >>= 1;
  }
  return r;
}
}  // namespace

MultipolePipeline::MultipolePipeline(std::vector<const MultipoleRingModel*> rings, const std::vector<ProbeArray>& arrays,
                                     int pole_pairs, int steps)
    : rings_(std::move(rings)), arrays_(arrays), p_(pole_pairs), n_(steps) {
  if (rings_.empty() || !rings_[0]) throw InputError("the multipole engine needs the master ring's model");
  const MultipoleRingModel& m0 = *rings_[0];
  for (const MultipoleRingModel* r : rings_)
    if (!r || r->r0_mm() != m0.r0_mm() || r->plane_z_mm() != m0.plane_z_mm() || r->reach_rho_mm() != m0.reach_rho_mm() ||
        r->reach_z_mm() != m0.reach_z_mm() || r->rho_nodes() != m0.rho_nodes())
      throw InputError("the multipole engine's rings must share the read circle, plane, reach and grid");
  if (pole_pairs < 1) throw InputError("pole_pairs = " + std::to_string(pole_pairs) + " is out of range: allowed >= 1");
  if (steps < 16) throw InputError("steps = " + std::to_string(steps) + " is out of range: allowed >= 16");
  for (const ProbeArray& a : arrays_) {
    if (a.is_point()) throw InputError("the multipole engine reads Bz arrays: allowed two, diff4, ring:N");
    std::vector<Probe> ps;
    for (std::size_t k = 0; k < a.size(); ++k) {
      const double b = deg_to_rad(a.angle_deg[k]);
      ps.push_back({m0.r0_mm() * std::cos(b), m0.r0_mm() * std::sin(b), cd(a.w_cos[k], a.w_sin[k])});
    }
    probes_.push_back(std::move(ps));
  }
  cos_pt_.resize(std::size_t(n_));
  sin_pt_.resize(std::size_t(n_));
  for (int m = 0; m < n_; ++m) {
    // p theta_m reduced exactly (integer arithmetic) before the trigonometry.
    const double a = 2.0 * kPi * static_cast<double>((static_cast<long>(p_) * m) % n_) / n_;
    cos_pt_[std::size_t(m)] = std::cos(a);
    sin_pt_[std::size_t(m)] = std::sin(a);
  }
}

int MultipolePipeline::envelope_order(const Mount& mt) const {
  std::vector<Eigen::MatrixXd> amp;
  harmonics_at(rings_[0]->plane_z_mm() + mt.dz_mm, amp);
  return envelope_order(mt, amp);
}

void MultipolePipeline::harmonics_at(double z_mm, std::vector<Eigen::MatrixXd>& amp) const {
  thread_local std::vector<Eigen::MatrixXd> full;  // (per thread: no allocation per sample)
  full.resize(rings_.size());
  amp.resize(rings_.size());
  for (std::size_t r = 0; r < rings_.size(); ++r) rings_[r]->amplitudes_at_z(z_mm, full[r]);
  // The harmonics that matter at this height (the model keeps those of the whole reach).
  const double a1 = full[0].col(0).cwiseAbs().sum();
  for (std::size_t r = 0; r < rings_.size(); ++r) {
    Eigen::Index H = 1;
    for (Eigen::Index l = 0; l < full[r].cols(); ++l)
      if (full[r].col(l).cwiseAbs().sum() > kHarmonicTol * a1) H = l + 1;
    amp[r] = full[r].leftCols(H);
  }
}

int MultipolePipeline::envelope_order(const Mount& mt, const std::vector<Eigen::MatrixXd>& amp) const {
  int J = 0;
  if (force_j_ >= 0) {
    J = force_j_;
  } else {
    const double d = std::hypot(mt.dx_mm, mt.dy_mm);
    if (d == 0.0) return 0;
    double pmin = rings_[0]->r0_mm();
    for (const auto& ps : probes_)
      for (const Probe& q : ps) pmin = std::min(pmin, std::hypot(q.x + mt.sx_mm, q.y + mt.sy_mm));
    const double x = d / pmin;
    const double a1 = amp[0].col(0).cwiseAbs().sum();
    for (std::size_t r = 0; r < rings_.size(); ++r)
      for (Eigen::Index l = 0; l < amp[r].cols(); ++l) {
        // Harmonic n's envelope: the phase modulation e^{i n p chi}, chi ~ x sin(theta + .), has the Bessel
        // coefficients |J_j(n p x)| <= (n p x / 2)^j / j!; b = 0.6 n p x (20 % above) covers the radius's
        // modulation of A_n and chi's higher orders. Orders from J + 1 on: w b^j / j! e^b below the tolerance.
        const double w = amp[r].col(l).cwiseAbs().sum() / a1, b = 0.6 * (2.0 * l + 1.0) * rings_[r]->pole_pairs() * x;
        double term = w * std::exp(b);
        int j = 0;
        while ((term > kEnvelopeTol || j < b) && j < kMaxEnvelopeOrder) {
          ++j;
          term *= b / j;
        }
        J = std::max(J, j - 1);
      }
    if (J >= kMaxEnvelopeOrder - 1)
      throw InputError("mount.dx_mm, dy_mm = " + num(mt.dx_mm) + ", " + num(mt.dy_mm) +
                       " mm: an eccentricity beyond the multipole engine's envelopes: allowed |d| below r0 / p");
  }
  return J;
}

int MultipolePipeline::coarse_angles(int J) {
  // 2J + 1 rounded up to a length of factors 2, 3, 5 and 7 only (FFTW's fast sizes).
  for (int M = 2 * J + 1;; ++M) {
    int r = M;
    for (const int f : {2, 3, 5, 7})
      while (r % f == 0) r /= f;
    if (r == 1) return M;
  }
}

void MultipolePipeline::envelopes(const Mount& mt, std::size_t a, int M, const std::vector<Eigen::MatrixXd>& amp,
                                  Work& w) const {
  const MultipoleRingModel& m0 = *rings_[0];
  const int nr = m0.rho_nodes();
  const double r0 = m0.r0_mm(), reach = m0.reach_rho_mm();
  const cd d(mt.dx_mm, mt.dy_mm);
  // The amplitudes' Chebyshev coefficients, row i over every (ring, harmonic) column.
  std::size_t cols = 0;
  std::vector<std::size_t> first(rings_.size());
  for (std::size_t r = 0; r < rings_.size(); ++r) {
    first[r] = cols;
    cols += static_cast<std::size_t>(amp[r].cols());
  }
  w.cols = cols;
  w.ct.resize(std::size_t(nr) * cols);
  for (std::size_t r = 0; r < rings_.size(); ++r)
    for (Eigen::Index l = 0; l < amp[r].cols(); ++l)
      for (int i = 0; i < nr; ++i) w.ct[std::size_t(i) * cols + first[r] + std::size_t(l)] = amp[r](i, l);
  const std::vector<Probe>& ps = probes_[a];
  const std::size_t K = ps.size();
  // The probes' weights times e^{+i n p arg P} (U) and e^{-i n p arg P} (V), per probe and column.
  w.om.resize(4 * K * cols);  // per probe: Re, Im of om, then of omc (cols each)
  for (std::size_t k = 0; k < K; ++k) {
    const cd Pk(ps[k].x + mt.sx_mm, ps[k].y + mt.sy_mm);
    const cd u = Pk / std::sqrt(std::norm(Pk));
    double* om = &w.om[4 * k * cols];
    for (std::size_t r = 0; r < rings_.size(); ++r) {
      const cd up = power(u, rings_[r]->pole_pairs()), up2 = up * up;
      cd ph = up;
      for (Eigen::Index l = 0; l < amp[r].cols(); ++l) {
        const std::size_t c = first[r] + std::size_t(l);
        const cd o = ps[k].w * ph, oc = ps[k].w * std::conj(ph);
        om[c] = o.real();
        om[cols + c] = o.imag();
        om[2 * cols + c] = oc.real();
        om[3 * cols + c] = oc.imag();
        ph *= up2;
      }
    }
  }
  const int Mp = (M + 3) / 4 * 4;  // padded to whole blocks of 4 (the extra angles repeat theta = 0)
  w.mp = Mp;
  w.U.assign(2 * std::size_t(Mp) * cols, 0.0);  // per column: Re U at the Mp angles, then Im U
  w.V.assign(2 * std::size_t(Mp) * cols, 0.0);
  w.geo.resize(std::size_t(Mp) * std::size_t(5 + nr));
  ProbeAngles g;
  g.M = Mp;
  g.nr = nr;
  double* base = w.geo.data();
  double* zr = base;
  double* zi = base + Mp;
  g.zr = zr;
  g.zi = zi;
  g.rho = base + 2 * Mp;
  g.ur = base + 3 * Mp;
  g.ui = base + 4 * Mp;
  g.t = base + 5 * Mp;
  if (w.m_angles != M) {  // (the table of the last M on this thread)
    w.zeta.assign(2 * std::size_t(Mp), 0.0);
    for (int j = 0; j < Mp; ++j) {
      w.zeta[std::size_t(j)] = j < M ? std::cos(2.0 * kPi * j / M) : 1.0;
      w.zeta[std::size_t(Mp + j)] = j < M ? std::sin(2.0 * kPi * j / M) : 0.0;
    }
    w.m_angles = M;
  }
  std::copy(w.zeta.begin(), w.zeta.end(), zr);
  for (std::size_t k = 0; k < K; ++k) {
    const double vmax = probe_geometry(g, ps[k].x + mt.sx_mm, ps[k].y + mt.sy_mm, d.real(), d.imag(), r0, reach);
    if (!(vmax <= 1.0 + 1e-9))
      throw InputError("a probe radius " + num(r0 + vmax * reach) + " mm (or " + num(r0 - vmax * reach) +
                       ") is off the multipole model's reach r0 +- " + num(reach) +
                       " mm: allowed mounts with |s| + |d| within the reach");
    for (std::size_t r = 0; r < rings_.size(); ++r)
      ring_envelopes(g, rings_[r]->pole_pairs(), cols, first[r], std::size_t(amp[r].cols()), w.ct.data(),
                     &w.om[4 * k * cols], w.U.data(), w.V.data());
  }
}

void MultipolePipeline::assemble(int J, const std::vector<Eigen::MatrixXd>& amp, Work& w, std::vector<cd>& z) const {
  // Envelope order f of harmonic n sits at -n p + f (U) and n p + f (V), folded modulo N; the orders up to
  // (M - 1) / 2 >= J are placed (an even M's order M/2, below the tolerance, is left out).
  const int M = coarse_angles(J), N = n_;
  J = (M - 1) / 2;
  z.assign(std::size_t(N), cd(0, 0));
  w.in.resize(std::size_t(M));
  w.out.resize(std::size_t(M));
  const ComplexDft& dft_m = ComplexDft::of(M);
  std::size_t c = 0;
  for (std::size_t r = 0; r < rings_.size(); ++r)
    for (Eigen::Index l = 0; l < amp[r].cols(); ++l, ++c) {
      const long np = static_cast<long>(2 * l + 1) * rings_[r]->pole_pairs();
      for (int side = 0; side < 2; ++side) {
        const double* src = (side == 0 ? w.U : w.V).data() + 2 * c * std::size_t(w.mp);
        for (int j = 0; j < M; ++j) w.in[std::size_t(j)] = cd(src[j], src[w.mp + j]);
        if (M > 1) dft_m.forward(w.in.data(), w.out.data());
        else w.out[0] = w.in[0];
        const long shift = side == 0 ? -np : np;
        long F = ((shift - J) % N + N) % N;  // then stepped (no division per order)
        for (int f = -J; f <= J; ++f, ++F) {
          if (F == N) F = 0;
          z[std::size_t(F)] += w.out[std::size_t(f < 0 ? f + M : f)] * (0.5 / M);
        }
      }
    }
  ComplexDft::of(N).backward(z.data(), z.data());
}

void MultipolePipeline::eps(const Mount& mt, std::vector<Eigen::VectorXd>& eps_deg, const SignalChain::Applied& chain,
                            std::vector<Eigen::VectorXd>* phi_e_deg) const {
  if (mt.tilted())
    throw InputError("mount.tilt_x_deg, tilt_y_deg, magnet_tilt_deg: the multipole engine reads untilted mounts "
                     "(the five offsets): allowed 0 (tilts need the direct pipeline)");
  const double z_mm = rings_[0]->plane_z_mm() + mt.dz_mm;
  thread_local std::vector<Eigen::MatrixXd> amp;
  harmonics_at(z_mm, amp);
  const int J = envelope_order(mt, amp);
  eps_deg.resize(arrays_.size());
  if (phi_e_deg) phi_e_deg->resize(arrays_.size());
  thread_local std::vector<cd> z;
  thread_local std::vector<double> C, S;
  thread_local Work work;
  C.resize(std::size_t(n_));
  S.resize(std::size_t(n_));
  for (std::size_t a = 0; a < arrays_.size(); ++a) {
    envelopes(mt, a, coarse_angles(J), amp, work);
    assemble(J, amp, work, z);
    for (int m = 0; m < n_; ++m) {
      double c = z[std::size_t(m)].real(), s = z[std::size_t(m)].imag();
      chain(c, s);
      C[std::size_t(m)] = c;
      S[std::size_t(m)] = s;
    }
    Eigen::VectorXd& e = eps_deg[a];
    e.resize(n_);
    // wrap(phi_e - p theta) in bulk: the channels turned back by p theta (core/vector_math.hpp).
    channel_angles(C.data(), S.data(), cos_pt_.data(), sin_pt_.data(), std::size_t(n_), e.data(), nullptr, nullptr);
    for (int m = 0; m < n_; ++m) {
      double v = e[m];
      if (v <= -kPi) v = kPi;  // (-180, 180] electrical
      e[m] = rad_to_deg(v) / p_;
    }
    if (phi_e_deg) {
      Eigen::VectorXd& ph = (*phi_e_deg)[a];
      ph.resize(n_);
      for (int m = 0; m < n_; ++m) ph[m] = rad_to_deg(std::atan2(S[std::size_t(m)], C[std::size_t(m)]));
    }
  }
}

}  // namespace magenc
