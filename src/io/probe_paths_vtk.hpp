// Probe paths as VTK polylines (.vtp) for the ParaView state probe_paths.pvsm.
//
// File contract (paraview_states/README.md relies on it; keep names stable):
//   * one vtkPolyData, coordinates in mm in the MAGNET frame (the frame of
//     output/field/*.vti and mesh.vtu), i.e. where each probe sits relative
//     to the magnet at rest while the rotor turns;
//   * K polylines (one per probe), polyline k = probe k, M points each, in
//     rotor-angle order; the points of probe k are stored contiguously
//     (point index k*M + m). When theta_deg is M uniform steps over exactly
//     one turn (theta_m = theta_0 + 360*m/M), each polyline is closed: its
//     M+1 point ids end with its first point again (no duplicated point);
//   * point data  `Bz`        (double, T)   field the probe reads at that point
//                                           (n.B with a tilted sensor or magnet; Bz otherwise);
//   * point data  `theta_deg` (double, deg) rotor angle of that sample;
//   * point data  `probe`     (int)         probe index k (0-based);
//   * cell data   `probe`     (int)         probe index k of each polyline.
// Studies write it as output/<study>/paths_<case>.vtp.
#pragma once
#include <Eigen/Core>
#include <filesystem>

#include "probe/angle_error.hpp"

namespace magenc {

// Writes the probe paths of one mounting case to `file` (.vtp, XML, binary
// appended, zlib-compressed) atomically: written under a temporary name in the
// same directory, then renamed; no partial file on failure. Parent
// directories are created.
//
//   positions_mm  3 x (M*K)  probe positions in the magnet frame [mm];
//                            column m*K + k = probe k at rotor angle m
//                            (the layout the probe pipeline produces).
//   Bz_T          M*K        field read by that probe at that angle [T],
//                            same column order as positions_mm.
//   probes_K      K >= 1     number of probes.
//   theta_deg     M >= 1     rotor angle of each step [deg].
//
// Throws std::invalid_argument on inconsistent sizes or non-finite values,
// magenc::ComputeError if VTK cannot write the file.
void write_probe_paths_vtp(const std::filesystem::path& file, const Eigen::Matrix3Xd& positions_mm,
                           const Eigen::VectorXd& Bz_T, int probes_K, const Eigen::VectorXd& theta_deg);

// The paths of one mounting case as the pipeline computes them: probe
// positions from probe_paths_mm(setup, mount) and the readings of `result`
// (angle_error(field, setup, mount) for the same setup and mount), written
// with write_probe_paths_vtp.
void write_case_probe_paths_vtp(const std::filesystem::path& file, const ProbeSetup& setup, const Mount& mount,
                                const AngleErrorResult& result);

}  // namespace magenc
