#include "experiments/runner/version.h"
namespace glintlab {
const char* version() { return "0.1.0"; }
}  // namespace glintlab
