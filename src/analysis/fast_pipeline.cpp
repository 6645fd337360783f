#include "analysis/fast_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <complex>
#include <string>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "core/vector_math.hpp"
#include "probe/environment.hpp"
#include "probe/sensor.hpp"
#include "probe/spectrum.hpp"
#include "probe/trig_interpolation.hpp"

namespace magenc {

namespace {
thread_local long t_bounded_pp = 0;  // pp_bounded's successes on this thread (FastPipeline::bounded_pp_count)
}  // namespace

long FastPipeline::bounded_pp_count() { return t_bounded_pp; }


FastPipeline::FastPipeline(const CircleFieldModel& model, const std::vector<ProbeArray>& arrays, double magnet_height_mm,
                           const CircleFieldModel* axial, double elevation_deg)
    : model_(model), arrays_(arrays), magnet_height_mm_(magnet_height_mm), axial_(axial), elevation_deg_(elevation_deg) {
  const int N = model.nodes();
  if (axial_ && (axial_->nodes() != N || axial_->terms() != model.terms() || axial_->r0_mm() != model.r0_mm() ||
                 axial_->plane_z_mm() != model.plane_z_mm() || axial_->reach_xy_mm() != model.reach_xy_mm() ||
                 axial_->reach_z_mm() != model.reach_z_mm() || axial_->full_vector() != model.full_vector()))
    throw InputError("FastPipeline: the axial-magnetization model must share the field model's nodes, stencil and order");
  for (const auto& a : arrays_) {
    std::vector<int> slots;
    for (std::size_t k = 0; k < a.size(); ++k) {
      const double pos = a.angle_deg[k] * N / 360.0;
      const double r = std::round(pos);
      if (std::abs(pos - r) > 1e-9)
        throw InputError("radius.fast_steps = " + std::to_string(N) + " does not place a theta sample on probe angle " +
                         num(a.angle_deg[k]) + " deg of array " + a.name +
                         ": allowed a multiple of the array's angular step (e.g. 360 for two, diff4, ring:8)");
      const int idx = ((static_cast<int>(r) % N) + N) % N;
      auto it = std::find(angle_index_.begin(), angle_index_.end(), idx);
      if (it == angle_index_.end()) {
        angle_index_.push_back(idx);
        slots.push_back(static_cast<int>(angle_index_.size()) - 1);
      } else {
        slots.push_back(static_cast<int>(it - angle_index_.begin()));
      }
    }
    slot_.push_back(std::move(slots));
  }
  cos_theta_.resize(N);
  sin_theta_.resize(N);
  for (int m = 0; m < N; ++m) {
    cos_theta_[m] = std::cos(2.0 * kPi * m / N);
    sin_theta_[m] = std::sin(2.0 * kPi * m / N);
  }
  using C = CircleFieldModel::Construction;
  const auto banded = [](const CircleFieldModel* m) {
    return !m || m->construction() == C::symmetry || m->construction() == C::symmetrized;
  };
  residual_ = model.has_node_residual() || (axial_ && axial_->has_node_residual());
  if (banded(&model) && banded(axial_)) {
    for (int M = 24; M < N; ++M)
      if (N % M == 0) {
        coarse_ = M;
        break;
      }
  }
  if (coarse_ > 0) {
    // The interpolant's real coefficients from the M coarse samples (peak_bounds): a_0 = mean, a_k, b_k =
    // (2/M) sum x_j cos, sin(2 pi j k / M), and for M even a_{M/2} = (1/M) sum x_j (-1)^j (the half weight).
    const int M = coarse_;
    coef_map_ = Eigen::MatrixXd::Zero(2 * (M / 2) + 1, M);  // rows a_0, a_1, b_1, ..., a_{M/2}, b_{M/2}
    for (int j = 0; j < M; ++j) {
      coef_map_(0, j) = 1.0 / M;
      for (int k = 1; 2 * k < M; ++k) {
        coef_map_(2 * k - 1, j) = 2.0 / M * std::cos(2.0 * kPi * j * k / M);
        coef_map_(2 * k, j) = 2.0 / M * std::sin(2.0 * kPi * j * k / M);
      }
      if (M % 2 == 0) coef_map_(M - 1, j) = (j % 2 == 0 ? 1.0 : -1.0) / M;  // (b_{M/2} stays 0)
    }
  }
  for (int K = 3 * coarse_; coarse_ > 0 && K <= N; ++K)
    if (N % K == 0) {
      medium_ = K;
      break;
    }
  // The channels of every array as a linear map of the distinct probes' readings (columns 2a, 2a + 1).
  channel_weights_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(angle_index_.size()),
                                           static_cast<Eigen::Index>(2 * arrays_.size()));
  for (std::size_t a = 0; a < arrays_.size(); ++a)
    for (std::size_t k = 0; k < arrays_[a].size(); ++k) {
      const auto i = static_cast<Eigen::Index>(slot_[a][k]);
      channel_weights_(i, static_cast<Eigen::Index>(2 * a)) += arrays_[a].w_cos[k];
      channel_weights_(i, static_cast<Eigen::Index>(2 * a + 1)) += arrays_[a].w_sin[k];
    }
  if (residual_) asymmetry_tables();
}

