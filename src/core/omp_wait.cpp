#include "core/omp_wait.hpp"

#include <unistd.h>

#include <cstdlib>

namespace magenc {

void prefer_passive_omp_wait(int argc, char** argv) {
  (void)argc;
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // execv failed (no /proc): carry on with the default policy; only speed is affected.
}

}  // namespace magenc
