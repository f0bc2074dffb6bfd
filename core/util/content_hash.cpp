#include "core/util/content_hash.h"

// XXH3 compiled into this file (xxhash's header-only mode): the program links no libxxhash, one
// library fewer for the dynamic loader to map and search at every start.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include <cstdio>
#include <stdexcept>

namespace glintlab::core {

ContentHash::ContentHash() : state_(XXH3_createState()) {
  if (!state_ || XXH3_128bits_reset(static_cast<XXH3_state_t*>(state_)) != XXH_OK)
    throw std::runtime_error("ContentHash: cannot initialise XXH3 state");
}

ContentHash::~ContentHash() { XXH3_freeState(static_cast<XXH3_state_t*>(state_)); }

ContentHash& ContentHash::add(const void* data, size_t bytes) {
  uint64_t n = bytes;
  XXH3_128bits_update(static_cast<XXH3_state_t*>(state_), &n, sizeof n);
  XXH3_128bits_update(static_cast<XXH3_state_t*>(state_), data, bytes);
  return *this;
}

ContentHash& ContentHash::add(std::string_view bytes) { return add(bytes.data(), bytes.size()); }
ContentHash& ContentHash::add(double v) { return add(&v, sizeof v); }
ContentHash& ContentHash::add(int64_t v) { return add(&v, sizeof v); }

std::string ContentHash::hex() const {
  XXH128_hash_t h = XXH3_128bits_digest(static_cast<XXH3_state_t*>(state_));
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return buf;
}

std::string hash_hex(std::string_view bytes) {
  ContentHash h;
  h.add(bytes);
  return h.hex();
}

}  // namespace glintlab::core