void FastPipeline::asymmetry_tables() {
  // Node j = (probe's angle index - m) mod N of the model's node residual, component c, into the channels:
  // table(m, col) = sum_i channel_weights_(i, col) d_c(node of probe i at theta_m).
  const int N = model_.nodes(), C = model_.full_vector() ? 3 : 1;
  const auto P = static_cast<Eigen::Index>(angle_index_.size());
  asym_probe_max_T_.assign(angle_index_.size(), 0.0);
  const CircleFieldModel* models[2] = {&model_, axial_};
  for (int k = 0; k < 2; ++k) {
    const CircleFieldModel* md = models[k];
    const bool has = md && md->has_node_residual();
    double dmax = 0;  // the largest |d| (vector) over the nodes: a bound on |n . d| for every probe
    for (int j = 0; has && j < N; ++j) {
      double d2 = 0;
      for (int c = 0; c < C; ++c) d2 += md->node_residual_T(c, j) * md->node_residual_T(c, j);
      dmax = std::max(dmax, std::sqrt(d2));
    }
    for (double& v : asym_probe_max_T_) v += dmax;
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd& tab = asym_tables_[std::size_t(k)][std::size_t(c)];
      tab = Eigen::MatrixXd::Zero(N, channel_weights_.cols());
      for (int m = 0; has && c < C && m < N; ++m)
        for (Eigen::Index i = 0; i < P; ++i) {
          int j = angle_index_[std::size_t(i)] - m;
          if (j < 0) j += N;
          tab.row(m) += md->node_residual_T(c, j) * channel_weights_.row(i);
        }
    }
    // |n . (dC_c + i dS_c)_c| <= sqrt(sum_c |dC_c + i dS_c|^2) for a unit n (Cauchy-Schwarz): per array.
    asym_channel_max_[std::size_t(k)].assign(arrays_.size(), 0.0);
    for (std::size_t a = 0; a < arrays_.size(); ++a)
      for (int m = 0; m < N; ++m) {
        double v2 = 0;
        for (const Eigen::MatrixXd& tab : asym_tables_[std::size_t(k)])
          v2 += tab(m, Eigen::Index(2 * a)) * tab(m, Eigen::Index(2 * a)) +
                tab(m, Eigen::Index(2 * a + 1)) * tab(m, Eigen::Index(2 * a + 1));
        asym_channel_max_[std::size_t(k)][a] = std::max(asym_channel_max_[std::size_t(k)][a], std::sqrt(v2));
      }
  }
}

void FastPipeline::asymmetry(const MountKinematics* K, double ce, double se, double scale, bool probes,
                             Asymmetry& out) const {
  const int N = model_.nodes();
  const auto P = static_cast<Eigen::Index>(angle_index_.size());
  out.K = K;
  out.w[0] = scale * (axial_ ? ce : 1.0);
  out.w[1] = scale * (axial_ ? se : 0.0);
  out.probe_max_T.resize(angle_index_.size());
  for (std::size_t i = 0; i < angle_index_.size(); ++i) out.probe_max_T[i] = std::abs(scale) * asym_probe_max_T_[i];
  out.channel_max.assign(arrays_.size(), 0.0);
  for (std::size_t a = 0; a < arrays_.size(); ++a)
    for (int k = 0; k < 2; ++k) out.channel_max[a] += std::abs(out.w[k]) * asym_channel_max_[std::size_t(k)][a];
  out.probes.resize(probes ? N : 0, P);
  const CircleFieldModel* models[2] = {&model_, axial_};
  const int C = model_.full_vector() ? 3 : 1;
  for (int m = 0; probes && m < N; ++m) {
    const Eigen::Vector3d n = asym_normal(out, m);
    const double nc[3] = {n.z(), n.x(), n.y()};  // the residuals' component order: Bz, Bx, By
    for (Eigen::Index i = 0; i < P; ++i) {
      int j = angle_index_[std::size_t(i)] - m;
      if (j < 0) j += N;
      double b = 0;
      for (int k = 0; k < 2; ++k)
        if (models[k] && models[k]->has_node_residual())
          for (int c = 0; c < C; ++c) b += out.w[k] * nc[c] * models[k]->node_residual_T(c, j);
      out.probes(m, i) = b;
    }
  }
}

Eigen::Vector3d FastPipeline::asym_normal(const Asymmetry& as, int m) const {
  return as.K ? as.K->direction_to_magnet(as.K->n_fixed, cos_theta_[std::size_t(m)], sin_theta_[std::size_t(m)])
              : Eigen::Vector3d::UnitZ();
}

std::complex<double> FastPipeline::asym_channel(const Asymmetry& as, const Eigen::Vector3d& n, int m,
                                                std::size_t a) const {
  const double nc[3] = {n.z(), n.x(), n.y()};
  const auto ic = static_cast<Eigen::Index>(2 * a);
  double dC = 0, dS = 0;
  for (int k = 0; k < 2; ++k) {
    if (as.w[k] == 0.0) continue;
    for (int c = 0; c < 3; ++c) {
      if (nc[c] == 0.0) continue;
      const Eigen::MatrixXd& tab = asym_tables_[std::size_t(k)][std::size_t(c)];
      dC += as.w[k] * nc[c] * tab(m, ic);
      dS += as.w[k] * nc[c] * tab(m, ic + 1);
    }
  }
  return {dC, dS};
}

