#include "experiments/sources/reference_cache.h"

#include "core/util/atomic_file.h"
#include "core/util/content_hash.h"
#include "core/util/io_error.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace glintlab {

namespace {
// 002: the checksum covers the header's size fields too (a swapped width and height passed 001's).
constexpr char kMagic[8] = {'G', 'L', 'R', 'E', 'F', '0', '0', '2'};

struct Header {
  char magic[8];
  int32_t width, height, channels, reserved;
  char key[32];
  char checksum[32];  // XXH3-128 hex of width, height, channels and the pixel bytes
};

std::string checksum(const Image& img) {
  core::ContentHash h;
  h.add(int64_t(img.width)).add(int64_t(img.height)).add(int64_t(img.channels));
  h.add(img.data.data(), img.data.size() * 4);
  return h.hex();
}
}  // namespace

ReferenceCache::ReferenceCache(std::string dir) : dir_(std::move(dir)) {}

std::string ReferenceCache::path_of(const std::string& key) const { return (fs::path(dir_) / (key + ".ref")).string(); }

std::optional<Image> ReferenceCache::load(const std::string& key, bool* corrupt) const {
  if (corrupt) *corrupt = false;
  if (!enabled()) return std::nullopt;
  std::string path = path_of(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  auto bad = [&]() -> std::optional<Image> {
    in.close();
    std::error_code ec;
    fs::remove(path, ec);
    if (corrupt) *corrupt = true;
    return std::nullopt;
  };
  Header h{};
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h)) return bad();
  if (std::memcmp(h.magic, kMagic, 8) != 0 || std::string(h.key, 32) != key.substr(0, 32)) return bad();
  if (h.width <= 0 || h.height <= 0 || h.channels <= 0 || h.width > 65536 || h.height > 65536 || h.channels > 4)
    return bad();
  Image img(h.width, h.height, h.channels);
  if (!in.read(reinterpret_cast<char*>(img.data.data()), std::streamsize(img.data.size() * 4))) return bad();
  if (in.peek() != std::char_traits<char>::eof()) return bad();
  if (checksum(img) != std::string(h.checksum, 32)) return bad();
  return img;
}

void ReferenceCache::store(const std::string& key, const Image& img) const {
  if (!enabled()) return;
  if (key.size() < 32) throw std::invalid_argument("ReferenceCache: key must be a 32-digit hash");
  fs::create_directories(dir_);
  Header h{};
  std::memcpy(h.magic, kMagic, 8);
  h.width = img.width;
  h.height = img.height;
  h.channels = img.channels;
  std::memcpy(h.key, key.data(), 32);
  std::string sum = checksum(img);
  std::memcpy(h.checksum, sum.data(), 32);
  write_file_atomic(path_of(key), [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(img.data.data()), std::streamsize(img.data.size() * 4));
    out.flush();
    if (!out) throw IoError(tmp.string() + ": cannot write reference cache entry");
  });
}

}  // namespace glintlab
