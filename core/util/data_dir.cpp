#include "core/util/data_dir.h"

#include "core/util/io_error.h"

#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <system_error>

namespace fs = std::filesystem;

namespace glintlab {
namespace {

// One file of each part a data folder must hold.
constexpr const char* kRequired[] = {"shaders/passes/surface.vert", "experiments/data/regression.json",
                                     "metrics/color/ocio/config.ocio"};

// Whether `p` is `dir` or lies under it, compared as written (both absolute, without symbolic links:
// /proc/self/exe and the build folder's real path are), so nothing in `dir` is looked at.
bool is_inside(const fs::path& p, const fs::path& dir) {
  const fs::path a = p.lexically_normal(), b = dir.lexically_normal();
  auto ai = a.begin();
  for (auto bi = b.begin(); bi != b.end(); ++bi, ++ai) {
    if (bi->empty() && std::next(bi) == b.end()) break;  // a trailing separator
    if (ai == a.end() || *ai != *bi) return false;
  }
  return true;
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

}  // namespace

DataLocations locate_data(const std::string& data_env, const std::string& results_env, const std::string& executable,
                          int depth) {
  DataLocations out;
  const bool in_build_tree =
      !executable.empty() && is_inside(fs::path(executable).parent_path(), GLINTLAB_BUILD_BINARY_DIR);
  fs::path prefix = fs::path(executable);  // the installation prefix, `depth` folders above the program
  for (int i = 0; i <= depth; ++i) prefix = prefix.parent_path();
  if (!data_env.empty()) {
    out.data = data_env;
    out.why = "$GLINTLAB_DATA_DIR";
  } else if (in_build_tree) {
    out.data = GLINTLAB_BUILD_SOURCE_DIR;
    out.why = "the source tree of the build folder " GLINTLAB_BUILD_BINARY_DIR ", where this program is";
  } else if (!executable.empty()) {
    std::string up;
    for (int i = 0; i < depth; ++i) up += "../";
    out.data = (prefix / "share" / "glintlab").lexically_normal().string();
    out.why = up + "share/glintlab beside " + (depth == 1 ? "the executable " : "") + executable;
  } else {
    out.data = "share/glintlab";
    out.why = "/proc/self/exe is unreadable, so the folder beside the executable is unknown";
  }
  if (in_build_tree) {
    out.plugins = GLINTLAB_BUILD_BINARY_DIR;
  } else if (!executable.empty()) {
    out.plugins = (prefix / "lib" / "glintlab").lexically_normal().string();
  }
  if (!results_env.empty())
    out.results = results_env;
  else if (in_build_tree)
    out.results = std::string(GLINTLAB_BUILD_SOURCE_DIR) + "/results";
  else
    out.results = "results";
  return out;
}

std::string data_dir_problem(const DataLocations& where) {
  for (const char* f : kRequired) {
    std::error_code ec;
    if (fs::is_regular_file(fs::path(where.data) / f, ec)) continue;
    return "glintlab's data folder " + where.data + " (" + where.why + ") has no " + f +
           "; set GLINTLAB_DATA_DIR to the folder that holds shaders/, experiments/ and metrics/color/ocio/ "
           "(PREFIX/share/glintlab of an installed glintlab, or the source tree)";
  }
  return "";
}

namespace {
std::string& anchor_file() {
  static std::string file;
  return file;
}
int anchor_depth = 1;
}  // namespace

void set_data_anchor(const std::string& file, int depth) {
  anchor_file() = file;
  anchor_depth = depth;
}

const DataLocations& data_locations() {
  static const DataLocations locations = [] {
    if (!anchor_file().empty())
      return locate_data(env("GLINTLAB_DATA_DIR"), env("GLINTLAB_RESULTS_DIR"), anchor_file(), anchor_depth);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return locate_data(env("GLINTLAB_DATA_DIR"), env("GLINTLAB_RESULTS_DIR"), ec ? std::string() : exe.string());
  }();
  return locations;
}

std::string data_path(const std::string& relative) {
  static const std::string problem = data_dir_problem(data_locations());
  if (!problem.empty()) throw IoError(problem);
  return data_locations().data + "/" + relative;
}

std::string results_path(const std::string& relative) {
  const std::string& r = data_locations().results;
  return relative.empty() ? r : r + "/" + relative;
}

}  // namespace glintlab
