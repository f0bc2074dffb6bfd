// Structure-aware mutation of JSON documents for libFuzzer (LLVMFuzzerCustomMutator /
// LLVMFuzzerCustomCrossOver): an input that parses is mutated as a tree -- values replaced by
// values of other types and by range edges, keys added, renamed and removed with the names of the
// libFuzzer dictionary (-dict=, generated from the reader's sources by tests/fuzz/make_dict.sh),
// subtrees copied, wrapped, unwrapped and spliced between inputs -- and written back; an input
// that does not parse, and a share of those that do, get libFuzzer's byte-level mutations.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_common.h"

namespace glintlab_fuzz {

using json = nlohmann::json;

// The strings of a libFuzzer dictionary file whose token is itself a JSON string ("\"key\"" in
// the file): key names and enum values. Other tokens (syntax, numbers) are left to the byte level.
inline std::vector<std::string> dictionary_strings(const std::string& dict_path) {
  std::vector<std::string> out;
  std::ifstream in(dict_path);
  std::string line;
  while (std::getline(in, line)) {
    size_t q = line.find('"');
    if (q == std::string::npos || line.find_first_not_of(" \t") == line.find('#')) continue;
    std::string tok;
    size_t i = q + 1;
    for (; i < line.size() && line[i] != '"'; ++i) {
      if (line[i] == '\\' && i + 1 < line.size()) {
        char c = line[++i];
        if (c == 'x' && i + 2 < line.size()) {
          tok += char(std::stoi(line.substr(i + 1, 2), nullptr, 16));
          i += 2;
        } else {
          tok += c;
        }
      } else {
        tok += line[i];
      }
    }
    if (tok.size() >= 2 && tok.front() == '"' && tok.back() == '"') {
      try {
        json s = json::parse(tok);
        if (s.is_string()) out.push_back(s.get<std::string>());
      } catch (const json::exception&) {
      }
    }
  }
  return out;
}

class JsonMutator {
 public:
  std::vector<std::string> tokens;  // key names and string values

  // One to three tree mutations of `j` (any JSON value).
  void mutate(json& j, std::mt19937_64& rng) {
    rng_ = &rng;
    int n = coin(2) ? 1 : 2 + int(pick(2));
    for (int i = 0; i < n; ++i) mutate_once(j);
  }

  // `a` with a random node replaced by a copy of a random node of `b` (or, for two objects, with
  // some of b's members).
  void cross_over(json& a, const json& b, std::mt19937_64& rng) {
    rng_ = &rng;
    std::vector<json*> na;
    nodes(a, na);
    std::vector<const json*> nb;
    nodes(b, nb);
    json* target = na[pick(na.size())];
    const json* donor = nb[pick(nb.size())];
    if (target->is_object() && donor->is_object() && coin(2)) {
      for (auto it = donor->begin(); it != donor->end(); ++it)
        if (coin(2)) (*target)[it.key()] = it.value();
    } else {
      json copy = *donor;
      *target = std::move(copy);
    }
  }

 private:
  std::mt19937_64* rng_ = nullptr;

  size_t pick(size_t n) { return n ? std::uniform_int_distribution<size_t>(0, n - 1)(*rng_) : 0; }
  bool coin(size_t one_in) { return pick(one_in) == 0; }

  std::string token() { return tokens.empty() ? std::string("x") : tokens[pick(tokens.size())]; }

  template <typename J, typename P>
  static void nodes(J& j, std::vector<P>& out) {
    out.push_back(&j);
    if (j.is_structured())
      for (auto& c : j) nodes(c, out);
  }

  json number() {
    static const double kEdges[] = {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 1e-3, 1e-4, 1e-6, 9.99e-7, 1e-9, 1e-12, 0.05,
                                    0.1, 0.3, 0.999999, 1.000001, 1.5707963267948966, 1.5707963267948968, 3.0,
                                    3.0000001, 14.0, 14.000001, 89.0, 89.00001, 90.0, 179.0, 179.00001, 180.0, 360.0,
                                    3600.0, 36000.0, 36000.1, 1e3, 1000.0001, 1e4, 1e5, 1e6, 1e7, 1.0000001e7, 1e9,
                                    1e12, 1e300, -1e300, 5e-324, 2.2250738585072014e-308,
                                    std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
                                    16384.0, 16384.5, 16385.0, 2147483647.0, 2147483648.0, -2147483649.0,
                                    9007199254740993.0, 1.8446744073709552e19};
    static const int64_t kInts[] = {0, 1, -1, 2, 3, 4, 7, 8, 9, 15, 16, 17, 63, 64, 65, 100, 255, 256, 1000, 4096,
                                    4097, 16384, 16385, 65536, 1000000, 1000001, 2147483647, 2147483648LL,
                                    -2147483648LL, -2147483649LL, 4294967295LL, 4294967296LL,
                                    std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::min()};
    switch (pick(6)) {
      case 0: return kEdges[pick(sizeof kEdges / sizeof kEdges[0])];
      case 1: return -kEdges[pick(sizeof kEdges / sizeof kEdges[0])];
      case 2: return kInts[pick(sizeof kInts / sizeof kInts[0])];
      case 3: return std::numeric_limits<uint64_t>::max() - pick(3);
      case 4: return std::ldexp(std::uniform_real_distribution<double>(-1.0, 1.0)(*rng_), int(pick(120)) - 60);
      default: return int64_t(pick(40)) - 8;
    }
  }

