#pragma once
namespace glintlab {
// Project version, printed by `glintlab --version` and recorded in summaries.
const char* version();
}  // namespace glintlab
