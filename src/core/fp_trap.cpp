#include "core/fp_trap.hpp"

#include <cfenv>

namespace magenc {

namespace {
#if defined(MAGENC_FP_TRAP) && defined(__GLIBC__)
constexpr bool kTrap = true;
constexpr int kTrapped = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
#else
constexpr bool kTrap = false;
#endif
}  // namespace

bool fp_trap_compiled_in() { return kTrap; }

void enable_fp_trap() {
#if defined(MAGENC_FP_TRAP) && defined(__GLIBC__)
  std::feclearexcept(kTrapped);  // flags raised before main must not fire at the next FP instruction
  feenableexcept(kTrapped);
#endif
}

FpTrapPause::FpTrapPause() : saved_(0) {
#if defined(MAGENC_FP_TRAP) && defined(__GLIBC__)
  saved_ = fedisableexcept(kTrapped);
#endif
}

FpTrapPause::~FpTrapPause() {
#if defined(MAGENC_FP_TRAP) && defined(__GLIBC__)
  std::feclearexcept(kTrapped);
  if (saved_ > 0) feenableexcept(saved_);
#endif
}

}  // namespace magenc
