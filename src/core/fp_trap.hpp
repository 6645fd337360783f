// Floating-point exception trap for Debug builds (style.md item 11).
//
// A Debug build (CMAKE_BUILD_TYPE=Debug compiles src/core/fp_trap.cpp with
// MAGENC_FP_TRAP) turns the IEEE flags FE_INVALID (0/0, inf - inf, sqrt(-1),
// ordered comparison with NaN, NaN -> int), FE_DIVBYZERO (x/0, log(0)) and
// FE_OVERFLOW into SIGFPE, so a NaN or inf is caught where it is produced
// rather than where it surfaces in a table. Underflow and inexact stay
// untrapped. Every other build leaves the floating-point environment alone.
//
// The trap is per thread: enable_fp_trap() acts on the calling thread, and a
// thread inherits the environment of the thread that creates it (pthreads, so
// std::thread and the OpenMP pool). It is therefore called first thing in main
// (run_main for the executables, tests/catch_main.cpp for the Catch2 tests),
// before any worker thread exists.
#pragma once

namespace magenc {

// True when this build traps (compiled with MAGENC_FP_TRAP on glibc).
bool fp_trap_compiled_in();

// Enables the trap on the calling thread when compiled in; no-op otherwise.
void enable_fp_trap();

// Masks the trap on the calling thread for its lifetime and restores the
// previous trap set on destruction (the raised flags are cleared, so code
// after the guard starts clean). For third-party code that raises these flags
// as part of correct operation; say which and why at the call site. Only the
// calling thread is affected: do not wrap OpenMP regions with it.
class FpTrapPause {
 public:
  FpTrapPause();
  ~FpTrapPause();
  FpTrapPause(const FpTrapPause&) = delete;
  FpTrapPause& operator=(const FpTrapPause&) = delete;

 private:
  // Trapped exception set (FE_* bits) to restore. Read only where the trap is compiled in
  // (fp_trap.cpp); the layout stays the same in every build, so the member stays too.
  [[maybe_unused]] int saved_;
};

}  // namespace magenc
