// The scene as the GPU holds it: mesh buffers and the environment map with
// its sampler. Uploaded once per run, shared by every pass and variant.
#pragma once

#include "core/scene/mesh.h"
#include "core/vk/gpu_resources.h"
#include "core/vk/handle.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace glintlab::core {

// Environment as the GPU needs it: an RGBA32F lat-long mip chain (level 0
// first, each level half the size of the previous, rounded down, at least 1).
struct EnvironmentTexture {
  uint32_t width = 0, height = 0;
  std::vector<std::vector<float>> mips_rgba;
};

class SceneGpu {
 public:
  SceneGpu(const VkContext& ctx, const Mesh& mesh, const EnvironmentTexture& env);
  // Another mesh under the environment of `same_environment` (shared, not uploaded again): the same
  // scene at another level of detail (a variant rendered below the output resolution).
  SceneGpu(const VkContext& ctx, const Mesh& mesh, const SceneGpu& same_environment);

  const Buffer& vertices() const { return vertices_; }
  const Buffer& indices() const { return indices_; }
  uint32_t index_count() const { return index_count_; }
  // The mesh's chunks (core/scene/mesh.h); a mesh without them is one chunk.
  const std::vector<MeshChunk>& chunks() const { return chunks_; }
  const Image2D& env_map() const { return env_->map; }
  VkSampler env_sampler() const { return env_->sampler.get(); }

 private:
  struct Environment {
    Image2D map;
    Sampler sampler;
  };
  void upload_mesh(const VkContext& ctx, const Mesh& mesh);
  Buffer vertices_, indices_;
  uint32_t index_count_ = 0;
  std::vector<MeshChunk> chunks_;
  std::shared_ptr<const Environment> env_;
};

}  // namespace glintlab::core
