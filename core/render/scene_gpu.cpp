#include "core/render/scene_gpu.h"

#include "core/scene/mesh.h"

namespace glintlab::core {

void SceneGpu::upload_mesh(const VkContext& ctx, const Mesh& mesh) {
  if (mesh.vertices.empty() || mesh.indices.empty()) throw VulkanError("SceneGpu: the mesh is empty");
  vertices_ = Buffer(ctx, mesh.vertices.size() * sizeof(Vertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  vertices_.upload(mesh.vertices.data(), mesh.vertices.size() * sizeof(Vertex));
  indices_ = Buffer(ctx, mesh.indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  indices_.upload(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  index_count_ = uint32_t(mesh.indices.size());
  chunks_ = mesh.chunks.empty() ? std::vector<MeshChunk>{whole_mesh_chunk(mesh)} : mesh.chunks;
}

SceneGpu::SceneGpu(const VkContext& ctx, const Mesh& mesh, const SceneGpu& same_environment)
    : env_(same_environment.env_) {
  upload_mesh(ctx, mesh);
}

SceneGpu::SceneGpu(const VkContext& ctx, const Mesh& mesh, const EnvironmentTexture& env) {
  upload_mesh(ctx, mesh);
  if (env.width == 0 || env.height == 0 || env.mips_rgba.empty())
    throw VulkanError("SceneGpu: the environment texture is empty");
  auto e = std::make_shared<Environment>();
  e->map = Image2D(ctx, env.width, env.height, VK_FORMAT_R32G32B32A32_SFLOAT,
                   VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, uint32_t(env.mips_rgba.size()));
  upload_rgba32f_mips(ctx, e->map, env.mips_rgba);
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = VK_FILTER_LINEAR;
  si.minFilter = VK_FILTER_LINEAR;
  si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  si.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;         // azimuth wraps
  si.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;  // poles clamp
  si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  si.maxLod = float(env.mips_rgba.size());
  VkSampler s;
  vk_check(vkCreateSampler(ctx.device(), &si, nullptr, &s), "vkCreateSampler");
  e->sampler = Sampler(ctx.device(), s);
  env_ = std::move(e);
}

}  // namespace glintlab::core
