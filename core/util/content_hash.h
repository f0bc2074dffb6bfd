// Content hashing for caches (SPIR-V, reference frames): XXH3-128 from
// libxxhash, printed as 32 hex digits. Feed every input that determines the
// cached result, each with its own add() call so boundaries are unambiguous.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace glintlab::core {

class ContentHash {
 public:
  ContentHash();
  ~ContentHash();
  ContentHash(const ContentHash&) = delete;
  ContentHash& operator=(const ContentHash&) = delete;

  ContentHash& add(std::string_view bytes);  // length-prefixed
  ContentHash& add(const void* data, size_t bytes);
  ContentHash& add(double v);
  ContentHash& add(int64_t v);
  std::string hex() const;

 private:
  void* state_;
};

std::string hash_hex(std::string_view bytes);

}  // namespace glintlab::core
