#include "core/errors.hpp"

#include "core/format.hpp"
#include "core/fp_trap.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>

namespace magenc {

std::string num(double v) { return fmt_sig(v, 6); }

void require_finite(std::initializer_list<std::pair<const char*, double>> named_values) {
  for (const auto& [name, v] : named_values)
    if (!std::isfinite(v)) throw InputError(std::string(name) + " is not a finite number: allowed a finite value");
}

int run_main(const std::string& program, const std::function<int()>& body) {
  enable_fp_trap();  // Debug builds only (fp_trap.hpp); before any OpenMP thread exists
  try {
    return body();
  } catch (const InputError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 2;
  } catch (const ComputeError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace magenc
