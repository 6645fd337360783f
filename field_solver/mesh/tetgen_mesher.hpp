// The one adapter around TetGen (only tetgen_mesher.cpp includes tetgen.h).
#pragma once
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

struct MesherOptions {
  double radius_edge_ratio = 2.0;  // TetGen -q quality bound (radius/shortest edge), > 1
  double min_dihedral_deg = 10.0;  // TetGen -q minimum dihedral angle (deg)
  bool verbose = false;            // false: TetGen runs quietly (-Q)
  long max_added_points = 0;       // > 0: TetGen adds at most this many points (-S); reaching it is refused
  double max_seconds = 0;          // > 0: TetGen runs in a child process, stopped and refused past this
};

// Quality tetrahedral mesh of the PLC with per-region attributes and maximum
// volumes (TetGen switches p q A a). Throws ComputeError naming TetGen's
// reason (self-intersection, small feature, ...) when TetGen fails, InputError when it reaches
// max_added_points (a feature too small for the mesh sizes: the mesh would not end) or runs past
// max_seconds. With max_seconds > 0 TetGen runs in a forked child process (the same mesh, byte for
// byte; its nodes, tets and regions come back through a pipe): past the budget the child is killed,
// and a crash inside TetGen is a ComputeError instead of the end of this process.
TetMesh tetrahedralize_plc(const Plc& plc, const MesherOptions& options);

}  // namespace magenc::fem
