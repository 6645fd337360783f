#include "core/vector_math.hpp"

#include <cmath>
#include <vector>

#if defined(__SSE2__)
#include <sleef.h>
#endif

// GCC on x86-64 builds the loops below twice, for AVX2 and for the baseline (the same operations, no FMA:
// the same sums), and picks one at load time (function multiversioning); elsewhere one build.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define MAGENC_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MAGENC_CLONES
#endif

namespace magenc {

#if defined(MAGENC_ATAN2_AVX2)
namespace detail {
std::size_t atan2_rad_avx2(const double* y, const double* x, double* out, std::size_t n);  // vector_math_avx2.cpp
std::size_t channel_angles_avx2(const double* C, const double* S, const double* ct, const double* st, std::size_t n,
                                double* eps_rad, double* cpsi, double* spsi);
}  // namespace detail
#endif

void atan2_rad(const double* y, const double* x, double* out, std::size_t n) {
  std::size_t i = 0;
#if defined(MAGENC_ATAN2_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) i = detail::atan2_rad_avx2(y, x, out, n);
#endif
#if defined(__SSE2__)
  for (; i + 2 <= n; i += 2)
    _mm_storeu_pd(out + i, Sleef_atan2d2_u35(_mm_loadu_pd(y + i), _mm_loadu_pd(x + i)));
#endif
  for (; i < n; ++i) out[i] = std::atan2(y[i], x[i]);
}

void channel_angles(const double* C, const double* S, const double* ct, const double* st, std::size_t n,
                    double* eps_rad, double* cpsi, double* spsi) {
  std::size_t i = 0;
#if defined(MAGENC_ATAN2_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) i = detail::channel_angles_avx2(C, S, ct, st, n, eps_rad, cpsi, spsi);
#endif
  if (i == n) return;
  thread_local std::vector<double> x, y;
  x.resize(n - i);
  y.resize(n - i);
  for (std::size_t k = i; k < n; ++k) {
    x[k - i] = C[k] * ct[k] + S[k] * st[k];
    y[k - i] = S[k] * ct[k] - C[k] * st[k];
    if (!cpsi) continue;
    const double r = std::sqrt(C[k] * C[k] + S[k] * S[k]);
    const double inv = 1.0 / (r == 0.0 ? 1.0 : r);
    cpsi[k] = r == 0.0 ? 1.0 : C[k] * inv;
    spsi[k] = r == 0.0 ? 0.0 : S[k] * inv;
  }
  atan2_rad(y.data(), x.data(), eps_rad + i, n - i);
}

namespace {
// Four nodes at once (GCC/Clang vector extension: one AVX2 register, two SSE2 registers).
typedef double v4d __attribute__((vector_size(32)));
// The same in memory at double alignment (the accumulators live in a std::vector<double>).
typedef double v4d_mem __attribute__((vector_size(32), aligned(8), may_alias));

// The block of nodes i..i+3; a missing node (past n) is z = 0, w = 0, which adds nothing to any sum with m >= 1.
// (By reference: a vector argument or result by value would depend on the clone's ABI.)
inline void load4(v4d& v, const double* p, std::size_t i, std::size_t n) {
  v = v4d{0.0, 0.0, 0.0, 0.0};
  for (int l = 0; l < 4; ++l)
    if (i + std::size_t(l) < n) v[l] = p[i + std::size_t(l)];
}
inline double lane_sum(const v4d& v) { return (v[0] + v[1]) + (v[2] + v[3]); }
}  // namespace

// Both functions take 8 nodes per step as two independent blocks of 4: the recurrence z^m = z^{m-1} z is a
// chain of dependent multiplications, and two chains keep the vector units busy.
MAGENC_CLONES
void unit_power_sums(const double* c, const double* s, const double* w, std::size_t n, int M, int K, double* C,
                     double* S, double* WC, double* WS) {
  // Per-lane accumulators of m = 1..M, summed across the lanes at the end (a fixed order).
  thread_local std::vector<double> acc;
  const std::size_t rows = std::size_t(M > 0 ? M : 0);
  acc.assign(16 * rows, 0.0);
  v4d_mem* const rows0 = reinterpret_cast<v4d_mem*>(acc.data());
  v4d w0 = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < n; i += 8) {
    v4d ac, as, bc, bs, aw = {0.0, 0.0, 0.0, 0.0}, bw = aw;
    load4(ac, c, i, n);
    load4(as, s, i, n);
    load4(bc, c, i + 4, n);
    load4(bs, s, i + 4, n);
    if (w) {
      load4(aw, w, i, n);
      load4(bw, w, i + 4, n);
    }
    w0 += aw + bw;
    v4d pa = ac, qa = as, pb = bc, qb = bs;  // Re and Im of z^m, blocks a and b
    v4d_mem* row = rows0;
    for (int m = 1; m <= M; ++m, row += 4) {
      if (m > 1) {
        const v4d na = pa * ac - qa * as, nb = pb * bc - qb * bs;
        qa = qa * ac + pa * as;
        qb = qb * bc + pb * bs;
        pa = na;
        pb = nb;
      }
      row[0] += pa + pb;
      row[1] += qa + qb;
      if (m <= K) {
        row[2] += aw * pa + bw * pb;
        row[3] += aw * qa + bw * qb;
      }
    }
  }
  C[0] = static_cast<double>(n);
  S[0] = 0.0;
  if (K >= 0) {
    WC[0] = lane_sum(w0);
    WS[0] = 0.0;
  }
  for (int m = 1; m <= M; ++m) {
    const v4d r[4] = {rows0[4 * (m - 1)], rows0[4 * (m - 1) + 1], rows0[4 * (m - 1) + 2], rows0[4 * (m - 1) + 3]};
    C[m] = lane_sum(r[0]);
    S[m] = lane_sum(r[1]);
    if (m <= K) {
      WC[m] = lane_sum(r[2]);
      WS[m] = lane_sum(r[3]);
    }
  }
}

MAGENC_CLONES
void unit_series(const double* c, const double* s, std::size_t n, const double* h, int K, double* out) {
  for (std::size_t i = 0; i < n; i += 8) {
    v4d ac, as, bc, bs;
    load4(ac, c, i, n);
    load4(as, s, i, n);
    load4(bc, c, i + 4, n);
    load4(bs, s, i + 4, n);
    v4d pa = {1.0, 1.0, 1.0, 1.0}, qa = {0.0, 0.0, 0.0, 0.0}, pb = pa, qb = qa, va = pa * h[0], vb = va;
    for (int m = 1; m <= K; ++m) {
      const v4d na = pa * ac - qa * as, nb = pb * bc - qb * bs;
      qa = qa * ac + pa * as;
      qb = qb * bc + pb * bs;
      pa = na;
      pb = nb;
      va += h[2 * m - 1] * pa + h[2 * m] * qa;
      vb += h[2 * m - 1] * pb + h[2 * m] * qb;
    }
    for (int l = 0; l < 4 && i + std::size_t(l) < n; ++l) out[i + std::size_t(l)] = va[l];
    for (int l = 0; l < 4 && i + 4 + std::size_t(l) < n; ++l) out[i + 4 + std::size_t(l)] = vb[l];
  }
}

}  // namespace magenc
