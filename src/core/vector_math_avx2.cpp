// The AVX2 loops of core/vector_math.cpp (called only on CPUs with AVX2). This file alone is compiled
// with -mavx2 and includes nothing shared with other files but SLEEF's C header and the intrinsics, so no
// code compiled for AVX2 can end up called on a CPU without it.
#include <cstddef>

#include <immintrin.h>
#include <sleef.h>

namespace magenc {
namespace detail {

// out[i] = atan2(y[i], x[i]) for i < n - n % 4; returns that count.
std::size_t atan2_rad_avx2(const double* y, const double* x, double* out, std::size_t n) {
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4)
    _mm256_storeu_pd(out + i, Sleef_atan2d4_u35avx2(_mm256_loadu_pd(y + i), _mm256_loadu_pd(x + i)));
  return i;
}

// channel_angles for i < n - n % 4; returns that count. Where x > 0 in all four lanes, atan(y / x).
std::size_t channel_angles_avx2(const double* C, const double* S, const double* ct, const double* st, std::size_t n,
                                double* eps_rad, double* cpsi, double* spsi) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d c = _mm256_loadu_pd(C + i), s = _mm256_loadu_pd(S + i);
    const __m256d tc = _mm256_loadu_pd(ct + i), ts = _mm256_loadu_pd(st + i);
    const __m256d x = _mm256_add_pd(_mm256_mul_pd(c, tc), _mm256_mul_pd(s, ts));
    const __m256d y = _mm256_sub_pd(_mm256_mul_pd(s, tc), _mm256_mul_pd(c, ts));
    const bool right = _mm256_movemask_pd(_mm256_cmp_pd(x, zero, _CMP_GT_OQ)) == 0xF;
    _mm256_storeu_pd(eps_rad + i, right ? Sleef_atand4_u35avx2(_mm256_div_pd(y, x)) : Sleef_atan2d4_u35avx2(y, x));
    if (!cpsi) continue;
    const __m256d r = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(c, c), _mm256_mul_pd(s, s)));
    const __m256d is0 = _mm256_cmp_pd(r, zero, _CMP_EQ_OQ);
    const __m256d inv = _mm256_div_pd(one, _mm256_blendv_pd(r, one, is0));  // (1 where both channels are 0)
    _mm256_storeu_pd(cpsi + i, _mm256_blendv_pd(_mm256_mul_pd(c, inv), one, is0));
    _mm256_storeu_pd(spsi + i, _mm256_blendv_pd(_mm256_mul_pd(s, inv), zero, is0));
  }
  return i;
}

}  // namespace detail
}  // namespace magenc