void FastPipeline::interpolate(const Eigen::MatrixXd& coarse, Eigen::MatrixXd& full) const {
  // The coarse samples' discrete Fourier coefficients (a real FFT of length M), zero-padded to N and a real
  // inverse FFT of length N: trigonometric interpolation on the M equispaced nodes, exact for every
  // trigonometric polynomial of degree < M/2 (half weight on the M/2 term, M even): probe/trig_interpolation.hpp.
  const int N = model_.nodes(), M = coarse_;
  const TrigInterpolation& interp = TrigInterpolation::of(M, N);
  full.resize(N, coarse.cols());
  for (Eigen::Index c = 0; c < coarse.cols(); ++c) interp(coarse.col(c).data(), full.col(c).data());
}

void FastPipeline::finish(const Eigen::MatrixXd& R, const SignalChain::Applied& chain,
                          std::vector<Eigen::VectorXd>& eps_deg, std::vector<double>* peak_T, PpTrack* track,
                          std::vector<UnitAngles>* psi, std::vector<double>* peak_hi_T, const Asymmetry* asym) const {
  const int N = model_.nodes();
  const std::size_t A = arrays_.size();
  thread_local Eigen::MatrixXd cs;  // the channels of every array at every node: C in column 2a, S in 2a + 1
  if (R.rows() != N && (!peak_T || peak_hi_T)) {
    // No field window, or only its bounds: the channels are linear in the readings, so form them at the M
    // coarse nodes and interpolate 2 per array instead of every distinct probe.
    if (peak_T) {
      peak_bounds(R, *peak_T, *peak_hi_T);
      for (std::size_t i = 0; asym && i < peak_T->size(); ++i) {  // |b + r| within |b| -+ max |r|
        (*peak_T)[i] = std::max(0.0, (*peak_T)[i] - asym->probe_max_T[i] * (1.0 + 1e-12));
        (*peak_hi_T)[i] += asym->probe_max_T[i] * (1.0 + 1e-12);
      }
    }
    thread_local Eigen::MatrixXd cs_coarse;
    cs_coarse.noalias() = R.lazyProduct(channel_weights_);  // (tiny: no blocked product)
    if (track && medium_ > 0 && pp_bounded(cs_coarse, chain, *track, asym)) return;
    interpolate(cs_coarse, cs);
    for (int m = 0; asym && m < N; ++m) {  // the field's asymmetry at the nominal nodes (symmetrized models)
      const Eigen::Vector3d n = asym_normal(*asym, m);
      for (std::size_t a = 0; a < A; ++a) {
        const std::complex<double> d = asym_channel(*asym, n, m, a);
        cs(m, static_cast<Eigen::Index>(2 * a)) += d.real();
        cs(m, static_cast<Eigen::Index>(2 * a + 1)) += d.imag();
      }
    }
  } else {
    thread_local Eigen::MatrixXd full;
    const Eigen::MatrixXd* Rn = &R;
    if (R.rows() != N) {
      interpolate(R, full);
      Rn = &full;
    }
    if (asym) {  // the field's asymmetry at the nominal nodes (symmetrized models)
      if (Rn != &full) full = R;
      full += asym->probes;
      Rn = &full;
    }
    if (peak_T) {
      peak_T->resize(angle_index_.size());
      for (std::size_t i = 0; i < peak_T->size(); ++i)
        (*peak_T)[i] = Rn->col(static_cast<Eigen::Index>(i)).cwiseAbs().maxCoeff();
      if (peak_hi_T) *peak_hi_T = *peak_T;  // (every node evaluated: the bounds are the value)
    }
    // cs = Rn W, column by column as sums of scaled probe columns (contiguous, vectorized).
    cs.setZero(N, channel_weights_.cols());
    for (Eigen::Index c = 0; c < cs.cols(); ++c)
      for (Eigen::Index i = 0; i < Rn->cols(); ++i)
        if (channel_weights_(i, c) != 0.0) cs.col(c) += channel_weights_(i, c) * Rn->col(i);
  }
  if (!track) return angles_of_channels(cs, chain, eps_deg, psi);
  std::vector<double> C(A), S(A);
  for (int m = 0; m < N; ++m) {
    for (std::size_t a = 0; a < A; ++a) {
      C[a] = cs(m, static_cast<Eigen::Index>(2 * a));
      S[a] = cs(m, static_cast<Eigen::Index>(2 * a + 1));
    }
    track_channels(m, C, S, chain, *track);
    if (track->wrapped) return;
  }
}

