// Shared GoogleTest entry point for every test executable.
#include "core/util/allocator.h"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  glintlab::tune_allocator_for_rendering();  // as the glintlab CLI does
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
