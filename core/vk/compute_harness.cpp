#include "core/vk/compute_harness.h"

#include "core/vk/gpu_resources.h"
#include "core/vk/pipeline.h"
#include "core/vk/shader_compiler.h"

#include <cstring>

namespace glintlab::core {

std::vector<float> run_compute(const VkContext& ctx, const std::string& shader_path, const std::vector<std::string>& defines,
                               const std::vector<float>& inputs, size_t output_floats, uint32_t count,
                               const std::vector<float>* extra) {
  CompiledShader cs = default_shader_compiler().compile(shader_path, ShaderStage::Compute, defines);
  ShaderModule module = make_shader_module(ctx, cs.spirv);
  std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
  if (extra) bindings.push_back({2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
  DescriptorSetLayout set_layout = make_set_layout(ctx, bindings);
  PipelineLayout layout = make_pipeline_layout(ctx, set_layout.get(), sizeof(uint32_t), VK_SHADER_STAGE_COMPUTE_BIT);
  Pipeline pipeline = make_compute_pipeline(ctx, layout.get(), module.get());

  const VkDeviceSize in_bytes = std::max<size_t>(inputs.size(), 1) * sizeof(float);
  const VkDeviceSize out_bytes = std::max<size_t>(output_floats, 1) * sizeof(float);
  Buffer in(ctx, in_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  Buffer out(ctx, out_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  if (!inputs.empty()) in.upload(inputs.data(), inputs.size() * sizeof(float));
  const VkDeviceSize extra_bytes = extra ? std::max<size_t>(extra->size(), 1) * sizeof(float) : 0;
  Buffer table;
  if (extra) {
    table = Buffer(ctx, extra_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!extra->empty()) table.upload(extra->data(), extra->size() * sizeof(float));
  }
  std::memset(out.mapped(), 0, out_bytes);

  DescriptorSet ds = make_descriptor_set(ctx, set_layout.get(), bindings);
  write_buffer_descriptor(ctx, ds.set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.handle(), in_bytes);
  write_buffer_descriptor(ctx, ds.set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, out.handle(), out_bytes);
  if (extra) write_buffer_descriptor(ctx, ds.set, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, table.handle(), extra_bytes);

  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.get(), 0, 1, &ds.set, 0, nullptr);
    vkCmdPushConstants(cmd, layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(uint32_t), &count);
    vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr,
                         0, nullptr);
  });
  std::vector<float> result(output_floats);
  std::memcpy(result.data(), out.mapped(), output_floats * sizeof(float));
  return result;
}

}  // namespace glintlab::core
