// inspect: a magnet and a sensor pose from a measured 3-axis field scan (docs/interfaces.md "inspect").
// Model: the scan's nominal positions p_i (magnet frame, mm) are off by one offset o (mm) for the whole
// scan; the sensor's axes are turned by R = Rz(c) Ry(b) Rx(a) (extrinsic x, then y, then z), so a reading
// is R^T B(p_i + o); B is the exact field (AnalyticField) of the configured cylinder with polarization
// magnitude Br (T) and direction (magnetization_deg, magnetization_elevation_deg).
// Fit: the free groups (offset, rotation, polarization, direction) by nonlinear least squares (Ceres,
// Levenberg-Marquardt) on the residuals reading_model - reading_measured (mT), from the nominal values.
// Uncertainty as in diagnose: sigma^2 = RSS/(3N - k) (J^T J)^-1 at the optimum, through the SVD of the
// column-normalised Jacobian (central differences); directions whose singular value is below
// 1/cond_limit of the largest are what the scan cannot separate: their parameters get sigma = infinity
// and are listed as not identifiable.
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "fields/magnet.hpp"

namespace magenc {

// A field scan: nominal positions (3 x N, mm, magnet frame) and the readings (3 x N, T, sensor axes).
struct FieldScan {
  Eigen::Matrix3Xd p_mm;
  Eigen::Matrix3Xd B_T;
};

inline constexpr int kInspectParams = 9;
// The parameters in fit.json order: offset_x_mm, offset_y_mm, offset_z_mm, rot_x_deg, rot_y_deg,
// rot_z_deg, polarization_T, magnetization_deg, magnetization_elevation_deg.
struct InspectParameter {
  std::string name;   // fit.json name
  std::string group;  // offset | rotation | polarization | direction
  std::string unit;   // mm | deg | T
  double scale;       // typical size (scaling of the fit and of the finite differences)
};
const std::array<InspectParameter, kInspectParams>& inspect_parameters();
// --free groups: a comma-separated subset of offset,rotation,polarization,direction; InputError otherwise.
std::vector<std::string> parse_inspect_groups(const std::string& text, const std::string& what);

using InspectValues = std::array<double, kInspectParams>;
// The nominal values of a magnet: no offset, no rotation, its Br and direction.
InspectValues nominal_inspect_values(const Magnet& magnet);
// Model readings R^T B(p + o) (3 x N, T) for the values v and the magnet's size.
Eigen::Matrix3Xd inspect_model_T(const Magnet& magnet, const Eigen::Matrix3Xd& p_mm, const InspectValues& v);

struct InspectOptions {
  std::vector<std::string> groups{"offset", "rotation", "polarization"};  // free groups
  double cond_limit = 1e6;   // condition number above which directions count as not identifiable
  int max_iterations = 200;
  double fd_step = 1e-5;     // central-difference step of the covariance Jacobian, in typical sizes
};

struct InspectResult {
  InspectValues value{}, sigma{};      // sigma: 0 for fixed, infinity when not identifiable
  std::array<bool, kInspectParams> free{};
  std::vector<std::string> free_names;  // fit order
  Eigen::MatrixXd correlation;          // free x free (NaN where sigma is infinite)
  Eigen::VectorXd singular_values;      // column-normalised Jacobian, descending
  double condition = 0;
  std::vector<std::string> not_identifiable;
  Eigen::Matrix3Xd fitted_T;            // model readings at the optimum
  double residual_rms_mT = 0;           // over all 3N components
  int iterations = 0;
};

// A fit whose residual RMS exceeds this fraction of the readings' RMS explains nothing of the scan.
inline constexpr double kInspectMaxResidualFraction = 0.5;
// A fitted polarization beyond the range of magnet.br_T, (0, 10] T, is no magnet's.
inline constexpr double kInspectMaxPolarization_T = 10.0;

// Fits the scan. InputError for fewer readings than free parameters, a point on the magnet's surface.
// ComputeError (exit 3, no output) when the optimizer fails (e.g. every step puts a point on the magnet's
// surface), ends at |polarization| > kInspectMaxPolarization_T, or leaves a residual RMS above
// kInspectMaxResidualFraction of the readings' RMS.
InspectResult inspect_scan(const Magnet& nominal, const FieldScan& scan, const InspectOptions& opts);

}  // namespace magenc
