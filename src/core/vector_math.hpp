// Elementwise maths over arrays in bulk: the Monte Carlo engine's angle evaluations and the calibration
// fit's trigonometric sums, vectorized (SLEEF, https://sleef.org, Debian libsleef-dev, for atan2; the sums
// are plain loops over blocks of nodes that the compiler vectorizes, with an AVX2 clone chosen at run
// time on x86-64 with GCC).
#pragma once
#include <cstddef>

namespace magenc {

// out[i] = atan2(y[i], x[i]) in radians, [-pi, pi], for i < n. SLEEF's 3.5-ULP atan2 (its runtime
// dispatch picks the CPU's vector extension): within 4 ULP of std::atan2 (tests/core/test_vector_math.cpp).
// out may alias x or y.
void atan2_rad(const double* y, const double* x, double* out, std::size_t n);

// The angles of channel pairs less theta, and their unit vectors: for i < n, with x = C ct + S st and
// y = S ct - C st ((C, S) turned back by theta; ct, st = cos, sin theta),
//   eps_rad[i] = atan2(y, x)  (atan(y / x) where x > 0, in blocks of 4 on AVX2: within 5 ULP of atan2),
// and when cpsi, spsi are not null, (cpsi, spsi)[i] = (C, S) / |(C, S)|, (1, 0) where both are 0.
void channel_angles(const double* C, const double* S, const double* ct, const double* st, std::size_t n,
                    double* eps_rad, double* cpsi, double* spsi);

// Power sums of the unit complex numbers z_i = c[i] + i s[i] (|z_i| = 1; i < n), z^m by complex
// multiplication (angle addition, so the round-off grows like m): for m = 0..M
//   C[m] = sum_i Re z_i^m,  S[m] = sum_i Im z_i^m,
// and for m = 0..K (K <= M) the weighted sums WC[m] = sum_i w[i] Re z_i^m, WS[m] = sum_i w[i] Im z_i^m.
// Arrays C, S have M + 1 entries, WC, WS K + 1. The order of the additions is fixed (blocks of 8 nodes), so
// the sums do not depend on the thread count.
void unit_power_sums(const double* c, const double* s, const double* w, std::size_t n, int M, int K, double* C,
                     double* S, double* WC, double* WS);

// out[i] = h[0] + sum_{m=1..K} (h[2m - 1] Re z_i^m + h[2m] Im z_i^m), z_i = c[i] + i s[i] as above: a
// trigonometric series of degree K at the angles of the z_i.
void unit_series(const double* c, const double* s, std::size_t n, const double* h, int K, double* out);

}  // namespace magenc
