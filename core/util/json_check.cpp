#include "core/util/json_check.h"
#include "core/util/strings.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace glintlab {

namespace {
std::string type_name(const nlohmann::json& v) { return v.type_name(); }

std::string quoted_list(const std::vector<std::string>& xs) { return join(xs, ", ", "\""); }

std::string fmt_num(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}
}  // namespace

std::string dump_json(const nlohmann::json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

void check_json_depth(const nlohmann::json& j, const std::string& file) {
  std::vector<std::pair<const nlohmann::json*, size_t>> stack = {{&j, 1}};
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    if (!node->is_structured()) continue;
    if (depth > kMaxJsonDepth)
      throw ConfigError(file + ": nested more than " + std::to_string(kMaxJsonDepth) +
                        " levels deep (no glintlab file is)");
    for (const auto& child : *node) stack.emplace_back(&child, depth + 1);
  }
}

nlohmann::json read_json_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ConfigError(path + ": not a regular file (only regular files are read)");
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception& e) {  // syntax errors, and numbers beyond a double (1e400)
    throw ConfigError(path + ": malformed JSON: " + e.what());
  }
  check_json_depth(j, path);
  return j;
}

JsonReader::JsonReader(const nlohmann::json& j, std::string file, std::string path)
    : j_(j), file_(std::move(file)), path_(std::move(path)) {
  if (!j_.is_object())
    throw ConfigError(file_ + ": " + (path_.empty() ? std::string("<root>") : path_) +
                      ": expected an object, got " + type_name(j_));
}

std::string JsonReader::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void JsonReader::fail(const std::string& key, const std::string& message) const {
  throw ConfigError(file_ + ": " + key_path(key) + ": " + message);
}

bool JsonReader::has(const std::string& key) const {
  asked_.insert(key);
  return j_.contains(key);
}

const nlohmann::json& JsonReader::find(const std::string& key) const {
  auto it = j_.find(key);
  if (it == j_.end()) fail(key, "required key is missing");
  return *it;
}

const nlohmann::json& JsonReader::raw(const std::string& key) {
  used_.insert(key);
  asked_.insert(key);
  return find(key);
}

double JsonReader::get_number(const std::string& key, double lo, double hi) {
  const auto& v = raw(key);
  if (!v.is_number()) fail(key, "expected a number in [" + fmt_num(lo) + ", " + fmt_num(hi) + "], got " + type_name(v));
  double x = v.get<double>();
  if (!std::isfinite(x) || x < lo || x > hi)
    fail(key, "value " + fmt_num(x) + " is out of range; allowed [" + fmt_num(lo) + ", " + fmt_num(hi) + "]");
  return x;
}

double JsonReader::get_number(const std::string& key, double def, double lo, double hi) {
  if (!has(key)) return def;
  return get_number(key, lo, hi);
}

int JsonReader::get_int(const std::string& key, long long lo, long long hi) {
  const auto& v = raw(key);
  bool integral = v.is_number_integer() || (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>());
  if (!integral)
    fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                  (v.is_number() ? "the non-integer " + fmt_num(v.get<double>()) : type_name(v)));
  double x = v.get<double>();
  if (x < double(lo) || x > double(hi))
    fail(key, "value " + fmt_num(x) + " is out of range; allowed [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(x);
}

int JsonReader::get_int(const std::string& key, long long def, long long lo, long long hi) {
  if (!has(key)) return static_cast<int>(def);
  return get_int(key, lo, hi);
}

bool JsonReader::get_bool(const std::string& key) {
  const auto& v = raw(key);
  if (!v.is_boolean()) fail(key, "expected true or false, got " + type_name(v));
  return v.get<bool>();
}

bool JsonReader::get_bool(const std::string& key, bool def) { return has(key) ? get_bool(key) : def; }

std::string JsonReader::get_string(const std::string& key) {
  const auto& v = raw(key);
  if (!v.is_string()) fail(key, "expected a string, got " + type_name(v));
  return v.get<std::string>();
}

std::string JsonReader::get_string(const std::string& key, const std::string& def) {
  return has(key) ? get_string(key) : def;
}

std::string JsonReader::get_enum(const std::string& key, const std::vector<std::string>& allowed) {
  const auto& v = raw(key);
  if (!v.is_string()) fail(key, "expected one of " + quoted_list(allowed) + ", got " + type_name(v));
  std::string s = v.get<std::string>();
  for (const auto& a : allowed)
    if (a == s) return s;
  fail(key, "\"" + s + "\" is not allowed; expected one of " + quoted_list(allowed));
}

std::string JsonReader::get_enum(const std::string& key, const std::string& def,
                                 const std::vector<std::string>& allowed) {
  return has(key) ? get_enum(key, allowed) : def;
}

std::vector<double> JsonReader::get_numbers(const std::string& key, size_t n, double lo, double hi) {
  const auto& v = raw(key);
  std::string want = "an array of " + std::to_string(n) + " numbers in [" + fmt_num(lo) + ", " + fmt_num(hi) + "]";
  if (!v.is_array() || v.size() != n) fail(key, "expected " + want + ", got " + (v.is_array() ? "an array of " + std::to_string(v.size()) : type_name(v)));
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) {
    if (!v[i].is_number()) fail(key, "element " + std::to_string(i) + ": expected " + want);
    double x = v[i].get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
      fail(key, "element " + std::to_string(i) + " = " + fmt_num(x) + " is out of range; allowed [" + fmt_num(lo) + ", " + fmt_num(hi) + "]");
    out.push_back(x);
  }
  return out;
}

std::vector<double> JsonReader::get_numbers(const std::string& key, const std::vector<double>& def, double lo,
                                            double hi) {
  return has(key) ? get_numbers(key, def.size(), lo, hi) : def;
}

JsonReader JsonReader::child(const std::string& key) {
  const auto& v = raw(key);
  if (!v.is_object()) fail(key, "expected an object, got " + type_name(v));
  return JsonReader(v, file_, key_path(key));
}

std::optional<JsonReader> JsonReader::optional_child(const std::string& key) {
  if (!has(key)) return std::nullopt;
  return child(key);
}

std::vector<JsonReader> JsonReader::array(const std::string& key, size_t min_len, size_t max_len) {
  const auto& v = raw(key);
  if (!v.is_array()) fail(key, "expected an array of objects, got " + type_name(v));
  if (v.size() < min_len || v.size() > max_len)
    fail(key, "expected between " + std::to_string(min_len) + " and " +
                  (max_len == SIZE_MAX ? std::string("any number of") : std::to_string(max_len)) + " elements, got " +
                  std::to_string(v.size()));
  std::vector<JsonReader> out;
  for (size_t i = 0; i < v.size(); ++i) {
    std::string p = key_path(key) + "[" + std::to_string(i) + "]";
    if (!v[i].is_object()) throw ConfigError(file_ + ": " + p + ": expected an object, got " + type_name(v[i]));
    out.emplace_back(v[i], file_, p);
  }
  return out;
}

void JsonReader::finish() const {
  std::vector<std::string> unknown;
  for (auto it = j_.begin(); it != j_.end(); ++it)
    if (!used_.count(it.key())) unknown.push_back(it.key());
  if (unknown.empty()) return;
  std::vector<std::string> known(asked_.begin(), asked_.end());
  throw ConfigError(file_ + ": " + key_path(unknown.front()) + ": unknown key" +
                    (unknown.size() > 1 ? " (also unknown: " + quoted_list({unknown.begin() + 1, unknown.end()}) + ")" : "") +
                    (known.empty() ? "" : "; allowed keys here: " + quoted_list(known)));
}

}  // namespace glintlab
