#include "core/errors.hpp"

#include "core/fp_trap.hpp"

#include <CLI/CLI.hpp>
#include <iostream>
#include <sstream>

namespace magenc {

std::string num(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
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
