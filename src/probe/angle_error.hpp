// The probe-path pipeline: field (magnet frame) -> mounting -> probe array ->
// angle -> error eps(theta) -> spectrum.
#pragma once
#include <Eigen/Core>

#include "core/defaults.hpp"
#include "fields/field_source.hpp"
#include "probe/environment.hpp"
#include "probe/mounting.hpp"
#include "core/config.hpp"
#include "probe/probe_array.hpp"
#include "probe/sensor.hpp"
#include "probe/signal_chain.hpp"
#include "probe/speed.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

struct ProbeSetup {
  ProbeArray array;           // probe angles and channel weights ("point" for the in-plane principles)
  double r0_mm = defaults::kProbeRadius_mm;  // nominal probe radius (unused by the point array)
  double plane_z_mm = defaults::kPlaneZ_mm;  // sensing plane height in the magnet frame (z_s)
  int steps = 3600;           // M samples of theta over one turn (>= 16)
  SignalChain chain;          // channel offsets, gain mismatch, phase error (applied before atan2)
  // Magnet height L (mm): the magnet tilt pivots about the centre of the magnet's
  // bottom face P = (0, 0, -L/2) (magnet frame), so the kinematics need L. Set it
  // with the magnet's height (probe_setup_from_config does); it matters only when
  // mount.magnet_tilt_deg != 0. With the exact field a mismatch with the field's
  // magnet is an InputError.
  double magnet_height_mm = defaults::kMagnetHeight_mm;
  // How the die turns the field into channels (probe/sensor.hpp, docs/physics.md "Sensor principles"):
  // bz reads n.B at the array's probes; inplane, xmr, amr read b1 = x'.B, b2 = y'.B at one spot.
  SensorPrinciple principle = SensorPrinciple::Bz;
  SensingArea area{};         // finite sensing area (plate_mm = 0: points)
  FieldWindow window{};       // the field magnitude the chip needs (off by default)
  // Stray fields and temperature (probe/environment.hpp): the magnet's field scaled by Br(T)/Br, the
  // stray field added at every probe before the reading, the offsets and the air gap at T. Neutral
  // by default (no stray field, 20 C): then the pipeline is exactly the one without it.
  Environment env{};
  // A turning encoder (probe/speed.hpp, docs/physics.md "Speed"): the chip's timing at speed.rpm, applied to
  // the channels of a whole turn after the signal chain. Static by default (rpm 0): then never entered.
  SpeedChain speed{};
  // The die centre's nominal position in the fixed frame (sensor.center_mm): the probe circle or the
  // spot is centred there; the mount's static offsets add to it. Zero: on the axis.
  Eigen::Vector2d center_mm = Eigen::Vector2d::Zero();
  // The chip's direction, zero and gain trim (probe/sensor.hpp); the default changes nothing.
  ChipOrientation orientation{};
  // A multipole track (docs/physics.md "Multipole rings and nonius"): the read head's ELECTRICAL spacing
  // (the array's angles b_k / p: sensor_setup_from_config divides them), the electrical angle phi_e =
  // atan2(u_s, u_c) read incrementally, eps = wrap(phi_e - p theta) / p in (-180/p, 180/p]. 1 and false:
  // the single-period reading of a uniform magnet, unchanged.
  int pole_pairs = 1;
  bool multipole = false;
};

// The setup with every "auto" of its orientation resolved on the nominal mount (docs/physics.md "Ring
// magnets and sensors off the axis"): the same field, principle, array, centre and plane; every mount
// offset and tilt, signal-chain error and environment effect zero. direction = the sign of the winding of
// atan2(u_s, u_c) over a turn; the gain trim multiplies 1 + gain_mismatch by A_c / A_s, the channels'
// first-harmonic amplitudes; zero = minus the circular mean error (the angle of the mean of exp(i eps))
// with that direction and trim. InputError when the angle does not wind once at the nominal mount.
// A setup without "auto" is returned unchanged. angle_error() resolves it itself when needed; a study
// that runs many mounts resolves once.
ProbeSetup resolve_orientation(const FieldSource& field, const ProbeSetup& setup);

// The ProbeSetup of the [sensor] keys (principle, r0, steps, signal chain, sensing area, field window),
// the sensing plane z_s = L/2 + h and the magnet height; the array from array_spec (`what` names it in
// errors). check_principle_keys() first. Under an in-plane principle the array is point: array_spec
// "point", or sensor.array's default ("two") when what is "sensor.array" (the default is not a choice);
// any other array is an InputError naming `what` and the principle.
// Also reads sensor.center_mm and the orientation (sensor.direction, sensor.zero_deg, sensor.gain_trim), and
// refuses (InputError naming the keys) a sensing point in the magnet's material at the nominal mount.
ProbeSetup sensor_setup_from_config(const Config& cfg, const std::string& array_spec,
                                    const std::string& what = "sensor.array");

struct AngleErrorResult {
  Eigen::VectorXd theta_deg;  // M rotor angles, 360*m/M
  Eigen::VectorXd eps_deg;    // angle error wrap(phi - theta), degrees
  Eigen::MatrixXd probe_B_T;  // M x K probe readings (T; before the signal chain): bz n.B of each probe,
                              // in-plane principles hypot(b1, b2) of the spot (K = 1)
  Eigen::MatrixXd inplane_B_T;// in-plane principles: M x 2, the components b1 = x'.B, b2 = y'.B (T); bz: empty
  Eigen::MatrixXd channels;   // M x 2: the channels (u_c, u_s) after the signal chain, the arguments of atan2
                              // (T for bz and inplane, unit amplitude for xmr and amr; amr: twice the angle)
  Spectrum spectrum;
  // Field window (docs/physics.md "Sensor principles"): the extremes of the magnitude the principle uses, mT:
  // bz the peak |reading| over the turn of each probe, min and max over the probes; in-plane principles
  // hypot(b1, b2), min and max over theta. in_window: both lie in setup.window (always true when it is off).
  double field_min_mT = 0, field_max_mT = 0;
  bool in_window = true;
  // The chip's direction and zero the angle was taken with ("auto" resolved): what a correction of the
  // channels (ogp) applies to its own angle.
  ChipOrientation orientation{};
};

