// started_by_mpi_launcher(): whether this process was started by an MPI launcher (mpirun / mpiexec of
// Open MPI or MPICH, Slurm's srun), read from the environment the launcher sets for its processes. A
// process started without one is a single rank: it starts MPI only when it solves with PETSc, so that
// its input checks do not wait for MPI's singleton start-up (about 0.4 s).
#pragma once

#include <cstdlib>

namespace magenc {

inline bool started_by_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

}  // namespace magenc
