#include "core/material/glint_table.h"

#include "core/material/sand_material.h"
#include "core/util/atomic_file.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "core/vk/compute_harness.h"
#include "core/vk/shader_compiler.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
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
std::string& disk_dir() {
  static std::string dir;
  return dir;
}

std::vector<std::string> table_defines(const GlintModelDecl& d) {
  std::vector<std::string> defines = glint_model_defines(d);
  defines.push_back("GLINT_TABLE_GENERATE");
  return defines;
}

bool read_table(const fs::path& file, size_t n, std::vector<float>& out) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) != n * sizeof(float)) return false;
  std::ifstream in(file, std::ios::binary);
  out.resize(n);
  return bool(in.read(reinterpret_cast<char*>(out.data()), std::streamsize(n * sizeof(float))));
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
  const fs::path file = disk_dir().empty() ? fs::path() : fs::path(disk_dir()) / "glint-tables" / (key + ".f32");
  const bool cached = !file.empty() && read_table(file, d.table_size, table);
  if (!cached) table = run_compute(ctx, kTableShader, defines, {}, d.table_size, d.table_size);
  for (size_t i = 0; i < table.size(); ++i)
    if (!std::isfinite(table[i]))
      throw ConfigError((d.file.empty() ? d.name : d.file) + ": glint_table_entry(" + std::to_string(i) +
                        ") is not finite (" + std::to_string(table[i]) + "); every table entry must be a finite number");
  if (!cached && !file.empty()) {
    fs::create_directories(file.parent_path());
    write_file_atomic(file, [&](const fs::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out.write(reinterpret_cast<const char*>(table.data()), std::streamsize(table.size() * sizeof(float)));
      if (!out) throw IoError(tmp.string() + ": cannot write the glint table");
    });
  }
  auto shared = std::make_shared<const std::vector<float>>(std::move(table));
  memory_cache()[key] = shared;
  return shared;
}

}  // namespace glintlab::core
