#include "experiments/cli/exit_codes.h"

#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/vk_context.h"

#include <filesystem>
#include <stdexcept>

static_assert(glintlab::kExitDevice == glintlab::core::kExitDeviceHang,
              "a device that does not finish exits with the device code (core/vk/vk_context.h)");

namespace glintlab {

int run_guarded(const std::function<int()>& body, std::ostream& err) {
  try {
    return body();
  } catch (const ConfigError& e) {
    err << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    err << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const core::VulkanError& e) {
    err << "error: Vulkan: " << e.what() << "\n";
    return kExitDevice;
  } catch (const core::ShaderCompileError& e) {
    err << "error: shader: " << e.what() << "\n";
    return kExitDevice;
  } catch (const IoError& e) {
    err << "error: " << e.what() << "\n";
    return kExitIo;
  } catch (const std::filesystem::filesystem_error& e) {
    err << "error: " << e.what() << "\n";
    return kExitIo;
  } catch (const std::exception& e) {
    err << "error: internal: " << e.what() << "\n";
    return kExitInternal;
  }
}

}  // namespace glintlab
