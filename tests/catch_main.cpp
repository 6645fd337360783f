// Shared main of the Catch2 test executables. In Debug builds it enables the
// floating-point trap (src/core/fp_trap.hpp) before Catch runs anything, so every
// test case, and every thread it starts, traps FE_INVALID | FE_DIVBYZERO |
// FE_OVERFLOW; Catch reports the SIGFPE against the running test case.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "core/fp_trap.hpp"

int main(int argc, char* argv[]) {
  magenc::enable_fp_trap();
  return Catch::Session().run(argc, argv);
}
