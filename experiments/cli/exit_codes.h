// Exit codes of every glintlab command (documented in the README).
//   0  success
//   1  the command ran and found a defect it exists to report: NaN/Inf/negative pixels, a Vulkan
//      validation message, a regression (`check`), an error above `--threshold` (`compare`)
//   2  bad input: a file, key, option or value that is not allowed (the message names it)
//   3  no usable Vulkan device or driver, or the device failed (VulkanError)
//   4  I/O failure: a file could not be read or written for a reason other than its content
//   5  internal error (a bug: please report it with the message)
#pragma once

#include <functional>
#include <ostream>

namespace glintlab {

enum ExitCode : int {
  kExitOk = 0,
  kExitDefect = 1,
  kExitBadInput = 2,
  kExitDevice = 3,
  kExitIo = 4,
  kExitInternal = 5,
};

// Runs a command body and maps what it throws to the codes above, printing
// "error: <what>" on `err`: ConfigError / std::invalid_argument -> 2,
// core::VulkanError and ShaderCompileError -> 3, IoError / std::filesystem_error -> 4,
// anything else -> 5.
int run_guarded(const std::function<int()>& body, std::ostream& err);

}  // namespace glintlab