// Probe positions for every theta: returns 3 x (M*K) in the magnet frame (mm),
// column m*K + k = probe k at theta_m. Full kinematics (tilts included, mounting.hpp).
Eigen::Matrix3Xd probe_paths_mm(const ProbeSetup& setup, const Mount& mount);
// The same for arbitrary rotor angles theta_deg (M values): 3 x (M*K).
Eigen::Matrix3Xd probe_paths_mm(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_deg);
// The M = steps uniform rotor angles 360*m/M of one turn, in degrees.
Eigen::VectorXd uniform_theta_deg(int steps);

// Probe normals (magnet frame, unit) for the same columns: 3 x (M*K).
Eigen::Matrix3Xd probe_normals(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_deg);

// Runs the pipeline for one mounting case: all M*K probe positions (and, with
// a tilt, normals), one batch field call (OpenMP inside the source), readings
// n.B, channels, signal chain, atan2, wrap, spectrum. Without any tilt the
// readings are Bz (the source's cheaper Bz kernel); with a tilt, n.B from the
// full vector. With a sensing area each probe is n x n points of the die plane
// (weights of sensing.hpp) and its reading their weighted mean. The in-plane
// principles read b1, b2 at the spot from the full vector (die axes Rs x, Rs y
// through the same kinematics); xmr normalizes them, amr doubles their angle
// and wraps eps into (-90, 90].
// Throws InputError when
//  * the setup is invalid: r0 <= 0 or NaN (bz arrays), steps < 16, non-finite
//    plane height, non-finite mount values, |tilt| > 45 deg, invalid signal
//    chain (or offsets of the other kind for the principle), magnet height <= 0
//    when the magnet is tilted, an array that does not fit the principle
//    (point for the in-plane ones, two/diff4/ring:N for bz), a negative or
//    non-finite plate, plate_points outside [1, 32], a field window min > max;
//  * an in-plane principle is asked of a source that gives only Bz on a plane
//    (gives_full_vector() false);
//  * (angle_error, in-plane principles) the field direction at the spot does
//    not turn once per turn (the spot is too far off the axis);
//  * a tilt (sensor or magnet) is asked of a source that only knows Bz on a
//    plane (gives_full_vector() false: linear, a 2-D grid);
//  * the path is degenerate: r0 - |s| - |d| <= 0 (a probe circle may pass over
//    the rotation axis, the angle no longer turns once per turn) - any field;
//  * for the exact field (AnalyticField): a probe path enters the magnet or
//    touches its surface (radius <= R while |z_s + dz| <= L/2). The test is
//    exact (closest approach | |p_k + s| - |d| | of each probe's circle), not
//    just at the samples. A sensing plane above the top face (the normal case,
//    h + dz > 0) always passes; a plane within the magnet's height is allowed
//    only with every probe path outside radius R (a sensor beside the magnet).
//    The field itself is defined inside too (B includes mu0*M0), but a probe
//    inside a magnet is not a mounting the program should silently answer.
//    grid:/fem: sources reject points outside their region themselves.
//    With a tilt the test is conservative (it may refuse a mount that just
//    clears the magnet, never accepts one that enters it): the probe's path
//    in the rotor frame is a circle about the axis of radius rho_k at height
//    z_k; the tilted magnet lies within radius |d| + R + L|sin g| of the axis
//    and within z in [-L/2 - R|sin g|, -L/2 + L cos g + R|sin g|]; the path
//    must avoid that ring-shaped hull (| rho_k - |d| | > R + L|sin g|, or z_k
//    outside the z range). With g = 0 this is the exact test above.
// Throws ComputeError if the field gives a non-finite angle.
AngleErrorResult angle_error(const FieldSource& field, const ProbeSetup& setup, const Mount& mount);

// The error curve at arbitrary rotor angles theta_deg (any order, any spacing; e.g. a measured curve's
// angles): theta_deg, eps_deg and probe_B_T are filled, spectrum is left empty (it needs uniform samples).
// setup.steps is not used. Same validation and errors as angle_error().
AngleErrorResult angle_error_at(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                const Eigen::VectorXd& theta_deg);
// At a speed (setup.speed.acts()) angle_error() applies the steady-state chain of probe/speed.hpp to the
// channels of the whole turn; angle_error_at() has no whole turn and refuses a speed (InputError).
// Convenience: only the spectrum.
Spectrum error_spectrum(const FieldSource& field, const ProbeSetup& setup, const Mount& mount);

// Periods of the read angle per turn: the principle's (amr 2) times the track's pole pairs.
int reading_turns(const ProbeSetup& setup);

// The electrical spacing of a multipole magnet: with magnet.pattern = axial_multipole or radial_multipole
// (pole pairs p) the array's angles are divided by p and the reading is incremental (ProbeSetup::pole_pairs);
// refuses (InputError naming the keys) a bz array whose read radius does not lie over the track (outside
// [magnet.inner_radius_mm, magnet.radius_mm]). No change for the other patterns.
void apply_multipole_reading(const Config& cfg, ProbeSetup& setup);

}  // namespace magenc
