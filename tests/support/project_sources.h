// The project's own source files, for the tests that check a list of names lives in one place only
// (a glint model's name, a resolve's options): every .cpp .h .glsl .comp .frag .vert .py under core/,
// experiments/, shaders/ and metrics/, except those under the `exempt` folders (relative to the
// repository root), with their text.
#pragma once

#include "tests/support/temp_dir.h"

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace glintlab::test {

struct SourceFile {
  std::filesystem::path path;
  std::string text;
};

inline std::vector<SourceFile> project_sources(const std::vector<std::string>& exempt) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(GLINTLAB_SHADER_DIR).parent_path();
  const std::set<std::string> exts = {".cpp", ".h", ".glsl", ".comp", ".frag", ".vert", ".py"};
  std::vector<SourceFile> files;
  for (const char* top : {"core", "experiments", "shaders", "metrics"})
    for (const auto& e : fs::recursive_directory_iterator(root / top)) {
      if (!e.is_regular_file() || !exts.count(e.path().extension().string())) continue;
      const std::string rel = fs::relative(e.path(), root).generic_string();
      bool skip = false;
      for (const auto& x : exempt) skip = skip || rel.rfind(x + "/", 0) == 0;
      if (!skip) files.push_back({e.path(), read_text(e.path())});
    }
  return files;
}

}  // namespace glintlab::test