void FastPipeline::peak_bounds(const Eigen::MatrixXd& R, std::vector<double>& lo_T, std::vector<double>& hi_T) const {
  const int M = coarse_, H = M / 2;
  // Each probe's interpolant's coefficients (rows a_0, a_1, b_1, ..., a_{M/2}, b_{M/2}), one small product.
  thread_local Eigen::MatrixXd coef;
  coef.noalias() = coef_map_ * R;
  const double h = 2.0 * kPi / M;
  lo_T.resize(angle_index_.size());
  hi_T.resize(angle_index_.size());
  for (Eigen::Index i = 0; i < R.cols(); ++i) {
    const double* a = coef.col(i).data();
    double D2 = 0;  // >= |b''| everywhere
    for (int k = 1; k <= H; ++k) D2 += double(k) * k * std::sqrt(a[2 * k - 1] * a[2 * k - 1] + a[2 * k] * a[2 * k]);
    // Between two coarse nodes h apart, |b| exceeds the larger end value by at most |b''| h^2 / 8. The
    // relative margins 1e-12 cover the round-off of the interpolated values eps_field takes the peaks from.
    const double coarse = R.col(i).cwiseAbs().maxCoeff();
    lo_T[std::size_t(i)] = coarse * (1.0 - 1e-12);
    hi_T[std::size_t(i)] = (coarse + D2 * h * h / 8.0) * (1.0 + 1e-12);
  }
}

std::complex<double> FastPipeline::w_at(int m, const std::vector<double>& Wr, const std::vector<double>& Wi,
                                        int kmin) const {
  const int N = model_.nodes(), nk = static_cast<int>(Wr.size());
  const double qc = cos_theta_[std::size_t(m)], qs = sin_theta_[std::size_t(m)];
  double ar = Wr[std::size_t(nk - 1)], ai = Wi[std::size_t(nk - 1)];
  for (int j = nk - 2; j >= 0; --j) {
    const double nr = ar * qc - ai * qs + Wr[std::size_t(j)];
    ai = ar * qs + ai * qc + Wi[std::size_t(j)];
    ar = nr;
  }
  const int i0 = static_cast<int>(((static_cast<long>(kmin) * m) % N + N) % N);  // e^{i kmin theta_m}
  const double c0 = cos_theta_[std::size_t(i0)], s0 = sin_theta_[std::size_t(i0)];
  return {ar * c0 - ai * s0, ar * s0 + ai * c0};
}

void FastPipeline::asym_on_grid(const Asymmetry& as, int K, std::vector<std::complex<double>>& out) const {
  const int s = model_.nodes() / K;
  out.resize(static_cast<std::size_t>(K) * arrays_.size());
  for (int p = 0; p < K; ++p) {
    const Eigen::Vector3d n = asym_normal(as, p * s);
    for (std::size_t a = 0; a < arrays_.size(); ++a) out[std::size_t(p) * arrays_.size() + a] = asym_channel(as, n, p * s, a);
  }
}

