// Fixed-size discrete Fourier transforms on FFTW plans made once per size, and the exact trigonometric
// interpolation built on them (the Monte Carlo engine's readings: analysis/fast_pipeline.hpp).
//
// Plans: one process-wide cache keyed by the sizes, filled on first use under a mutex (FFTW's planner
// is not thread-safe), with FFTW_ESTIMATE and no wisdom, so that the plan, and with it every number, is
// the same in every run and on every thread. The transforms run with FFTW's new-array execute functions
// (thread-safe) on per-thread scratch arrays aligned like the arrays the plans were made on (the
// caller's arrays are copied in and out). The plans are destroyed at exit; FFTW's own planner tables
// stay, reachable from its globals (fftw_cleanup is not called: it would void plans made elsewhere).
#pragma once
#include <complex>

struct fftw_plan_s;  // fftw3.h's plan (fftw_plan is fftw_plan_s*); fftw3.h stays inside the .cpp

namespace magenc {

// Trigonometric interpolation from M equispaced samples x_j = f(2 pi j / M) to the N equispaced values
// y_m = p(2 pi m / N), where p is the trigonometric interpolant of degree M/2: the samples' discrete
// Fourier coefficients X_k = sum_j x_j e^{-2 pi i j k / M} (a real FFT of length M), zero-padded to N,
// and a real inverse FFT of length N, scaled by 1/M:
//   p(theta) = (1/M) [X_0 + 2 sum_{0 < k < M/2} Re(X_k e^{i k theta}) + Re(X_{M/2}) cos(M/2 theta)],
// the last term (M even only) at half weight, split between +-M/2. Exact (up to round-off) for every
// trigonometric polynomial of degree < M/2, and for a cos(M/2 theta) term (a sin(M/2 theta) term
// vanishes on the nodes). Needs 1 <= M <= N.
class TrigInterpolation {
 public:
  // The shared instance for these sizes (plans made on first use; thread-safe). std::invalid_argument
  // when M < 1 or N < M.
  static const TrigInterpolation& of(int m, int n);
  int m() const { return m_; }
  int n() const { return n_; }
  // values[0..N-1] from samples[0..M-1] (samples is not modified; values may be samples itself).
  void operator()(const double* samples, double* values) const;

 private:
  TrigInterpolation(int m, int n);
  int m_ = 0, n_ = 0;
  fftw_plan_s* forward_ = nullptr;   // real M -> half spectrum (M/2 + 1)
  fftw_plan_s* backward_ = nullptr;  // half spectrum (N/2 + 1) -> real N
  friend struct TransformCache;
};

// The unscaled complex DFT of length n in both directions:
//   forward  X_k = sum_j x_j e^{-2 pi i j k / n},   backward  x_j = sum_k X_k e^{+2 pi i j k / n}
// (backward(forward(x)) = n x).
class ComplexDft {
 public:
  // The shared instance of this length (plans made on first use; thread-safe). std::invalid_argument when n < 1.
  static const ComplexDft& of(int n);
  int n() const { return n_; }
  // out[0..n-1] from in[0..n-1] (in is not modified; in and out may be the same array).
  void forward(const std::complex<double>* in, std::complex<double>* out) const;
  void backward(const std::complex<double>* in, std::complex<double>* out) const;

 private:
  explicit ComplexDft(int n);
  void run(fftw_plan_s* plan, const std::complex<double>* in, std::complex<double>* out) const;
  int n_ = 0;
  fftw_plan_s* forward_ = nullptr;
  fftw_plan_s* backward_ = nullptr;
  friend struct TransformCache;
};

}  // namespace magenc
