// Shared by the Vulkan tests: a context with validation on, and a check that
// it reported nothing.
#pragma once

#include "core/vk/vk_context.h"

#include <gtest/gtest.h>

#include <memory>

namespace glintlab::test {

// One validated lavapipe context for the whole test executable: creating an
// instance with validation costs ~0.2 s, so tests share it. Every test that
// uses it checks the message count did not grow (see ValidationGuard).
inline core::VkContext& shared_context() {
  static std::unique_ptr<core::VkContext> ctx = std::make_unique<core::VkContext>(core::ContextOptions{"", true});
  return *ctx;
}

// Fails the current test if the validation layer reported anything while it lived.
class ValidationGuard {
 public:
  explicit ValidationGuard(core::VkContext& ctx) : ctx_(ctx), start_(ctx.validation_message_count()) {}
  ~ValidationGuard() {
    auto msgs = ctx_.validation_messages();
    EXPECT_EQ(msgs.size(), start_) << "validation messages were reported; first new one: "
                                   << (msgs.size() > start_ ? msgs[start_] : std::string());
  }

 private:
  core::VkContext& ctx_;
  size_t start_;
};

}  // namespace glintlab::test
