// atan2_rad's AVX2 loop (core/vector_math.cpp calls it on CPUs with AVX2). This file alone is compiled
// with -mavx2 and includes nothing shared with other files but SLEEF's C header, so no code compiled
// for AVX2 can end up called on a CPU without it.
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

}  // namespace detail
}  // namespace magenc
