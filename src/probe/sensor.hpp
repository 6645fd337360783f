// Sensing principles, field windows and finite sensing areas (docs/physics.md,
// "Sensor principles"). How the die turns the field into two channels:
//   bz      (default) Hall plates reading n.B at the probes of an array (two,
//           diff4, ring:N) on the circle r0; channel offsets in mT;
//   inplane one spot at the die centre (array `point`, r0 unused) reading the
//           in-plane components b1 = x'.B, b2 = y'.B along the die axes
//           x' = Rs x, y' = Rs y (Rs the sensor tilt); u_c = -b1, u_s = -b2
//           (3-D Hall, Hall with concentrators); channel offsets in mT;
//   xmr     saturated GMR/TMR: u = -(b1, b2)/|(b1, b2)| (direction only);
//           channel offsets relative to the unit amplitude;
//   amr     anisotropic MR: alpha = atan2(-b2, -b1), u_c = cos 2alpha,
//           u_s = sin 2alpha; phi = atan2(u_s, u_c)/2, the error is defined
//           modulo 180 deg and wrapped into (-90, 90]; relative offsets.
// A field window [field_min_mT, field_max_mT] (off: 0 and inf) is the field
// magnitude the chip needs: bz the peak |reading| of each probe over a turn,
// in-plane principles hypot(b1, b2) at every theta. A finite sensing area is a
// square of side plate_mm centred on each probe or spot in the die plane; the
// reading is its mean, by an n x n Gauss-Legendre rule (n = plate_points).
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "core/config.hpp"

namespace magenc {

enum class SensorPrinciple { Bz, InPlane, Xmr, Amr };

// "bz", "inplane", "xmr", "amr" -> the principle; InputError naming `what` otherwise.
SensorPrinciple parse_principle(const std::string& text, const std::string& what = "sensor.principle");
std::string principle_name(SensorPrinciple p);
// The principles in declaration order.
const std::vector<SensorPrinciple>& all_principles();
// The in-plane principles read one spot (array `point`) from Bx, By.
inline bool reads_in_plane(SensorPrinciple p) { return p != SensorPrinciple::Bz; }
// xmr and amr: unit-amplitude channels, offsets relative (offset_*_rel); bz and inplane: offsets in mT.
inline bool relative_offsets(SensorPrinciple p) { return p == SensorPrinciple::Xmr || p == SensorPrinciple::Amr; }
// Electrical turns of the channel angle atan2(u_s, u_c) per mechanical turn: 2 for amr, 1 otherwise.
inline int electrical_turns(SensorPrinciple p) { return p == SensorPrinciple::Amr ? 2 : 1; }

struct FieldWindow {
  double min_mT = 0;                                        // sensor.field_min_mT
  double max_mT = std::numeric_limits<double>::infinity();  // sensor.field_max_mT
  // Off (0 and inf): every field is inside.
  bool active() const { return min_mT > 0 || max_mT < std::numeric_limits<double>::infinity(); }
  // [lo, hi] of a magnitude lies in the window.
  bool contains(double lo_mT, double hi_mT) const { return lo_mT >= min_mT && hi_mT <= max_mT; }
  // min >= 0 and finite, max > 0 (may be inf), min <= max (InputError naming the key).
  void validate() const;
};

struct SensingArea {
  double plate_mm = 0;   // side of the square sensing area (0 = a point)
  int plate_points = 4;  // n of the n x n Gauss-Legendre rule (used when plate_mm > 0)
  bool point() const { return plate_mm == 0; }
  // plate_mm finite in [0, 10] mm, plate_points in [1, 32] (InputError naming the key).
  void validate() const;
  // Offsets (u, v) in the die plane (mm) and weights (sum 1) of the rule over the square:
  // one node (0, 0) with weight 1 for a point.
  void nodes(std::vector<double>& u_mm, std::vector<double>& v_mm, std::vector<double>& w) const;
  static constexpr double kMaxPlate_mm = 10.0;
  static constexpr int kMaxPoints = 32;
};

// Gauss-Legendre rule of n points on [-1, 1] (Golub-Welsch: the eigenvalues of the symmetric
// tridiagonal Jacobi matrix, off-diagonal k/sqrt(4k^2 - 1), are the nodes; 2 v_0^2 of the
// normalized eigenvectors the weights). Exact for polynomials of degree <= 2n - 1. n >= 1.
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w);

// The chip's direction and zero (docs/physics.md "Ring magnets and sensors off the axis"):
// phi = wrap(direction * atan2(u_s, u_c) + zero); amr: the same on the electrical angle, halved.
// "auto" (sensor.direction, sensor.zero_deg) and the gain trim (sensor.gain_trim = auto: the sin
// channel scaled so that both channels have the cos channel's first-harmonic amplitude, MagAlpha's
// BCT) are taken on the nominal mount by resolve_orientation (probe/angle_error.hpp).
struct ChipOrientation {
  int direction = 1;           // 1 | -1
  double zero_deg = 0;         // added to the angle
  bool direction_auto = false;
  bool zero_auto = false;
  bool gain_auto = false;      // sensor.gain_trim = auto
  bool any_auto() const { return direction_auto || zero_auto || gain_auto; }
  // The default: the angle as the channels give it (every on-axis result of earlier versions).
  bool identity() const { return direction == 1 && zero_deg == 0 && !any_auto(); }
  // Reads sensor.direction ("1", "-1", "auto"), sensor.zero_deg (degrees in [-360, 360] or "auto")
  // and sensor.gain_trim ("none", "auto"); InputError naming the key otherwise.
  static ChipOrientation from_config(const Config& cfg);
};

// Studies whose fast paths assume a solid magnet and an array centred on the axis (radius, design): an
// InputError naming the key (magnet.inner_radius_mm, sensor.plane_height_mm <= 0, sensor.center_mm,
// sensor.direction, sensor.zero_deg, sensor.gain_trim) when the configuration leaves that layout; `who` says
// which study.
void require_on_axis_layout(const Config& cfg, const std::string& who);

// A key that does not apply to the configured principle must keep its default (which means "not
// used"): sensor.r0_mm for the point principles, the mT offsets for xmr/amr, the relative offsets for
// bz/inplane. InputError naming the key and the principle otherwise. (A key at its default is not
// "set": the array's default two stands for point under an in-plane principle.)
void check_principle_keys(const Config& cfg);

// The [sensor] keys: sensing plane and probe radius, probe array and samples per turn (probe_array,
// angle_error), the signal chain (signal_chain.hpp), the principle, field window and sensing area (above).
// The temperature drifts of the offsets are Environment::keys() (probe/environment.hpp).
std::vector<KeySpec> sensor_keys();

}  // namespace magenc
