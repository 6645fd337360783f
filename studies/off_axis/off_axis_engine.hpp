// The off_axis study's computation (docs/studies/off_axis.md): a ring magnet read three ways on one
// tolerance box (magnet eccentricity and lean, sensor radial/tangential/axial offsets and tilt):
//   side-shaft: a point sensor (inplane, xmr) beside the ring, raw, with the gain trim (sensor.gain_trim =
//               auto, MagAlpha's BCT) and with each calibration method taken at the nominal mount;
//   bore:       Bz arrays (ring:N, diff4) on the circle r0 around the bore above the ring face.
// Every reader's direction and zero are "auto" (resolved once on the nominal mount). Per reader: the
// nominal curve, the Monte Carlo p50/p99 of pp, the mean spectrum, the field window; the budget (each
// mounting group of the box alone); p99 against the side-shaft read radius and the bore array's gap; the
// in-plane field magnitude around the ring on the mid-plane (the field map).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/calibration.hpp"
#include "analysis/tolerance.hpp"
#include "core/config.hpp"
#include "fields/analytic_field.hpp"

namespace magenc {

struct OffAxisOptions {
  Eigen::Vector2d side_center_mm{18.0, 0.0};
  double side_height_mm = -2.0;  // sensing plane of the side-shaft chip above the top face (mid-plane: -L/2)
  std::vector<std::string> side_principles = {"inplane", "xmr"};
  std::vector<std::string> methods = {"ogp", "harmonics:16", "lut:64"};
  std::vector<std::string> bore_arrays = {"diff4", "ring:8", "ring:16"};
  double bore_r0_mm = 13.5;
  double bore_height_mm = 1.0;
  ToleranceBox box;
  long samples = 200;
  std::uint64_t seed = 1;
  int steps = 360;
  std::vector<double> scan_side_x_mm = {16.5, 17, 18, 20, 23, 27};
  std::vector<double> scan_gap_mm = {0.5, 1, 1.5, 2, 3};
  long scan_samples = 60;

  static std::vector<KeySpec> keys();  // [off_axis] and the tol.* box
  static OffAxisOptions from_config(const Config& cfg);
};

struct OffAxisReader {
  std::string label;      // "side inplane raw", "side inplane trimmed", "side inplane ogp", "bore ring:8"
  std::string layout;     // side-shaft | bore
  std::string principle;  // inplane, xmr, bz
  std::string treatment;  // raw, trimmed (BCT), a calibration method, or the array name
  ProbeSetup setup;       // resolved (direction, zero, trim)
  Correction correction;  // none for raw, trimmed and bore
  Eigen::VectorXd nominal_eps_deg;   // the nominal mount's curve
  double nominal_pp_deg = 0;
  double p50_deg = 0, p99_deg = 0;   // pp over the box
  Eigen::VectorXd mean_c_deg;        // mean c_1..c_8 over the box
  double field_min_mT = 0, field_max_mT = 0;  // over the box
  std::vector<double> budget_p99_deg;         // per group of OffAxisResult::groups
};

struct OffAxisResult {
  Magnet magnet;
  double k = 1;                   // the side-shaft ellipse of the first side principle: A / B of its field
  double trim_gain_mismatch = 0;  // what the gain trim sets (k - 1 for the in-plane Hall)
  double ogp_trim = 0;            // 1/r - 1 of ogp's fitted ellipse at the nominal mount (r = A_s / A_c)
  std::vector<OffAxisReader> readers;
  std::vector<std::string> groups;  // budget groups
  Eigen::VectorXd theta_deg;
  std::vector<double> scan_side_p99_raw, scan_side_p99_trim, scan_side_k;  // per scan_side_x_mm
  std::vector<std::vector<double>> scan_gap_p99;                           // bore array x gap
  // The field map: |B_inplane| (mT) on the mid-plane over a square grid of x, y.
  std::vector<double> map_x_mm, map_y_mm;
  std::vector<std::vector<double>> map_mT;  // rows: y (last y first), columns: x
  double wall_s = 0;
};

OffAxisResult run_off_axis(const Config& cfg, const OffAxisOptions& opt);

}  // namespace magenc
