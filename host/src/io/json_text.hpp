#pragma once
// Numbers and strings as JSON and exact decimal text (internal to libnoether): the run summary's
// JSON (summary_format.cpp) and the fit's (fit.cpp) write them the same way.
#include <cmath>
#include <cstdio>
#include <string>

namespace noether::detail {

// A double to 17 significant digits: reads back to the same double (for --set values, messages).
inline std::string exact_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A JSON number; null for NaN and infinities.
inline std::string json_number(double x) { return std::isfinite(x) ? exact_text(x) : "null"; }

// A JSON string: quotes and backslashes escaped, control characters as \u00XX.
inline std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

}  // namespace noether::detail