bool FastPipeline::pp_bounded(const Eigen::MatrixXd& cs_coarse, const SignalChain::Applied& chain,
                              PpTrack& track, const Asymmetry* asym) const {
  using cd = std::complex<double>;
  if (asym && !chain.ideal) return false;  // (the chain would act on the asymmetry too)
  const int N = model_.nodes(), M = coarse_, K = medium_, s = N / K;
  const int kmin = -(M / 2) - 1, kmax = M / 2 - 1, nk = kmax - kmin + 1;  // the frequencies of w
  const ComplexDft& dft_m = ComplexDft::of(M);  // unscaled (probe/trig_interpolation.hpp)
  const ComplexDft& dft_k = ComplexDft::of(K);
  thread_local std::vector<cd> z, Z, Y, wp;
  thread_local std::vector<double> Wr, Wi;
  z.resize(static_cast<std::size_t>(M));
  Z.resize(static_cast<std::size_t>(M));
  wp.resize(static_cast<std::size_t>(K));
  std::vector<double> lo(arrays_.size()), hi(arrays_.size());  // (the track is set once every array is done)
  Wr.resize(static_cast<std::size_t>(nk));
  Wi.resize(static_cast<std::size_t>(nk));
  thread_local std::vector<cd> asym_grid;  // the asymmetry's part of every array's channels on the K-node grid
  if (asym) asym_on_grid(*asym, K, asym_grid);
  for (std::size_t a = 0; a < arrays_.size(); ++a) {
    for (int j = 0; j < M; ++j) {
      double C = cs_coarse(j, static_cast<Eigen::Index>(2 * a)), S = cs_coarse(j, static_cast<Eigen::Index>(2 * a + 1));
      chain(C, S);  // affine: commutes with the interpolation
      z[std::size_t(j)] = cd(C, S);
    }
    dft_m.forward(z.data(), Z.data());
    // z's coefficients (the M/2 term split in half between +-M/2), shifted by one: w = z e^{-i theta}.
    const cd W0 = Z[1] / double(M);  // w's constant term: z's frequency 1
    const double A = std::sqrt(W0.real() * W0.real() + W0.imag() * W0.imag());
    if (!(A > 0)) return false;
    const cd rot = std::conj(W0) / A;
    // Symmetrized models: w + r_m at node m, r_m = (dC + i dS) e^{-i theta_m} rot (the asymmetry's part of
    // the channels), |r_m| <= dmax, so |arg(w + r) - arg w| <= asin(dmax / |w|) <= asin(dmax / (A - E)).
    const auto r_at = [&](int m) {
      return asym_channel(*asym, asym_normal(*asym, m), m, a) * cd(cos_theta_[std::size_t(m)], -sin_theta_[std::size_t(m)]) * rot;
    };
    const double dmax = asym ? asym->channel_max[a] : 0.0;
    double E = 0, D1 = 0, D2 = 0;
    for (int q = -(M / 2); q <= M / 2; ++q) {
      cd v = Z[std::size_t((q % M + M) % M)] * rot / double(M);
      if (2 * std::abs(q) == M) v *= 0.5;
      const int k = q - 1;
      Wr[std::size_t(k - kmin)] = v.real();
      Wi[std::size_t(k - kmin)] = v.imag();
      if (k != 0) {
        const double av = std::sqrt(v.real() * v.real() + v.imag() * v.imag());  // (not hypot: no overflow here)
        E += av;
        D1 += std::abs(k) * av;
        D2 += double(k) * k * av;
      }
    }
    // |w| >= Re w >= A - E on the whole circle, so |eps - mean| <= 30 deg and the bounds below hold.
    const double lo_w = A - E;
    if (!(lo_w - dmax > 0.5 * A)) return false;
    const double F2 = D2 / lo_w + (D1 / lo_w) * (D1 / lo_w);  // |f''| for f = arg w
    const double h = 2.0 * kPi / K;
    // f above the chord of an interval of length h at most this (twice the asymmetry's bound added: at
    // the ends and inside)
    const double delta = F2 * h * h / 8.0 + 2.0 * std::asin(dmax / lo_w);
    if (!(delta < 0.1)) return false;
    const double td = std::tan(delta);
    // w on the K-node grid (every s-th node): its coefficients folded modulo K, one inverse FFT.
    Y.assign(static_cast<std::size_t>(K), cd(0.0, 0.0));
    for (int k = kmin; k <= kmax; ++k) Y[std::size_t((k % K + K) % K)] += cd(Wr[std::size_t(k - kmin)], Wi[std::size_t(k - kmin)]);
    dft_k.backward(Y.data(), wp.data());
    thread_local std::vector<double> t;
    t.resize(static_cast<std::size_t>(K));
    double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
    for (int p = 0; p < K; ++p) {
      if (asym)
        wp[std::size_t(p)] += asym_grid[std::size_t(p) * arrays_.size() + a] *
                              cd(cos_theta_[std::size_t(p * s)], -sin_theta_[std::size_t(p * s)]) * rot;
      t[std::size_t(p)] = wp[std::size_t(p)].imag() / wp[std::size_t(p)].real();
      t_lo = std::min(t_lo, t[std::size_t(p)]);
      t_hi = std::max(t_hi, t[std::size_t(p)]);
    }
    // An interval whose end values are below tan(f_max - delta) (above tan(f_min + delta)) holds no node
    // above the max (below the min): only the others are evaluated node by node (Horner in e^{i theta}).
    const double T_hi = (t_hi - td) / (1.0 + t_hi * td), T_lo = (t_lo + td) / (1.0 - t_lo * td);
    for (int p = 0; p < K && s > 1; ++p) {
      const double ta = t[std::size_t(p)], tb = t[std::size_t((p + 1) % K)];
      if (std::max(ta, tb) < T_hi && std::min(ta, tb) > T_lo) continue;
      for (int i = 1; i < s; ++i) {
        const int m = p * s + i;
        cd wm = w_at(m, Wr, Wi, kmin);
        if (asym) wm += r_at(m);
        const double tm = wm.imag() / wm.real();
        t_lo = std::min(t_lo, tm);
        t_hi = std::max(t_hi, tm);
      }
    }
    lo[a] = t_lo;
    hi[a] = t_hi;
  }
  track.t_lo = lo;
  track.t_hi = hi;
  ++t_bounded_pp;
  return true;
}

// The PpTrack at theta_m = 360 m/N from the channels C[a], S[a] of every array: the signal chain, then
// tan(eps) = y / x with (x, y) = (C, S) turned back by theta.
void FastPipeline::track_channels(int m, std::vector<double>& Cv, std::vector<double>& Sv,
                                  const SignalChain::Applied& chain, PpTrack& track) const {
  const double ct = cos_theta_[std::size_t(m)], st = sin_theta_[std::size_t(m)];
  for (std::size_t a = 0; a < arrays_.size(); ++a) {
    double C = Cv[a], S = Sv[a];
    chain(C, S);  // signal chain (probe/signal_chain.hpp); no-op for an ideal chain
    const double x = C * ct + S * st, y = S * ct - C * st;
    if (!(x > 0)) {
      track.wrapped = true;
      return;
    }
    const double t = y / x;
    track.t_lo[a] = std::min(track.t_lo[a], t);
    track.t_hi[a] = std::max(track.t_hi[a], t);
  }
}

