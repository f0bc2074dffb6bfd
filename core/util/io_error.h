// Errors of reading and writing files for reasons other than their content
// (permissions, a full disk, a path that is a folder): the CLI maps them to
// their own exit code, apart from bad input.
#pragma once

#include <stdexcept>

namespace glintlab {

class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace glintlab
