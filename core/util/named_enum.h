// One table of names per enum: parsing, printing and the list of allowed names
// all read the same table, so adding a value is adding one row, and a name
// that is not in the table is an error, never a silent fall-through.
//
//   enum class Aa { None, Ssaa };
//   inline constexpr EnumTable<Aa, 2> kAaNames{{{Aa::None, "none"}, {Aa::Ssaa, "ssaa"}}};
//   enum_name(kAaNames, Aa::Ssaa) == "ssaa";  enum_from_name(kAaNames, "ssaa") == Aa::Ssaa
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace glintlab {

template <typename E, size_t N>
using EnumTable = std::array<std::pair<E, const char*>, N>;

template <typename E, size_t N>
std::vector<std::string> enum_names(const EnumTable<E, N>& table) {
  std::vector<std::string> out;
  for (const auto& [v, name] : table) out.emplace_back(name);
  return out;
}

// Throws std::logic_error for a value missing from the table (a programming error).
template <typename E, size_t N>
const char* enum_name(const EnumTable<E, N>& table, E value) {
  for (const auto& [v, name] : table)
    if (v == value) return name;
  throw std::logic_error("enum value without a name in its table");
}

template <typename E, size_t N>
std::optional<E> enum_from_name(const EnumTable<E, N>& table, std::string_view name) {
  for (const auto& [v, n] : table)
    if (name == n) return v;
  return std::nullopt;
}

// "\"a\", \"b\", \"c\"" for error messages.
template <typename E, size_t N>
std::string enum_name_list(const EnumTable<E, N>& table) {
  std::string out;
  for (const auto& [v, name] : table) out += (out.empty() ? "\"" : ", \"") + std::string(name) + "\"";
  return out;
}

}  // namespace glintlab
