// Stray-field immunity (docs/physics.md "Environment: stray fields and temperature"): per sensor
// (bz arrays two, diff4, ring:N on r0; the one-spot principles inplane, xmr, amr) on the configured
// mount and field:
//  * a uniform stray field of magnitude b over a sphere of directions (polar x azimuth grid, poles
//    once): the worst pp and c1 over the directions, and the worst direction;
//  * the field each sensor tolerates for each error threshold (worst pp over the directions <= the
//    threshold): the largest b up to which it holds, by a logarithmic scan of b and bisection;
//  * an infinite straight conductor at a distance from the sensor centre carrying a current, in two
//    orientations: along y at the height of the die (its field is normal to the die there) and along
//    z (vertical: its field lies in the die plane);
//  * the error over the directions at one magnitude, for the direction maps.
// The mount is fixed, so every run reads the magnet's field at the same points: the field is
// evaluated once per sensor (a cache of the last batch) and each stray field costs only the
// readings' combination (the same pipeline, angle_error.hpp).
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

inline constexpr double kmT_per_kA_per_m = 1.2566370614359172;  // mu0 * 1 kA/m in mT (air)

struct StrayFieldOptions {
  std::vector<std::string> sensors = {"two", "diff4", "ring:8", "inplane", "xmr", "amr"};
  std::vector<double> levels_kA_per_m = {0.1, 0.5, 1, 2, 4};  // ISO 11452-8-style test levels (H in air)
  double curve_min_mT = 0.01, curve_max_mT = 20;               // error vs magnitude: log range
  int curve_points = 17;
  int polar_points = 13;    // polar angles 0..180 deg (both poles included)
  int azimuth_points = 24;  // azimuths 0..360 deg (excluded)
  double map_kA_per_m = 4;  // magnitude of the direction maps
  std::vector<double> thresholds_deg = {0.1, 1.0};  // pp thresholds of the tolerated field
  double search_max_mT = 1000;                       // tolerated-field search: upper end
  std::vector<double> wire_distances_mm = {5, 10, 20, 50};  // conductor distance from the sensor centre
  std::vector<double> wire_currents_A = {10, 100, 1000};
  int steps = 360;          // theta samples per turn

  static std::vector<KeySpec> keys();  // [study] keys
  static StrayFieldOptions from_config(const Config& cfg);
  // The unit directions of the sphere grid and their polar and azimuth angles (deg).
  void directions(std::vector<Eigen::Vector3d>& dirs, std::vector<double>& polar_deg,
                  std::vector<double>& azimuth_deg) const;
};

struct StrayError {
  double pp_deg = 0, c1_deg = 0;  // the worst over the directions (pp) and c1 of that direction
  double max_c1_deg = 0;          // largest c1 over the directions
  Eigen::Vector3d worst_dir = Eigen::Vector3d::UnitZ();  // direction of the worst pp
};

struct ToleratedField {
  double threshold_deg = 0;
  double field_mT = 0;   // largest uniform magnitude with worst pp <= threshold (inf: beyond search_max_mT)
  bool beyond = false;   // no magnitude up to search_max_mT exceeds the threshold
};

struct WireCase {
  std::string orientation;  // "along y" (field normal to the die at its height) or "along z" (in the die plane)
  double distance_mm = 0, current_A = 0;
  double pp_deg = 0, c1_deg = 0;
  double field_mT = 0;  // |B| of the conductor at the sensor centre
};

struct StraySensorResult {
  std::string label;
  SensorPrinciple principle = SensorPrinciple::Bz;
  double base_pp_deg = 0;              // the mount alone (no stray field)
  std::vector<double> curve_mT;        // error vs magnitude
  std::vector<StrayError> curve;
  std::vector<StrayError> levels;      // per options.levels_kA_per_m
  std::vector<ToleratedField> tolerated;  // per options.thresholds_deg
  std::vector<WireCase> wires;         // distances x currents x orientations
  Eigen::MatrixXd map_pp_deg;          // polar_points x azimuth_points at map_kA_per_m
};

struct StrayFieldResult {
  std::string field;  // FieldSource::name()
  Mount mount;
  std::vector<double> polar_deg, azimuth_deg;  // of the map grid (rows, columns)
  std::vector<StraySensorResult> sensors;
};

// Angle error of `setup` on `mount` with the uniform stray field b (mT, fixed frame) over the directions:
// the worst. `field` should be a field whose batches repeat (see the header comment).
StrayError worst_over_directions(const FieldSource& field, const ProbeSetup& setup, const Mount& mount, double b_mT,
                                 const std::vector<Eigen::Vector3d>& dirs);

// Runs the study's computation (sensors from `base` as in sensor_principles: r0, plane, magnet height,
// chain; steps from opt). InputError for a sensor the field cannot serve.
StrayFieldResult run_stray_field(const FieldSource& field, const ProbeSetup& base, const Mount& mount,
                                 const StrayFieldOptions& opt);

}  // namespace magenc
