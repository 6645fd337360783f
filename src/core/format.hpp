// Numbers and words as text: the one place where magenc turns a double into
// characters, for summaries (fmt, fmt_auto), tables and plot data (fmt_sig)
// and one-line error messages (num in errors.hpp is fmt_sig(v, 6)).
#pragma once
#include <string>

namespace magenc {

// Fixed-point text with `digits` decimals; "-0.000" is printed as "0.000";
// "nan" for NaN and infinities.
std::string fmt(double v, int digits = 3);

// Number for summary tables: fixed with `digits` decimals when |v| >= 10^-(digits-1),
// otherwise scientific with 2 significant digits ("3.1e-06"); "0" when v == 0 or
// |v| < zero_below; "nan" for NaN and infinities.
std::string fmt_auto(double v, int digits = 4, double zero_below = 0.0);

// Shortest text with `significant` significant digits, as printf's "%.<significant>g"
// (and an std::ostream with precision(significant)) prints it: "0.1", "1e-07", "inf".
// Tables use 10 digits, configuration echoes 12, messages 6.
std::string fmt_sig(double v, int significant);

// s without leading and trailing blanks (space, tab, CR, LF).
std::string trim(const std::string& s);

// The current time in UTC, ISO 8601 ("2026-11-23T18:40:47Z"), for run metadata.
std::string utc_timestamp_iso();

}  // namespace magenc