void FastPipeline::angles_of_channels(const Eigen::MatrixXd& cs, const SignalChain::Applied& chain,
                                      std::vector<Eigen::VectorXd>& eps_deg, std::vector<UnitAngles>* psi) const {
  const int N = model_.nodes();
  eps_deg.resize(arrays_.size());
  if (psi) psi->resize(arrays_.size());
  thread_local std::vector<double> Cc, Sc;
  for (std::size_t a = 0; a < arrays_.size(); ++a) {
    const double* C = cs.col(static_cast<Eigen::Index>(2 * a)).data();
    const double* S = cs.col(static_cast<Eigen::Index>(2 * a + 1)).data();
    if (!chain.ideal) {
      // The signal chain (probe/signal_chain.hpp), node by node.
      Cc.resize(std::size_t(N));
      Sc.resize(std::size_t(N));
      for (int m = 0; m < N; ++m) {
        double c = C[m], s = S[m];
        chain(c, s);
        Cc[std::size_t(m)] = c;
        Sc[std::size_t(m)] = s;
      }
      C = Cc.data();
      S = Sc.data();
    }
    // eps = the angle of (C, S) turned back by theta, in [-180, 180] deg; psi = theta + eps = atan2(S, C),
    // whose cosine and sine are the normalized channels (core/vector_math.hpp, all nodes at once).
    Eigen::VectorXd& e = eps_deg[a];
    e.resize(N);
    if (speed_.acts()) {  // the steady state at speed on this array's channels (probe/speed.hpp)
      thread_local Eigen::MatrixXd ch;
      ch.resize(N, 2);
      for (int m = 0; m < N; ++m) {
        ch(m, 0) = C[m];
        ch(m, 1) = S[m];
      }
      const SpeedChain::FilteredTurn turn = speed_.filter(ch);
      const bool held = speed_.sample_hz > 0;
      double *cp = nullptr, *sp = nullptr;
      if (psi) {
        (*psi)[a].cos_psi.resize(N);
        (*psi)[a].sin_psi.resize(N);
        cp = (*psi)[a].cos_psi.data();
        sp = (*psi)[a].sin_psi.data();
      }
      channel_angles(ch.col(0).data(), ch.col(1).data(), cos_theta_.data(), sin_theta_.data(), std::size_t(N),
                     e.data(), held ? nullptr : cp, held ? nullptr : sp);
      e *= 180.0 / kPi;
      speed_.output(turn, e, 1, held ? cp : nullptr, held ? sp : nullptr);  // (held: the output's direction)
      if (psi && !held && speed_.prediction == Prediction::Ideal) {  // the channels' angle turned by the lead
        const double lead = deg_to_rad(speed_.lag_deg(1)), cl = std::cos(lead), sl = std::sin(lead);
        for (int m = 0; m < N; ++m) {
          const double c = cp[m], s = sp[m];
          cp[m] = c * cl - s * sl;
          sp[m] = s * cl + c * sl;
        }
      }
      continue;
    }
    double *cp = nullptr, *sp = nullptr;
    if (psi) {
      (*psi)[a].cos_psi.resize(N);
      (*psi)[a].sin_psi.resize(N);
      cp = (*psi)[a].cos_psi.data();
      sp = (*psi)[a].sin_psi.data();
    }
    channel_angles(C, S, cos_theta_.data(), sin_theta_.data(), std::size_t(N), e.data(), cp, sp);
    e *= 180.0 / kPi;
  }
}

void FastPipeline::eps_tilted(const Mount& mt, const SignalChain::Applied& chain, double elevation_deg,
                              std::vector<Eigen::VectorXd>& eps_deg, std::vector<double>* peak_T,
                              const EnvReadings* env, PpTrack* track, std::vector<UnitAngles>* psi,
                              std::vector<double>* peak_hi_T) const {
  if (!model_.full_vector())
    throw InputError("a tilted mount needs a surrogate with the full field vector (CircleFieldModel full_vector)");
  const int N = model_.nodes();
  const int T = model_.terms();
  const double r0 = model_.r0_mm(), zs = model_.plane_z_mm();
  const MountKinematics K(mt, zs, magnet_height_mm_);
  // Fixed-frame position of each distinct probe (angle index i -> b = 2 pi i / N).
  std::vector<Eigen::Vector3d> fixed(angle_index_.size());
  for (std::size_t i = 0; i < angle_index_.size(); ++i)
    fixed[i] = K.fixed_position_mm(r0 * cos_theta_[std::size_t(angle_index_[i])], r0 * sin_theta_[std::size_t(angle_index_[i])]);
  thread_local std::vector<double> u;
  u.resize(std::size_t(T));
  const double ce = axial_ ? std::cos(deg_to_rad(elevation_deg)) : 1.0;
  const double se = axial_ ? std::sin(deg_to_rad(elevation_deg)) : 0.0;
  const int step = coarse_ > 0 ? N / coarse_ : 1;
  thread_local Eigen::MatrixXd R;  // (per thread: no allocation per sample)
  R.resize(N / step, static_cast<Eigen::Index>(angle_index_.size()));
  for (int r = 0; r < R.rows(); ++r) {
    const int m = r * step;
    // cos, sin of theta_m from the table (the same values std::cos(2 pi m/N) gives: no trig per probe).
    const double ct = cos_theta_[std::size_t(m)], st = sin_theta_[std::size_t(m)];
    const Eigen::Vector3d n = K.direction_to_magnet(K.n_fixed, ct, st);
    for (std::size_t i = 0; i < angle_index_.size(); ++i) {
      int j = angle_index_[i] - m;
      if (j < 0) j += N;
      // Displacement from node j (nominal position of this probe at theta, magnet frame).
      const Eigen::Vector3d q = K.point_to_magnet(fixed[i], ct, st);
      model_.monomials(q.x() - r0 * cos_theta_[std::size_t(j)], q.y() - r0 * sin_theta_[std::size_t(j)], q.z() - zs, u.data());
      double Bn = model_.Bn_T(j, u.data(), n.x(), n.y(), n.z());
      // cos(al) * diametric + sin(al) * axial (B is linear in M).
      if (axial_) Bn = ce * Bn + se * axial_->Bn_T(j, u.data(), n.x(), n.y(), n.z());
      if (env) Bn = env->br_scale * Bn + env->stray_T[i];
      R(r, static_cast<Eigen::Index>(i)) = Bn;
    }
  }
  if (!residual_) return finish(R, chain, eps_deg, peak_T, track, psi, peak_hi_T);
  thread_local Asymmetry asym;  // symmetrized models: n . (the field's asymmetry) at the nominal nodes
  asymmetry(&K, ce, se, env ? env->br_scale : 1.0, coarse_ == 0 || (peak_T && !peak_hi_T), asym);
  finish(R, chain, eps_deg, peak_T, track, psi, peak_hi_T, &asym);
}

