// glintlab's own libraries loaded on first use (core/util/plugin.h): one that cannot be loaded is an
// I/O error that says which library, what for, why, and which Debian packages to install; one that is
// not glintlab's (no table of the right version) is refused.
#include "core/util/plugin.h"

#include "core/util/io_error.h"

#include <gtest/gtest.h>

#include <string>

using namespace glintlab;

TEST(Plugin, AMissingLibrarySaysWhatToInstall) {
  try {
    load_plugin("libglintlab_no_such_plugin.so", "glintlab_no_such_api", 1, "nothing at all", "libfoo1 libbar2");
    FAIL() << "a missing library loaded";
  } catch (const IoError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cannot load libglintlab_no_such_plugin.so, glintlab's nothing at all: "), std::string::npos) << m;
    EXPECT_NE(m.find("cannot open shared object file"), std::string::npos) << m;  // dlerror()'s reason
    EXPECT_NE(m.find("apt install libfoo1 libbar2"), std::string::npos) << m;
  }
}

TEST(Plugin, ALibraryThatIsNotGlintlabsIsRefused) {
  // The C library is loaded but has no glintlab table.
  EXPECT_THROW(load_plugin("libc.so.6", "glintlab_oiio_api", 1, "a test", "libc6"), IoError);
}

TEST(Plugin, ALazyPluginLoadsOnFirstUseAndSaysAgainWhyItCannot) {
  LazyPlugin missing("libglintlab_no_such_plugin.so", "glintlab_no_such_api", 1, "nothing", "libfoo1");
  EXPECT_FALSE(missing.loaded());
  EXPECT_THROW(missing.table<int>(), IoError);
  EXPECT_THROW(missing.table<int>(), IoError);  // not a table left half made
  EXPECT_FALSE(missing.loaded());
}
