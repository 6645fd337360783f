// Error types and the common main() wrapper.
#pragma once
#include <functional>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>

namespace magenc {

// Bad user input (config value, CLI flag, input file). The message is one line
// that names the input and its allowed range; executables exit with code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A computation that failed for a reason other than input (mesher failure,
// solver not converging, NaN in a result). Executables exit with code 3.
class ComputeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A number as it appears in one-line error messages (6 significant digits).
std::string num(double v);

// Throws InputError "<name> is not a finite number: allowed a finite value" for the first of the named
// values that is NaN or infinite (the checks of Mount::validate, SignalChain::validate).
void require_finite(std::initializer_list<std::pair<const char*, double>> named_values);

// Runs body() and turns exceptions into a one-line message on stderr and a
// non-zero exit code: InputError -> 2, ComputeError -> 3, anything else -> 1.
// In Debug builds it first enables the floating-point trap (fp_trap.hpp).
int run_main(const std::string& program, const std::function<int()>& body);

}  // namespace magenc
