// Where a program finds its data (core/util/data_dir.h): $GLINTLAB_DATA_DIR, else the source tree for a
// program in its build folder, else ../share/glintlab beside the executable; and the default output folder.
// The installed program itself is run by tests/install/install_test.sh.
#include "core/util/data_dir.h"

#include "core/util/io_error.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using glintlab::data_dir_problem;
using glintlab::locate_data;

namespace {

// The build folder: this test program is in it.
fs::path build_dir() { return fs::read_symlink("/proc/self/exe").parent_path(); }

}  // namespace

TEST(DataDir, ABuildTreeProgramReadsTheSourceTree) {
  const auto d = locate_data("", "", (build_dir() / "glintlab").string());
  EXPECT_EQ(d.data, GLINTLAB_SOURCE_DIR);
  EXPECT_EQ(d.results, std::string(GLINTLAB_SOURCE_DIR) + "/results");
  EXPECT_NE(d.why.find("source tree"), std::string::npos) << d.why;
  EXPECT_EQ(data_dir_problem(d), "");
  // This test program is such a program.
  EXPECT_EQ(glintlab::data_locations().data, std::getenv("GLINTLAB_DATA_DIR") ? std::getenv("GLINTLAB_DATA_DIR")
                                                                                : GLINTLAB_SOURCE_DIR);
  EXPECT_EQ(glintlab::data_path("shaders"), glintlab::data_locations().data + "/shaders");
}

TEST(DataDir, AnInstalledProgramReadsShareBesideItsFolderAndWritesHere) {
  const auto d = locate_data("", "", "/opt/gl/bin/glintlab");
  EXPECT_EQ(d.data, "/opt/gl/share/glintlab");
  EXPECT_EQ(d.results, "results");
  EXPECT_NE(d.why.find("/opt/gl/bin/glintlab"), std::string::npos) << d.why;
  // A folder whose name only starts with the build folder's is not inside it.
  const auto beside = locate_data("", "", build_dir().string() + "-copy/bin/glintlab");
  EXPECT_EQ(beside.data, build_dir().string() + "-copy/share/glintlab");
  EXPECT_EQ(beside.results, "results");
}

TEST(DataDir, TheVariablesOverride) {
  const auto d = locate_data("/data/here", "/out/there", "/opt/gl/bin/glintlab");
  EXPECT_EQ(d.data, "/data/here");
  EXPECT_EQ(d.why, "$GLINTLAB_DATA_DIR");
  EXPECT_EQ(d.results, "/out/there");
  const auto b = locate_data("/data/here", "", (build_dir() / "glintlab").string());
  EXPECT_EQ(b.data, "/data/here");
  EXPECT_EQ(b.results, std::string(GLINTLAB_SOURCE_DIR) + "/results");
}

TEST(DataDir, AnIncompleteFolderIsNamedWithTheVariable) {
  glintlab::test::TempDir dir("data_dir");
  const auto d = locate_data("", "", (dir / "bin" / "glintlab").string());
  const std::string p = data_dir_problem(d);
  EXPECT_NE(p.find((dir / "share" / "glintlab").string()), std::string::npos) << p;
  EXPECT_NE(p.find("beside the executable " + (dir / "bin" / "glintlab").string()), std::string::npos) << p;
  EXPECT_NE(p.find("has no shaders/passes/surface.vert"), std::string::npos) << p;
  EXPECT_NE(p.find("set GLINTLAB_DATA_DIR"), std::string::npos) << p;

  // Each part is required: the first one missing is named.
  const fs::path share = dir / "share" / "glintlab";
  for (const char* f : {"shaders/passes/surface.vert", "experiments/data/regression.json", "metrics/color/ocio/config.ocio"}) {
    EXPECT_NE(data_dir_problem(d).find(std::string("has no ") + f), std::string::npos) << data_dir_problem(d);
    fs::create_directories((share / f).parent_path());
    std::ofstream(share / f) << "x";
  }
  EXPECT_EQ(data_dir_problem(d), "");
  const auto env = locate_data((dir / "nowhere").string(), "", "/opt/gl/bin/glintlab");
  EXPECT_NE(data_dir_problem(env).find((dir / "nowhere").string() + " ($GLINTLAB_DATA_DIR) has no"),
            std::string::npos)
      << data_dir_problem(env);
}
