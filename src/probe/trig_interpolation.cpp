#include "probe/trig_interpolation.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include <fftw3.h>

namespace magenc {

namespace {

// Every array a plan is made on or executed on starts on a 64-byte boundary: fftw_alignment_of() is 0
// for all of them (FFTW's SIMD alignment is at most 64 bytes), as its new-array execute functions need.
constexpr std::size_t kAlign_bytes = 64;

template <class T>
class AlignedArray {
 public:
  AlignedArray() = default;
  explicit AlignedArray(std::size_t n) { reserve(n); }
  AlignedArray(const AlignedArray&) = delete;
  AlignedArray& operator=(const AlignedArray&) = delete;
  ~AlignedArray() { std::free(p_); }
  // At least n elements (contents not kept when it grows).
  T* reserve(std::size_t n) {
    if (n > n_) {
      std::free(p_);
      const std::size_t bytes = (std::max<std::size_t>(n, 1) * sizeof(T) + kAlign_bytes - 1) / kAlign_bytes * kAlign_bytes;
      p_ = static_cast<T*>(std::aligned_alloc(kAlign_bytes, bytes));
      if (!p_) throw std::bad_alloc();
      n_ = n;
    }
    return p_;
  }
  T* get() const { return p_; }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
};

// This thread's arrays for the transforms (grown to the largest size used).
struct Scratch {
  AlignedArray<double> real_in, real_out;
  AlignedArray<fftw_complex> spec_in, spec_out;
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

fftw_plan checked(fftw_plan p, const std::string& what) {
  if (!p) throw std::runtime_error("FFTW could not plan " + what);
  return p;
}

}  // namespace

// The process-wide plans, made under the mutex and destroyed at exit (after main returns, on one thread).
struct TransformCache {
  std::mutex mutex;
  std::map<std::pair<int, int>, std::unique_ptr<TrigInterpolation>> interpolations;
  std::map<int, std::unique_ptr<ComplexDft>> dfts;

  static TransformCache& instance() {
    static TransformCache cache;
    return cache;
  }
  ~TransformCache() {
    for (auto& [key, t] : interpolations) {
      fftw_destroy_plan(t->forward_);
      fftw_destroy_plan(t->backward_);
    }
    for (auto& [key, d] : dfts) {
      fftw_destroy_plan(d->forward_);
      fftw_destroy_plan(d->backward_);
    }
  }
};

TrigInterpolation::TrigInterpolation(int m, int n) : m_(m), n_(n) {
  // Called with the cache's mutex held (the planner is not thread-safe).
  AlignedArray<double> x(static_cast<std::size_t>(m)), y(static_cast<std::size_t>(n));
  AlignedArray<fftw_complex> X(static_cast<std::size_t>(m / 2 + 1)), Y(static_cast<std::size_t>(n / 2 + 1));
  const std::string sizes = std::to_string(m) + " -> " + std::to_string(n);
  forward_ = checked(fftw_plan_dft_r2c_1d(m, x.get(), X.get(), FFTW_ESTIMATE), "the real DFT of " + sizes);
  backward_ = checked(fftw_plan_dft_c2r_1d(n, Y.get(), y.get(), FFTW_ESTIMATE), "the inverse real DFT of " + sizes);
}

const TrigInterpolation& TrigInterpolation::of(int m, int n) {
  thread_local const TrigInterpolation* last = nullptr;  // (no lock when the sizes repeat)
  if (last && last->m_ == m && last->n_ == n) return *last;
  if (m < 1 || n < m)
    throw std::invalid_argument("TrigInterpolation: M = " + std::to_string(m) + ", N = " + std::to_string(n) +
                                ": allowed 1 <= M <= N");
  TransformCache& cache = TransformCache::instance();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  auto& slot = cache.interpolations[{m, n}];
  if (!slot) slot.reset(new TrigInterpolation(m, n));
  last = slot.get();
  return *last;
}

void TrigInterpolation::operator()(const double* samples, double* values) const {
  const int M = m_, N = n_;
  if (M == N) {  // (the interpolant at its own nodes; the c2r below would halve an M/2 = N/2 term)
    if (values != samples) std::copy(samples, samples + M, values);
    return;
  }
  Scratch& s = scratch();
  double* x = s.real_in.reserve(static_cast<std::size_t>(M));
  double* y = s.real_out.reserve(static_cast<std::size_t>(N));
  fftw_complex* X = s.spec_in.reserve(static_cast<std::size_t>(M / 2 + 1));
  fftw_complex* Y = s.spec_out.reserve(static_cast<std::size_t>(N / 2 + 1));
  std::copy(samples, samples + M, x);
  fftw_execute_dft_r2c(forward_, x, X);
  // The half spectrum of length N (c2r counts every 0 < k < N/2 twice, for k and -k), scaled by 1/M;
  // the M/2 term (M even) at half weight. c2r destroys its input: Y is scratch.
  const double scale = 1.0 / M;
  for (int k = 0; k <= N / 2; ++k) Y[k][0] = Y[k][1] = 0.0;
  for (int k = 0; 2 * k < M; ++k) {
    Y[k][0] = scale * X[k][0];
    Y[k][1] = scale * X[k][1];
  }
  if (M % 2 == 0) Y[M / 2][0] = 0.5 * scale * X[M / 2][0];
  fftw_execute_dft_c2r(backward_, Y, y);
  std::copy(y, y + N, values);
}

ComplexDft::ComplexDft(int n) : n_(n) {
  // Called with the cache's mutex held (the planner is not thread-safe).
  AlignedArray<fftw_complex> a(static_cast<std::size_t>(n)), b(static_cast<std::size_t>(n));
  const std::string size = std::to_string(n);
  forward_ = checked(fftw_plan_dft_1d(n, a.get(), b.get(), FFTW_FORWARD, FFTW_ESTIMATE), "the DFT of length " + size);
  backward_ = checked(fftw_plan_dft_1d(n, a.get(), b.get(), FFTW_BACKWARD, FFTW_ESTIMATE),
                      "the inverse DFT of length " + size);
}

const ComplexDft& ComplexDft::of(int n) {
  thread_local const ComplexDft* last = nullptr;  // (no lock when the length repeats)
  if (last && last->n_ == n) return *last;
  if (n < 1) throw std::invalid_argument("ComplexDft: n = " + std::to_string(n) + ": allowed n >= 1");
  TransformCache& cache = TransformCache::instance();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  auto& slot = cache.dfts[n];
  if (!slot) slot.reset(new ComplexDft(n));
  last = slot.get();
  return *last;
}

void ComplexDft::run(fftw_plan_s* plan, const std::complex<double>* in, std::complex<double>* out) const {
  // std::complex<double> and fftw_complex share their layout (FFTW's manual, "Complex numbers").
  Scratch& s = scratch();
  const auto n = static_cast<std::size_t>(n_);
  fftw_complex* a = s.spec_in.reserve(n);
  fftw_complex* b = s.spec_out.reserve(n);
  std::copy(in, in + n, reinterpret_cast<std::complex<double>*>(a));
  fftw_execute_dft(plan, a, b);
  const auto* r = reinterpret_cast<const std::complex<double>*>(b);
  std::copy(r, r + n, out);
}

void ComplexDft::forward(const std::complex<double>* in, std::complex<double>* out) const { run(forward_, in, out); }

void ComplexDft::backward(const std::complex<double>* in, std::complex<double>* out) const { run(backward_, in, out); }

}  // namespace magenc
