#include "core/material/glint_table.h"

#include "core/material/sand_material.h"
#include "core/util/atomic_file.h"
#include "core/util/content_hash.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "core/vk/compute_harness.h"
#include "core/vk/shader_compiler.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>

namespace glintlab::core {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTableShader = "glint/table.comp";

std::mutex& table_mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::shared_ptr<const std::vector<float>>>& memory_cache() {
  static std::map<std::string, std::shared_ptr<const std::vector<float>>> tables;
  return tables;
}
// Where no run set a folder: $XDG_CACHE_HOME/glintlab (else ~/.cache/glintlab), as the Vulkan
// driver's shader cache is kept; "" when neither is set.
std::string default_disk_dir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (fs::path(x) / "glintlab").string();
  if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".cache" / "glintlab").string();
  return "";
}
std::string& disk_dir() {
  static std::string dir = default_disk_dir();
  return dir;
}

std::vector<std::string> table_defines(const GlintModelDecl& d) {
  std::vector<std::string> defines = glint_model_defines(d);
  defines.push_back("GLINT_TABLE_GENERATE");
  return defines;
}

// A cached table is its n floats and, after them, the 32 hex digits of their XXH3-128 hash: an entry
// damaged on disk (or cut short) does not match and is generated again.
constexpr size_t kChecksumBytes = 32;

std::string table_checksum(const std::vector<float>& t) {
  ContentHash h;
  h.add(t.data(), t.size() * sizeof(float));
  return h.hex();
}

// The table of `file` when it is whole; false when it is missing, of another size or damaged (then
// `*damaged` is set for an entry that exists but does not match its checksum).
bool read_table(const fs::path& file, size_t n, std::vector<float>& out, bool* damaged) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  std::ifstream in(file, std::ios::binary);
  out.resize(n);
  std::string sum(kChecksumBytes, '\0');
  const bool whole = fs::file_size(file, ec) == n * sizeof(float) + kChecksumBytes &&
                     in.read(reinterpret_cast<char*>(out.data()), std::streamsize(n * sizeof(float))) &&
                     in.read(sum.data(), std::streamsize(sum.size())) && sum == table_checksum(out);
  if (!whole) *damaged = true;
  return whole;
}

}  // namespace

void set_glint_table_cache_dir(const std::string& dir) {
  std::lock_guard<std::mutex> lock(table_mutex());
  disk_dir() = dir;
}

std::shared_ptr<const std::vector<float>> glint_table(const VkContext& ctx, const GlintModelDecl& d) {
  if (d.table_size == 0) return std::make_shared<const std::vector<float>>();
  const std::vector<std::string> defines = table_defines(d);
  const std::string key =
      default_shader_compiler().source_hash(kTableShader, ShaderStage::Compute, defines) + "-" +
      std::to_string(d.table_size);
  std::lock_guard<std::mutex> lock(table_mutex());
  if (auto it = memory_cache().find(key); it != memory_cache().end()) return it->second;

  std::vector<float> table;
  auto path_in = [&](const std::string& dir) {
    return dir.empty() ? fs::path() : fs::path(dir) / "glint-tables" / (key + ".f32");
  };
  const fs::path file = path_in(disk_dir()), fallback = path_in(default_disk_dir());
  bool damaged = false;
  const bool cached = !file.empty() && read_table(file, d.table_size, table, &damaged);
  // a table generated where no run asked for it (glint-test) serves a run too; the run keeps its copy
  const bool found =
      cached || (!fallback.empty() && fallback != file && read_table(fallback, d.table_size, table, &damaged));
  if (!found && damaged)
    std::cerr << "note: the cached glint table of " << (d.file.empty() ? d.name : d.file) << " (" << file.string()
              << ") does not match its checksum: generating it again\n";
  if (!found) table = run_compute(ctx, kTableShader, defines, {}, d.table_size, d.table_size);
  for (size_t i = 0; i < table.size(); ++i)
    if (!std::isfinite(table[i]))
      throw ConfigError((d.file.empty() ? d.name : d.file) + ": glint_table_entry(" + std::to_string(i) +
                        ") is not finite (" + std::to_string(table[i]) + "); every table entry must be a finite number");
  if (!cached && !file.empty()) {
    fs::create_directories(file.parent_path());
    write_file_atomic(file, [&](const fs::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out.write(reinterpret_cast<const char*>(table.data()), std::streamsize(table.size() * sizeof(float)));
      const std::string sum = table_checksum(table);
      out.write(sum.data(), std::streamsize(sum.size()));
      if (!out) throw IoError(tmp.string() + ": cannot write the glint table");
    });
  }
  auto shared = std::make_shared<const std::vector<float>>(std::move(table));
  memory_cache()[key] = shared;
  return shared;
}

}  // namespace glintlab::core
