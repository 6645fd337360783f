// MultipolePipeline: the Monte Carlo engine's incremental reading of a multipole track (docs/physics.md
// "Multipole rings and nonius"; docs/multipole.md "The Monte Carlo engine"): Bz read heads with
// electrical spacing over one or more ideal rings (MultipoleRingModel; a nonius track's cross-talk is a
// second ring), the error eps = wrap(phi_e - p theta) / p in mechanical degrees at N uniform theta.
//
// Why it is cheap. A probe at fixed-frame position P (the nominal point plus the sensor offset s, complex
// numbers in the plane) sits in the magnet frame at e^{-i theta} (P - e^{i theta} d) (d: the magnet's
// eccentricity), i.e. at radius rho(theta) = |P - e^{i theta} d| and azimuth arg P + chi(theta) - theta
// with chi = arg(1 - e^{i theta} d / P). With Bz = sum_n A_n(rho, z) cos(n p phi) (MultipoleRingModel) its
// reading is
//   R(theta) = Re sum_n G_n(theta) e^{-i n p theta},  G_n = A_n(rho(theta), z_s + dz) e^{i n p (arg P + chi(theta))},
// and each envelope G_n depends on theta only through e^{i theta} d: a trigonometric polynomial of low
// degree J (J = 0 without eccentricity, so every reading is then a trigonometric polynomial in p theta).
// The complex channel C + i S = sum_k (w_cos,k + i w_sin,k) R_k of each array is therefore, per harmonic, two
// envelopes U_n, V_n (the sums over the probes of the weighted G_n and conj(G_n)) shifted to the
// frequencies -+ n p. They are evaluated at M = 2J + 1 coarse angles, transformed (length M), placed at their
// frequencies in a spectrum of length N (folded modulo N: exactly the values at the N nodes) and turned
// into C + i S at every node by one inverse FFT; then eps in bulk. J follows from |d|: harmonic n's envelope
// is mainly the phase modulation e^{i n p chi}, chi ~ x sin(theta + .), x = |d| / min |P|, whose coefficients
// are Bessel values |J_j(n p x)| <= (n p x / 2)^j / j!; with b = 0.6 n p x (20 % above, for the radius's
// modulation of A_n and chi's higher orders) J is the smallest order beyond which w_n b^j / j! e^b < 1e-8 for
// every harmonic (w_n its amplitude / A_1), checked against larger J in the tests; harmonics below 1e-9 of
// A_1 at the sample's height are skipped. Together they move eps by ~1e-7 deg at most on the tests' rings,
// of the order of the model's own misfit (tests/analysis/test_multipole_pipeline.cpp).
// The cost per sample: M x probes x harmonics small complex products, not probes x N field models.
#pragma once
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "probe/multipole_ring_model.hpp"
#include "probe/mounting.hpp"
#include "probe/probe_array.hpp"
#include "probe/signal_chain.hpp"

namespace magenc {

class MultipolePipeline {
 public:
  // rings: the master's model first (their fields add at every probe); all on the same read circle, plane
  // and reach (InputError otherwise). arrays: the read heads with their probe angles in MECHANICAL degrees
  // (electrical spacing: the array's angles / p, as sensor_setup_from_config sets them). pole_pairs: p of
  // the incremental reading. steps: N theta samples per turn (>= 16; any N: the probes need not fall on them).
  MultipolePipeline(std::vector<const MultipoleRingModel*> rings, const std::vector<ProbeArray>& arrays, int pole_pairs,
                    int steps);
  int steps() const { return n_; }
  std::size_t arrays() const { return arrays_.size(); }
  // eps_deg[a] (N samples, theta_m = 360 m / N) of every array for mount m: the incremental reading's error
  // in mechanical degrees, (-180/p, 180/p]. The signal chain acts on the channels before the angle.
  // phi_e_deg (optional): each array's electrical angle atan2(S, C) in degrees (the nonius decoding's input).
  // InputError for a tilted mount (the engine reads the five offsets) and a probe off the model's reach.
  void eps(const Mount& m, std::vector<Eigen::VectorXd>& eps_deg, const SignalChain::Applied& chain = {},
           std::vector<Eigen::VectorXd>* phi_e_deg = nullptr) const;
  // The envelopes' half-degree J the mount takes (M = 2J + 1 coarse angles); force_envelope_order(j >= 0)
  // sets it, -1 returns to the bound (tests).
  // (0 without eccentricity; M is 2J + 1 rounded up to a length of factors 2, 3, 5, 7: coarse_angles.)
  int envelope_order(const Mount& m) const;
  void force_envelope_order(int j) { force_j_ = j; }
  static int coarse_angles(int J);

 private:
  using cd = std::complex<double>;
  struct Probe {
    double x, y;     // nominal fixed-frame position (mm)
    cd w;            // w_cos + i w_sin
  };
  // The amplitudes at height z_mm (MultipoleRingModel::amplitudes_at_z) without the harmonics below
  // kHarmonicTol of A_1 there.
  void harmonics_at(double z_mm, std::vector<Eigen::MatrixXd>& amp) const;
  int envelope_order(const Mount& m, const std::vector<Eigen::MatrixXd>& amp) const;
  // Per-thread scratch of a sample.
  struct Work {
    std::size_t cols = 0;                       // (ring, harmonic) columns
    std::vector<double> ct, om, U, V, geo, zeta;
    int m_angles = 0;                           // the M of zeta (cos, sin of the coarse angles)
    int mp = 0;                                 // M padded to a multiple of 4 (the stride of U, V)
    std::vector<cd> in, out;
  };
  // The envelopes U, V of array a at the M coarse angles (w.U, w.V: per column, the real parts at the M
  // angles, then the imaginary ones).
  void envelopes(const Mount& m, std::size_t a, int M, const std::vector<Eigen::MatrixXd>& amp, Work& w) const;
  // C + i S at every node from the envelopes: spectral assembly, one inverse FFT.
  void assemble(int J, const std::vector<Eigen::MatrixXd>& amp, Work& w, std::vector<cd>& z) const;

  std::vector<const MultipoleRingModel*> rings_;
  std::vector<ProbeArray> arrays_;
  std::vector<std::vector<Probe>> probes_;
  int p_ = 1, n_ = 360, force_j_ = -1;
  std::vector<double> cos_pt_, sin_pt_;  // cos, sin of p theta_m
};

}  // namespace magenc
