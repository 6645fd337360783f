// The one adapter around TetGen (only tetgen_mesher.cpp includes tetgen.h).
#pragma once
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

struct MesherOptions {
  double radius_edge_ratio = 2.0;  // TetGen -q quality bound (radius/shortest edge), > 1
  double min_dihedral_deg = 10.0;  // TetGen -q minimum dihedral angle (deg)
  bool verbose = false;            // false: TetGen runs quietly (-Q)
};

// Quality tetrahedral mesh of the PLC with per-region attributes and maximum
// volumes (TetGen switches p q A a). Throws ComputeError naming TetGen's
// reason (self-intersection, small feature, ...) when TetGen fails.
TetMesh tetrahedralize_plc(const Plc& plc, const MesherOptions& options);

}  // namespace magenc::fem
