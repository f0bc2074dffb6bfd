// Small text, file and timing helpers every layer uses: one definition each.
#pragma once

#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace glintlab {

// "a, b, c" (or with another separator), each item wrapped in `quote` ("" for none).
inline std::string join(const std::vector<std::string>& items, const char* sep = ", ", const char* quote = "") {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) s += (i ? sep : "") + (quote + items[i] + quote);
  return s;
}

// `s` with A-Z as a-z and every other byte as it is (how OpenColorIO, file extensions and device names
// compare without regard to case here; no locale).
inline std::string ascii_lower(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  return s;
}

// A C/GLSL identifier: a letter or '_', then letters, digits and '_' (ASCII; no locale).
inline bool is_identifier(const std::string& s) {
  auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (s.empty() || !alpha(s[0])) return false;
  for (char c : s)
    if (!alpha(c) && !(c >= '0' && c <= '9')) return false;
  return true;
}

// A file's whole content, or nullopt when it cannot be opened (the caller says what it is in its error).
inline std::optional<std::string> read_text_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Milliseconds since t0 on the steady clock.
inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace glintlab
