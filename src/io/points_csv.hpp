// Point lists of field_at and field scans of inspect (docs/interfaces.md "field_at"): a CSV with the header
// x_mm,y_mm,z_mm (any column order, no other columns; '#' comment lines and
// blank lines ignored), one point per row in the magnet frame (mm), and the
// answer table x_mm,y_mm,z_mm,Bx_T,By_T,Bz_T.
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "fields/field_table.hpp"

namespace magenc {

// Reads the points file: 3 x N (mm), N >= 1. InputError (one line naming the
// file, the line and the column) on a missing, unknown or repeated column, a
// row with the wrong number of cells, a non-finite or non-numeric value, no rows.
Eigen::Matrix3Xd read_points_csv(const std::filesystem::path& path);
// The same from text (what the file holds); `where` names it in errors.
Eigen::Matrix3Xd parse_points_csv(const std::string& text, const std::string& where);

// A field scan (inspect --scan): header x_mm,y_mm,z_mm and Bx_mT,By_mT,Bz_mT or Bx_T,By_T,Bz_T (any
// order; the same rules and errors as the points file). p_mm: nominal positions (3 x N, mm, magnet
// frame); B_T: the readings in the sensor's axes (3 x N, converted to T); unit: "mT" or "T" as read.
// The largest reading must lie in the window of `limits` (a field table's, fields/field_table.hpp).
struct ScanTable {
  Eigen::Matrix3Xd p_mm, B_T;
  std::string unit;
};
ScanTable read_scan_csv(const std::filesystem::path& path, const FieldTableLimits& limits = {});
ScanTable parse_scan_csv(const std::string& text, const std::string& where, const FieldTableLimits& limits = {});

// The answer table: header x_mm,y_mm,z_mm,Bx_T,By_T,Bz_T and one row per point,
// every number with 17 significant digits (reads back to the same double).
std::string points_field_csv(const Eigen::Matrix3Xd& points_mm, const Eigen::Matrix3Xd& B_T);

}  // namespace magenc
