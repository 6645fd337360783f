// Floating-point trap of Debug builds (src/core/fp_trap.*, style.md item 11).
// Each check runs its operation in a forked child (a death test): the child
// inherits this process's floating-point environment, i.e. the trap that
// tests/catch_main.cpp enabled, so a child killed by SIGFPE proves the trap is
// active in the test executables. In a build without MAGENC_FP_TRAP the same
// children must survive (the trap is compiled out), and the test says so.
// MAGENC_EXPECT_FP_TRAP (tests/CMakeLists.txt: 1 in Debug) checks that the
// library was built with the trap exactly when the build type asks for it.
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cfenv>
#include <cfloat>
#include <csignal>
#include <functional>
#include <string>
#include <thread>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"

using namespace magenc;

namespace {

// How a forked child running op() ended.
struct ChildEnd {
  bool sigfpe = false;     // killed by SIGFPE
  bool exited_ok = false;  // returned from op() and exited with 0
  std::string what;        // for INFO
};

ChildEnd run_in_child(const std::function<void()>& op) {
  const pid_t pid = fork();
  if (pid == 0) {
    // Child: default SIGFPE action (not Catch's reporting handler), no core file.
    std::signal(SIGFPE, SIG_DFL);
    const rlimit no_core{0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    op();
    _exit(0);
  }
  ChildEnd end;
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid) {
    end.what = "fork/waitpid failed";
    return end;
  }
  end.sigfpe = WIFSIGNALED(status) && WTERMSIG(status) == SIGFPE;
  end.exited_ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  end.what = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status))
                                 : "exited with " + std::to_string(WEXITSTATUS(status));
  return end;
}

// volatile keeps the compiler from folding the operation away.
void divide_zero_by_zero() { volatile double z = 0.0; volatile double r = z / z; (void)r; }   // FE_INVALID
void divide_one_by_zero() { volatile double z = 0.0; volatile double r = 1.0 / z; (void)r; }  // FE_DIVBYZERO
void overflow() { volatile double m = DBL_MAX; volatile double r = m * 2.0; (void)r; }         // FE_OVERFLOW

void expect_trap(const ChildEnd& end) {
  INFO("child " << end.what);
  if (fp_trap_compiled_in())
    CHECK(end.sigfpe);
  else
    CHECK(end.exited_ok);
}

void say_if_compiled_out() {
  if (!fp_trap_compiled_in())
    WARN("floating-point trap not compiled in (not a Debug build): checked only that the operations do not trap");
}

}  // namespace

TEST_CASE("The trap is compiled in exactly in Debug builds", "[fp_trap]") {
  CHECK(fp_trap_compiled_in() == bool(MAGENC_EXPECT_FP_TRAP));
}

TEST_CASE("Debug builds trap invalid, divide-by-zero and overflow from the start of main", "[fp_trap]") {
  say_if_compiled_out();
  const auto op = GENERATE(as<std::string>{}, "0/0", "1/0", "DBL_MAX*2");
  INFO("operation " << op);
  if (op == "0/0") expect_trap(run_in_child(divide_zero_by_zero));
  if (op == "1/0") expect_trap(run_in_child(divide_one_by_zero));
  if (op == "DBL_MAX*2") expect_trap(run_in_child(overflow));
}

TEST_CASE("Threads started after main inherit the trap", "[fp_trap]") {
  // The OpenMP pool is made of pthreads created after main, as this std::thread is.
  say_if_compiled_out();
  expect_trap(run_in_child([] {
    std::thread t(divide_zero_by_zero);
    t.join();
  }));
}

TEST_CASE("run_main enables the trap for the executables", "[fp_trap]") {
  say_if_compiled_out();
  expect_trap(run_in_child([] {
    fedisableexcept(FE_ALL_EXCEPT);  // undo catch_main's trap: only run_main's counts here
    divide_zero_by_zero();           // untrapped: must survive
    run_main("test_fp_trap", [] {
      divide_zero_by_zero();
      return 0;
    });
  }));
}

TEST_CASE("Underflow and inexact are not trapped", "[fp_trap]") {
  const auto end = run_in_child([] {
    volatile double tiny = DBL_MIN;
    volatile double r = tiny * 1e-300;  // FE_UNDERFLOW | FE_INEXACT
    (void)r;
  });
  INFO("child " << end.what);
  CHECK(end.exited_ok);
}

TEST_CASE("FpTrapPause masks the trap in its scope and restores it after", "[fp_trap]") {
  say_if_compiled_out();
  const auto inside = run_in_child([] {
    FpTrapPause pause;
    divide_zero_by_zero();
    divide_one_by_zero();
    overflow();
  });
  INFO("inside the pause: child " << inside.what);
  CHECK(inside.exited_ok);
  expect_trap(run_in_child([] {
    { FpTrapPause pause; divide_zero_by_zero(); }
    divide_zero_by_zero();
  }));
}