void FastPipeline::eps(const Mount& mt, std::vector<Eigen::VectorXd>& eps_deg) const {
  eps_mount(mt, SignalChain::Applied{}, elevation_deg_, eps_deg);
}

bool FastPipeline::env_readings(const ToleranceCase& c, const Mount& mt, EnvReadings& out) const {
  if (c.env.neutral()) return false;
  c.env.validate_for(SensorPrinciple::Bz);
  out.br_scale = c.env.br_scale();
  const MountKinematics K(mt, model_.plane_z_mm(), magnet_height_mm_);
  std::vector<Eigen::Vector2d> xy;
  for (int idx : angle_index_)
    xy.emplace_back(model_.r0_mm() * cos_theta_[std::size_t(idx)], model_.r0_mm() * sin_theta_[std::size_t(idx)]);
  out.stray_T = stray_readings_T(c.env.stray, K, xy, SensingArea{}, false);
  return true;
}

FastPipeline::CaseState FastPipeline::case_state(const ToleranceCase& c) const {
  if (c.elevation_deg != 0 && !axial_)
    throw InputError("a magnetization elevation deviation needs the surrogate's axial-magnetization model "
                     "(FastPipeline axial)");
  CaseState st;
  st.mount = c.env.mount_at_temperature(c.mount);
  const SignalChain chain = c.env.chain_at_temperature(c.chain);
  chain.validate();
  st.chain = chain.applied();
  st.elevation_deg = elevation_deg_ + c.elevation_deg;
  st.has_env = env_readings(c, st.mount, st.env);
  return st;
}

void FastPipeline::eps(const ToleranceCase& c, std::vector<Eigen::VectorXd>& eps_deg,
                       std::vector<UnitAngles>* psi) const {
  const CaseState st = case_state(c);
  eps_mount(st.mount, st.chain, st.elevation_deg, eps_deg, nullptr, st.env_ptr(), nullptr, psi);
}

void FastPipeline::eps_mount(const Mount& mt, const SignalChain::Applied& chain, double elevation_deg,
                             std::vector<Eigen::VectorXd>& eps_deg, std::vector<double>* peak_T,
                             const EnvReadings* env, PpTrack* track, std::vector<UnitAngles>* psi,
                             std::vector<double>* peak_hi_T) const {
  if (mt.tilted()) return eps_tilted(mt, chain, elevation_deg, eps_deg, peak_T, env, track, psi, peak_hi_T);
  const int N = model_.nodes();
  const int T = model_.terms();
  thread_local std::vector<double> u;
  u.resize(std::size_t(T));
  const double ce = axial_ ? std::cos(deg_to_rad(elevation_deg)) : 1.0;
  const double se = axial_ ? std::sin(deg_to_rad(elevation_deg)) : 0.0;
  const int step = coarse_ > 0 ? N / coarse_ : 1;
  thread_local Eigen::MatrixXd R;  // (per thread: no allocation per sample)
  R.resize(N / step, static_cast<Eigen::Index>(angle_index_.size()));
  for (int r = 0; r < R.rows(); ++r) {
    const int m = r * step;
    const double c = cos_theta_[m], s = sin_theta_[m];
    // Displacement of every probe from its nominal node: Rot(-theta) s - d, dz.
    const double ex = c * mt.sx_mm + s * mt.sy_mm - mt.dx_mm;
    const double ey = -s * mt.sx_mm + c * mt.sy_mm - mt.dy_mm;
    model_.monomials(ex, ey, mt.dz_mm, u.data());
    for (std::size_t i = 0; i < angle_index_.size(); ++i) {
      int j = angle_index_[i] - m;
      if (j < 0) j += N;
      double b = axial_ ? ce * model_.bz_T(j, u.data()) + se * axial_->bz_T(j, u.data()) : model_.bz_T(j, u.data());
      if (env) b = env->br_scale * b + env->stray_T[i];
      R(r, static_cast<Eigen::Index>(i)) = b;
    }
  }
  if (!residual_) return finish(R, chain, eps_deg, peak_T, track, psi, peak_hi_T);
  thread_local Asymmetry asym;  // symmetrized models: the field's asymmetry (Bz) at the nominal nodes
  asymmetry(nullptr, ce, se, env ? env->br_scale : 1.0, coarse_ == 0 || (peak_T && !peak_hi_T), asym);
  finish(R, chain, eps_deg, peak_T, track, psi, peak_hi_T, &asym);
}

