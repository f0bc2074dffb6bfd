#pragma once
namespace glintlab {
// Project version (CMake's project version), printed by `glintlab --version` and recorded in summaries.
const char* version();
// The commit the build was configured from (`git describe --always --dirty`), "unknown" outside a checkout.
const char* commit();
}  // namespace glintlab