  json scalar() {
    switch (pick(8)) {
      case 0:
      case 1:
      case 2: return number();
      case 3: return coin(2);
      case 4: return nullptr;
      case 5: return std::string();
      default: return token();
    }
  }

  json value(int depth) {
    if (depth > 0 && coin(4)) {
      json c = coin(2) ? json::object() : json::array();
      size_t n = pick(4);
      for (size_t i = 0; i < n; ++i) {
        if (c.is_object())
          c[token()] = value(depth - 1);
        else
          c.push_back(value(depth - 1));
      }
      return c;
    }
    return scalar();
  }

  void tweak_number(json& n) {
    double x = n.get<double>();
    switch (pick(10)) {
      case 0: n = x * 2; break;
      case 1: n = x / 2; break;
      case 2: n = x + 1; break;
      case 3: n = x - 1; break;
      case 4: n = -x; break;
      case 5: n = std::nextafter(x, std::numeric_limits<double>::infinity()); break;
      case 6: n = std::nextafter(x, -std::numeric_limits<double>::infinity()); break;
      case 7:  // integer <-> float spelling of the same value
        if (n.is_number_float() && std::fabs(x) < 9e18 && x == std::floor(x))
          n = int64_t(x);
        else
          n = x;
        break;
      case 8: n = x * 10; break;
      default: n = x + 0.5; break;
    }
    if (n.is_number_float() && !std::isfinite(n.get<double>())) n = number();
  }

  void mutate_once(json& root) {
    std::vector<json*> all;
    nodes(root, all);
    json& n = *all[pick(all.size())];
    switch (pick(12)) {
      case 0:
        n = scalar();
        return;
      case 1:
        n = value(2);
        return;
      case 2: {  // copy another node here (copied first: it may lie inside n)
        json copy = *all[pick(all.size())];
        n = std::move(copy);
        return;
      }
      case 3:
        if (coin(2))
          n = json::array({n});
        else
          n = json::object({{token(), n}});
        return;
      case 4:
        if (n.is_structured() && !n.empty()) {
          json copy = n.is_object() ? std::next(n.begin(), long(pick(n.size())))->get<json>() : n[pick(n.size())];
          n = std::move(copy);
        }
        return;
      default:
        break;
    }
    if (n.is_number()) {
      if (coin(3))
        n = number();
      else
        tweak_number(n);
    } else if (n.is_string()) {
      std::string s = n.get<std::string>();
      switch (pick(6)) {
        case 0: n = std::string(); break;
        case 1: n = s + token(); break;
        case 2: n = s.substr(0, pick(s.size() + 1)); break;
        case 3: n = s + std::string(1, char(pick(128))); break;
        default: n = token(); break;
      }
    } else if (n.is_boolean()) {
      n = !n.get<bool>();
    } else if (n.is_object()) {
      switch (pick(6)) {
        case 0:
        case 1: n[token()] = coin(3) ? json(*all[pick(all.size())]) : value(2); break;
        case 2:
          if (!n.empty()) {
            const std::string k = std::next(n.begin(), long(pick(n.size()))).key();
            n.erase(k);
          }
          break;
        case 3:
          if (!n.empty()) {  // rename a key
            auto it = std::next(n.begin(), long(pick(n.size())));
            json v = *it;
            std::string k = it.key();
            n.erase(k);
            n[token()] = std::move(v);
          }
          break;
        case 4: {  // give an existing key another value
          if (!n.empty()) {
            auto it = std::next(n.begin(), long(pick(n.size())));
            *it = value(2);
          }
          break;
        }
        default: n = json::object(); break;
      }
    } else if (n.is_array()) {
      switch (pick(6)) {
        case 0:
          if (!n.empty()) n.erase(n.begin() + long(pick(n.size())));
          break;
        case 1:
          if (!n.empty()) {
            json copy = n[pick(n.size())];
            n.insert(n.begin() + long(pick(n.size() + 1)), std::move(copy));
          }
          break;
        case 2: n.push_back(value(2)); break;
        case 3:
          if (!n.empty()) n[pick(n.size())] = value(2);
          break;
        case 4:
          if (n.size() > 1) std::swap(n[pick(n.size())], n[pick(n.size())]);
          break;
        default: n = json::array(); break;
      }
    } else {  // null
      n = value(2);
    }
  }
};

// Writes j into data[0, max_size) as compact (sometimes indented) JSON; 0 if it does not fit.
inline size_t write_json(const json& j, uint8_t* data, size_t max_size, bool indent) {
  std::string s = j.dump(indent ? 2 : -1, ' ', false, json::error_handler_t::replace);
  if (s.size() > max_size) return 0;
  std::memcpy(data, s.data(), s.size());
  return s.size();
}

}  // namespace glintlab_fuzz
