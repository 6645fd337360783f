// FastPipeline: the angle error of several probe arrays at once, read from a CircleFieldModel
// (the surrogate of the radius scan, analysis/radius_scan.hpp: why and how).
#pragma once
#include <array>
#include <complex>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "core/defaults.hpp"
#include "analysis/circle_field_model.hpp"
#include "analysis/tolerance.hpp"
#include "probe/mounting.hpp"
#include "probe/probe_array.hpp"
#include "probe/signal_chain.hpp"
#include "probe/speed.hpp"

namespace magenc {

// The sensor's angle psi = theta + eps at every node as a unit vector: the channels after the signal
// chain, normalized (cos psi = C / |(C, S)|, sin psi = S / |(C, S)|; (1, 0) where both are 0).
struct UnitAngles {
  Eigen::VectorXd cos_psi, sin_psi;
};

// The fast pipeline on a CircleFieldModel for several arrays at once.
class FastPipeline {
 public:
  // Throws InputError when a probe angle is not a multiple of 360/N degrees
  // (then choose radius.fast_steps as a multiple of the array's N).
  // magnet_height_mm: L, the pivot height of a magnet tilt (tilted mounts only).
  // Magnetization elevation: without `axial`, `model` is the field itself and
  // every case's elevation deviation must be 0 (InputError otherwise). With
  // `axial`, `model` is the field of the diametric magnetization alone
  // (elevation 0) and `axial` that of the axial magnetization alone (|M| = M0
  // along z; same nodes, stencil and order): the field of a case is
  // cos(al) model + sin(al) axial, al = elevation_deg + the case's deviation
  // (exact: B is linear in M).
  FastPipeline(const CircleFieldModel& model, const std::vector<ProbeArray>& arrays, double magnet_height_mm = defaults::kMagnetHeight_mm,
               const CircleFieldModel* axial = nullptr, double elevation_deg = 0.0);
  // Readings interpolated in theta: with symmetry-built models (model.construction() == symmetry or
  // symmetrized, and the axial model's too) every probe reading is a trigonometric polynomial of degree <= 11 in theta
  // (degree 4 in the displacement, whose coordinates are degree 1 in theta; the node coefficients
  // degree <= 6 in the node angle; the normal degree 1; the environment adds constants). The readings
  // are then evaluated at M = coarse_steps() nodes (the smallest divisor of N that is >= 24, so every
  // degree <= 11 is resolved: 24 of 360) and interpolated exactly (up to round-off) to the N nodes; otherwise
  // (coarse_steps() == 0) every node is evaluated. The model's construction chooses, nothing else.
  // symmetrized models: the interpolated readings of their symmetric part plus, at every node, the node
  // residual at each probe's nominal node (n . residual for tilted mounts; CircleFieldModel::symmetrized).
  int coarse_steps() const { return coarse_; }
  // Evaluate every node even for symmetry-built models (the reference the interpolation is tested against).
  void evaluate_every_node() { coarse_ = 0; }
  // pp over every node even where pp_bounded applies (its reference in the tests).
  void evaluate_pp_on_every_node() { medium_ = 0; }
  // How many pp calls on this thread took pp_bounded (tests: the bounded route is exercised).
  static long bounded_pp_count();
  std::size_t arrays() const { return arrays_.size(); }
  int steps() const { return model_.nodes(); }
  // A turning encoder (probe/speed.hpp): every eps, psi and pp of this pipeline is then that of the steady
  // state at speed.rpm, the chain applied to each array's channels over the N nodes of the turn after the
  // signal chain, as angle_error() does (psi: theta + eps of the output as unit vectors). The field window
  // is the static one (the readings do not depend on the speed). Static by default. validate() first.
  void set_speed(const SpeedChain& s) {
    s.validate();
    speed_ = s;
  }
  const SpeedChain& speed() const { return speed_; }
  // eps_deg[a] (N samples, theta_m = 360 m/N) of every array a for mount m
  // (ideal signal chain, the nominal elevation).
  // A tilted mount (sensor or magnet tilt) needs a full_vector model
  // (InputError otherwise): each probe's position and normal then come from
  // MountKinematics and it reads n.B of the model at its own displacement.
  void eps(const Mount& m, std::vector<Eigen::VectorXd>& eps_deg) const;
  // The same for a whole tolerance case: the case's signal chain is applied to
  // the channels before atan2 (SignalChain::Applied, as in angle_error.hpp), and
  // its elevation deviation needs the axial model. An ideal chain and a zero
  // deviation give exactly eps(c.mount). The case's environment (a temperature, a homogeneous stray
  // field: ToleranceBox) scales the readings by Br(T)/Br, adds n.B_stray to each probe's reading and
  // drifts the offsets and the air gap, as angle_error() does; a neutral one changes nothing.
  // psi (optional): also the sensor's angle of every array as unit vectors (UnitAngles).
  void eps(const ToleranceCase& c, std::vector<Eigen::VectorXd>& eps_deg, std::vector<UnitAngles>* psi = nullptr) const;
  // Peak-to-peak of eps of every array (pp_deg has arrays() values).
  void pp(const Mount& m, double* pp_deg) const;
  void pp(const ToleranceCase& c, double* pp_deg) const;
  // pp as the max - min of eps (one atan2 per theta and array): the reference of pp's faster route.
  void pp_atan2(const ToleranceCase& c, double* pp_deg) const;
  // pp and the field-window magnitude of every array (docs/physics.md "Sensor principles", bz): the
  // peak |reading| over the turn of each of its probes, min (fmin_mT) and max (fmax_mT) over them.
  void pp_field(const ToleranceCase& c, double* pp_deg, double* fmin_mT, double* fmax_mT) const;
  // eps(c) and the field window of pp_field in one pass (the same numbers as the two calls).
  void eps_field(const ToleranceCase& c, std::vector<Eigen::VectorXd>& eps_deg, double* fmin_mT, double* fmax_mT,
                 std::vector<UnitAngles>* psi = nullptr) const;
  // eps(c) (and psi) with bounds on eps_field's field window instead of its value, cheaper with
  // symmetry-built models: every array's fmin_mT lies in [fmin_lo_mT, fmin_hi_mT] and fmax_mT in
  // [fmax_lo_mT, fmax_hi_mT]. Each probe's peak |reading| is at least the largest of its M coarse
  // readings and at most that plus D2 h^2 / 8 (D2 = sum k^2 |c_k| of its interpolant's coefficients
  // bounds |b''|, h = 360/M deg: the most |b| can exceed its larger value at the ends of an interval
  // between two coarse nodes), with relative margins of 1e-12 for the round-off of eps_field's interpolated
  // readings, so that eps_field's values lie strictly inside. Where every node is evaluated the bounds are the values.
  void eps_field_bounds(const ToleranceCase& c, std::vector<Eigen::VectorXd>& eps_deg, double* fmin_lo_mT,
                        double* fmin_hi_mT, double* fmax_lo_mT, double* fmax_hi_mT,
                        std::vector<UnitAngles>* psi = nullptr) const;

