// Validating reader for JSON configuration (experiment files, camera paths,
// material overrides). Every error names the file, the key path and what is
// allowed; unknown keys are errors. Parsing itself is nlohmann::json's.
//
//   JsonReader r(j, "experiments/data/default.json");          // root object
//   int w = r.get_int("width", 640, 1, 16384);             // optional with default
//   std::string s = r.get_enum("scene", {"plane","dune"}); // required
//   JsonReader cam = r.child("camera");                    // nested object
//   r.finish();                                            // unknown keys -> error
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace glintlab {

// Thrown for any invalid configuration. what() is the full user-facing message.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads a JSON file; a missing, non-regular (a FIFO, a device) or malformed
// file is a ConfigError naming the file (and line/column for syntax errors),
// and so is one nested deeper than kMaxJsonDepth.
nlohmann::json read_json_file(const std::string& path);

// Configuration is never deeper than this; deeper input (10^5 nested arrays)
// is refused before anything walks or prints it recursively.
constexpr size_t kMaxJsonDepth = 64;
// ConfigError naming `file` when `j` nests deeper than kMaxJsonDepth (checked
// without recursion).
void check_json_depth(const nlohmann::json& j, const std::string& file);

// j.dump(indent) that never throws for strings that are not UTF-8 (a file name can be any bytes):
// such bytes are written as U+FFFD. What every file glintlab writes from JSON goes through.
std::string dump_json(const nlohmann::json& j, int indent = -1);

class JsonReader {
 public:
  // `j` must outlive the reader. `file` names the source for messages,
  // `path` is the key path of `j` inside it ("" for the root).
  JsonReader(const nlohmann::json& j, std::string file, std::string path = "");

  bool has(const std::string& key) const;
  const nlohmann::json& raw(const std::string& key);  // marks key as used; required

  double get_number(const std::string& key, double lo, double hi);
  double get_number(const std::string& key, double def, double lo, double hi);
  int get_int(const std::string& key, long long lo, long long hi);
  int get_int(const std::string& key, long long def, long long lo, long long hi);
  bool get_bool(const std::string& key);
  bool get_bool(const std::string& key, bool def);
  std::string get_string(const std::string& key);
  std::string get_string(const std::string& key, const std::string& def);
  std::string get_enum(const std::string& key, const std::vector<std::string>& allowed);
  std::string get_enum(const std::string& key, const std::string& def, const std::vector<std::string>& allowed);
  // Fixed-length number array with per-element range, e.g. a vec3.
  std::vector<double> get_numbers(const std::string& key, size_t n, double lo, double hi);
  std::vector<double> get_numbers(const std::string& key, const std::vector<double>& def, double lo, double hi);

  JsonReader child(const std::string& key);  // required object
  std::optional<JsonReader> optional_child(const std::string& key);
  // Elements of a required array, each wrapped as a reader ("key[3]").
  std::vector<JsonReader> array(const std::string& key, size_t min_len = 0, size_t max_len = SIZE_MAX);

  // Element readers for arrays of objects / this reader's own json.
  const nlohmann::json& json() const { return j_; }
  const std::string& file() const { return file_; }
  std::string key_path(const std::string& key) const;

  // Throws ConfigError listing every key that was never read.
  void finish() const;
  // Throws ConfigError "<file>: <path.key>: <message>".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  const nlohmann::json& find(const std::string& key) const;
  const nlohmann::json& j_;
  std::string file_;
  std::string path_;
  std::set<std::string> used_;
  mutable std::set<std::string> asked_;  // every key the caller knows, present or not
};

}  // namespace glintlab
