// Evaluates a compute shader on an array of inputs. The renderer computes the
// glint models' tables with it (core/material/glint_table.cpp); it is also the
// GPU half of the shader-vs-fp64 tests, `glintlab stress` and `glintlab
// glint-test`. Binding contract:
//   layout(std430, set = 0, binding = 0) readonly buffer Inputs  { float inputs[];  };
//   layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
//   layout(push_constant) uniform Push { uint count; };
// local_size_x = 64; ceil(count / 64) workgroups are dispatched. With
// `extra`, a third storage buffer (binding 2) holds its floats: the data
// table of a glint model (core/material/glint_table.h).
#pragma once

#include "core/vk/vk_context.h"

#include <string>
#include <vector>

namespace glintlab::core {

std::vector<float> run_compute(const VkContext& ctx, const std::string& shader_path, const std::vector<std::string>& defines,
                               const std::vector<float>& inputs, size_t output_floats, uint32_t count,
                               const std::vector<float>* extra = nullptr);

}  // namespace glintlab::core