 private:
  const CircleFieldModel& model_;
  std::vector<ProbeArray> arrays_;
  std::vector<int> angle_index_;                // distinct probe angles as node indices
  std::vector<std::vector<int>> slot_;          // slot_[a][k]: index into angle_index_
  std::vector<double> cos_theta_, sin_theta_;   // theta grid
  double magnet_height_mm_ = defaults::kMagnetHeight_mm;  // L (magnet-tilt pivot)
  const CircleFieldModel* axial_ = nullptr;     // axial-magnetization model (elevation in the box)
  double elevation_deg_ = 0;                    // nominal elevation (with axial_)
  int coarse_ = 0;                              // M: readings at M nodes, interpolated (0: every node)
  bool residual_ = false;                       // symmetrized models: their node residuals are added
  // The node residuals of symmetrized models in the channels: per model (field, axial) and component
  // (Bz, Bx, By), N x 2 arrays(): sum over the distinct probes of channel weight x the residual at the
  // probe's nominal node at theta_m. asym_channel_max_: per model and array, a bound on the modulus of
  // n . (C, S part) for any unit n; asym_probe_max_T_: per distinct probe, a bound on |n . residual|.
  std::array<std::array<Eigen::MatrixXd, 3>, 2> asym_tables_;
  std::array<std::vector<double>, 2> asym_channel_max_;
  std::vector<double> asym_probe_max_T_;
  void asymmetry_tables();
  // One case's asymmetry (symmetrized models): K, the tilted mount's kinematics (nullptr: untilted, n =
  // z); w, the weights of the field and axial models' residuals (the elevation's cos, sin times the
  // environment's Br scale); probes (only when asked): every distinct probe's part at every node;
  // probe_max_T, channel_max: bounds on a probe's and an array's (C, S) part.
  struct Asymmetry {
    const MountKinematics* K = nullptr;
    double w[2] = {1.0, 0.0};
    Eigen::MatrixXd probes;
    std::vector<double> probe_max_T, channel_max;
  };
  void asymmetry(const MountKinematics* K, double ce, double se, double scale, bool probes, Asymmetry& out) const;
  // The probes' normal at theta_m (magnet frame) and the asymmetry's part of array a's (C, S) there.
  Eigen::Vector3d asym_normal(const Asymmetry& as, int m) const;
  std::complex<double> asym_channel(const Asymmetry& as, const Eigen::Vector3d& n, int m, std::size_t a) const;
  int medium_ = 0;                              // K: pp_bounded's grid (a divisor of N, >= 3 M)
  SpeedChain speed_;                            // the turning encoder (static by default)
  Eigen::MatrixXd channel_weights_;             // distinct probes x 2 arrays: C, S of each array
  Eigen::MatrixXd coef_map_;                    // coarse samples -> the interpolant's real coefficients
  // The environment's part of each distinct probe's reading: B' = br_scale B + stray_T[i].
  struct EnvReadings {
    double br_scale = 1;
    std::vector<double> stray_T;
  };
  // The case's environment at its mount (nullopt-like: empty when neutral).
  bool env_readings(const ToleranceCase& c, const Mount& mt, EnvReadings& out) const;
  // A tolerance case at its temperature: the mount, the applied chain, the elevation and the environment.
  struct CaseState {
    Mount mount;
    SignalChain::Applied chain;
    double elevation_deg = 0;
    EnvReadings env;
    bool has_env = false;
    const EnvReadings* env_ptr() const { return has_env ? &env : nullptr; }
  };
  CaseState case_state(const ToleranceCase& c) const;
  // peak_T (optional): per distinct probe angle, the largest |reading| over the turn (T).
  // env (optional): the environment's part of the readings (probe/environment.hpp).
  // Peak-to-peak without an atan2 per theta: while C cos th + S sin th > 0 (|eps| < 90 deg) eps is
  // atan(t), t = (S cos th - C sin th) / (C cos th + S sin th), monotone in t, so pp = atan(t_max) -
  // atan(t_min); `wrapped` when the denominator is <= 0 anywhere (then the caller takes atan2).
  struct PpTrack {
    std::vector<double> t_lo, t_hi;
    bool wrapped = false;
  };
  // track (optional): pp only; eps_deg is then left unset. psi (optional): UnitAngles too. peak_hi_T
  // (with peak_T): bounds on the peaks instead of their values (eps_field_bounds), peak_T the lower ones.
  void eps_mount(const Mount& m, const SignalChain::Applied& chain, double elevation_deg,
                 std::vector<Eigen::VectorXd>& eps_deg, std::vector<double>* peak_T = nullptr,
                 const EnvReadings* env = nullptr, PpTrack* track = nullptr,
                 std::vector<UnitAngles>* psi = nullptr, std::vector<double>* peak_hi_T = nullptr) const;
  void eps_tilted(const Mount& m, const SignalChain::Applied& chain, double elevation_deg,
                  std::vector<Eigen::VectorXd>& eps_deg, std::vector<double>* peak_T = nullptr,
                  const EnvReadings* env = nullptr, PpTrack* track = nullptr,
                  std::vector<UnitAngles>* psi = nullptr, std::vector<double>* peak_hi_T = nullptr) const;
  // From the readings R (rows: every node, or the M coarse nodes, then interpolated; columns: the
  // distinct probes): peak_T, and eps or the PpTrack of every array. asym (symmetrized models): the
  // field's asymmetry at the nominal nodes, added to the channels (or readings) at every node.
  void finish(const Eigen::MatrixXd& R, const SignalChain::Applied& chain, std::vector<Eigen::VectorXd>& eps_deg,
              std::vector<double>* peak_T, PpTrack* track, std::vector<UnitAngles>* psi,
              std::vector<double>* peak_hi_T = nullptr, const Asymmetry* asym = nullptr) const;
  // Bounds on every distinct probe's peak |reading| over the N nodes from its M coarse readings R (columns):
  // lo = the largest coarse |reading|, hi = lo + D2 h^2 / 8, with 1e-12 relative margins (eps_field_bounds).
  void peak_bounds(const Eigen::MatrixXd& R, std::vector<double>& lo_T, std::vector<double>& hi_T) const;
  // Without peak_T on the coarse nodes: the channels C, S (linear in the readings: channel_weights_) are
  // formed at the M nodes and only they are interpolated (2 columns per array instead of every probe).
  // full (N x columns) from the M coarse rows: FFT of length M, zero padding, inverse FFT of length N.
  void interpolate(const Eigen::MatrixXd& coarse, Eigen::MatrixXd& full) const;
  // pp (the PpTrack, in a frame turned by each array's mean angle) from the channels at the M coarse
  // nodes without the N-node grid. w = (C + i S) e^{-i theta} is a trigonometric polynomial (the
  // interpolant's coefficients); turned so that its constant term A is real, with E = sum |W_k|,
  // D1 = sum |k| |W_k|, D2 = sum k^2 |W_k| over k != 0: Re w >= A - E > 0 and f = arg w has
  // |f''| <= D2 / (A - E) + (D1 / (A - E))^2 = F2. w is evaluated on K nodes (one inverse FFT); between
  // two of them, h apart, f exceeds the larger end value by at most F2 h^2 / 8, so only the intervals
  // that could hold the max or the min are evaluated node by node. The same pp as the N-node pass up to
  // round-off. false (nothing done) where the bound is weak: A - E <= A / 2 or F2 h^2 / 8 >= 0.1 rad.
  // asym (symmetrized models): its part of the channels added at every node evaluated, its bound
  // widening delta (an ideal chain only).
  bool pp_bounded(const Eigen::MatrixXd& cs_coarse, const SignalChain::Applied& chain, PpTrack& track,
                  const Asymmetry* asym = nullptr) const;
  // pp_bounded's w at node m from its coefficients Wr + i Wi of the frequencies kmin, kmin + 1, ...
  // (Horner in e^{i theta}).
  std::complex<double> w_at(int m, const std::vector<double>& Wr, const std::vector<double>& Wi, int kmin) const;
  // The asymmetry's part of every array's channels on pp_bounded's K-node grid (row p, array a: p A + a).
  void asym_on_grid(const Asymmetry& as, int K, std::vector<std::complex<double>>& out) const;
  // The PpTrack at node m from the channels C[a], S[a] of every array.
  void track_channels(int m, std::vector<double>& C, std::vector<double>& S, const SignalChain::Applied& chain,
                      PpTrack& track) const;
  // eps (and psi) of every array from its channels at every node (cs: N x 2 arrays(), C then S), the
  // signal chain applied: eps = atan2 of (C, S) turned back by theta, in bulk (core/vector_math.hpp).
  void angles_of_channels(const Eigen::MatrixXd& cs, const SignalChain::Applied& chain,
                          std::vector<Eigen::VectorXd>& eps_deg, std::vector<UnitAngles>* psi) const;
  // pp of every array at mount mt: the PpTrack pass, then atan2 (eps_mount) when it wrapped.
  void pp_mount(const Mount& mt, const SignalChain::Applied& chain, double elevation_deg, const EnvReadings* env,
                double* pp_deg, std::vector<double>* peak_T = nullptr) const;
  // fmin_mT, fmax_mT of every array from the distinct probes' peak |reading| (T).
  void field_window(const std::vector<double>& peak_T, double* fmin_mT, double* fmax_mT) const;
};

}  // namespace magenc
