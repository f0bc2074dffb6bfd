// Small text and timing helpers every layer uses: one definition each.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace glintlab {

// "a, b, c" (or with another separator), each item wrapped in `quote` ("" for none).
inline std::string join(const std::vector<std::string>& items, const char* sep = ", ", const char* quote = "") {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) s += (i ? sep : "") + (quote + items[i] + quote);
  return s;
}

// Milliseconds since t0 on the steady clock.
inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace glintlab
