// On-disk cache of reference frames, keyed by a content hash of everything
// that determines them (scene, material, path frame, resolution, spp, shader
// source, device). Entries are raw fp32 with a header and a checksum; a
// truncated or corrupt entry is detected, reported and rebuilt.
#pragma once

#include "core/util/image.h"

#include <optional>
#include <string>

namespace glintlab {

class ReferenceCache {
 public:
  explicit ReferenceCache(std::string dir);  // "" disables the cache

  // The image if a valid entry exists. A corrupt entry is removed and
  // `*corrupt` set.
  std::optional<Image> load(const std::string& key, bool* corrupt = nullptr) const;
  // Atomic: writes a temporary file and renames it over the entry.
  void store(const std::string& key, const Image& img) const;
  std::string path_of(const std::string& key) const;
  bool enabled() const { return !dir_.empty(); }

 private:
  std::string dir_;
};

}  // namespace glintlab
