// JSON text for the files armsim writes.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace wmra {
namespace armsim {

inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if ((unsigned char)c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// v rounded to `decimals` places without trailing zeros (0.25, not 0.2500), so that long
// columns of samples stay compact; null where JSON has no number (NaN, infinities)
inline void append_json_number(std::string& out, double v, int decimals) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char buf[40];
  int n = std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  if (decimals > 0) {
    while (buf[n - 1] == '0') --n;
    if (buf[n - 1] == '.') --n;
  }
  if (n == 2 && buf[0] == '-' && buf[1] == '0') {
    out += '0';
    return;
  }
  out.append(buf, n);
}

}  // namespace armsim
}  // namespace wmra
