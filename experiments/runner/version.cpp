#include "experiments/runner/version.h"
namespace glintlab {
const char* version() { return GLINTLAB_VERSION; }
const char* commit() { return GLINTLAB_COMMIT; }
}  // namespace glintlab