namespace {
void peak_to_peak(const std::vector<Eigen::VectorXd>& e, double* pp_deg) {
  for (std::size_t a = 0; a < e.size(); ++a) pp_deg[a] = e[a].maxCoeff() - e[a].minCoeff();
}
}  // namespace

void FastPipeline::pp_mount(const Mount& mt, const SignalChain::Applied& chain, double elevation_deg,
                            const EnvReadings* env, double* pp_deg, std::vector<double>* peak_T) const {
  std::vector<Eigen::VectorXd> e;
  if (speed_.acts()) {  // pp of the output at speed: from eps (the PpTrack knows only the static angle)
    eps_mount(mt, chain, elevation_deg, e, peak_T, env);
    return peak_to_peak(e, pp_deg);
  }
  PpTrack track;
  track.t_lo.assign(arrays_.size(), std::numeric_limits<double>::infinity());
  track.t_hi.assign(arrays_.size(), -std::numeric_limits<double>::infinity());
  eps_mount(mt, chain, elevation_deg, e, peak_T, env, &track);
  if (!track.wrapped) {
    for (std::size_t a = 0; a < arrays_.size(); ++a)
      pp_deg[a] = rad_to_deg(std::atan(track.t_hi[a])) - rad_to_deg(std::atan(track.t_lo[a]));
    return;
  }
  eps_mount(mt, chain, elevation_deg, e, peak_T, env);
  peak_to_peak(e, pp_deg);
}

void FastPipeline::pp(const Mount& m, double* pp_deg) const {
  pp_mount(m, SignalChain::Applied{}, elevation_deg_, nullptr, pp_deg);
}

void FastPipeline::pp(const ToleranceCase& c, double* pp_deg) const {
  const CaseState st = case_state(c);
  pp_mount(st.mount, st.chain, st.elevation_deg, st.env_ptr(), pp_deg);
}

void FastPipeline::pp_atan2(const ToleranceCase& c, double* pp_deg) const {
  std::vector<Eigen::VectorXd> e;
  eps(c, e);
  peak_to_peak(e, pp_deg);
}

void FastPipeline::pp_field(const ToleranceCase& c, double* pp_deg, double* fmin_mT, double* fmax_mT) const {
  const CaseState st = case_state(c);
  std::vector<double> peak_T;
  pp_mount(st.mount, st.chain, st.elevation_deg, st.env_ptr(), pp_deg, &peak_T);
  field_window(peak_T, fmin_mT, fmax_mT);
}

void FastPipeline::field_window(const std::vector<double>& peak_T, double* fmin_mT, double* fmax_mT) const {
  for (std::size_t a = 0; a < arrays_.size(); ++a) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (int slot : slot_[a]) {
      lo = std::min(lo, peak_T[static_cast<std::size_t>(slot)]);
      hi = std::max(hi, peak_T[static_cast<std::size_t>(slot)]);
    }
    fmin_mT[a] = lo * 1e3;
    fmax_mT[a] = hi * 1e3;
  }
}

void FastPipeline::eps_field_bounds(const ToleranceCase& c, std::vector<Eigen::VectorXd>& e, double* fmin_lo_mT,
                                    double* fmin_hi_mT, double* fmax_lo_mT, double* fmax_hi_mT,
                                    std::vector<UnitAngles>* psi) const {
  const CaseState st = case_state(c);
  std::vector<double> lo_T, hi_T;
  eps_mount(st.mount, st.chain, st.elevation_deg, e, &lo_T, st.env_ptr(), nullptr, psi, &hi_T);
  field_window(lo_T, fmin_lo_mT, fmax_lo_mT);
  field_window(hi_T, fmin_hi_mT, fmax_hi_mT);
}

void FastPipeline::eps_field(const ToleranceCase& c, std::vector<Eigen::VectorXd>& e, double* fmin_mT,
                             double* fmax_mT, std::vector<UnitAngles>* psi) const {
  const CaseState st = case_state(c);
  std::vector<double> peak_T;
  eps_mount(st.mount, st.chain, st.elevation_deg, e, &peak_T, st.env_ptr(), nullptr, psi);
  field_window(peak_T, fmin_mT, fmax_mT);
}

}  // namespace magenc
