#include "core/format.hpp"

#include <ctime>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

namespace magenc {

std::string fmt(double v, int digits) {
  if (!std::isfinite(v)) return "nan";
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  std::string t = os.str();
  if (t.front() == '-' && t.find_first_not_of("-0.") == std::string::npos) t.erase(0, 1);
  return t;
}

std::string fmt_auto(double v, int digits, double zero_below) {
  if (!std::isfinite(v)) return "nan";
  if (v == 0 || std::abs(v) < zero_below) return "0";
  if (std::abs(v) >= std::pow(10.0, -(digits - 1))) return fmt(v, digits);
  std::ostringstream os;
  os << std::scientific << std::setprecision(1) << v;
  return os.str();
}

std::string fmt_sig(double v, int significant) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", significant, v);
  return buf;
}

std::string utc_timestamp_iso() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

}  // namespace magenc
