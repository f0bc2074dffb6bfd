// Small RAII owners of Vulkan buffers, images, and the one-time helpers that
// move data between them and the host. Nothing here knows about passes.
#pragma once

#include "core/util/no_fill_vector.h"
#include "core/vk/handle.h"
#include "core/vk/vk_context.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glintlab::core {

// A buffer in host-visible, host-coherent memory (all memory on lavapipe; on
// a discrete GPU this is the upload/readback path). Move-only; its parts are
// Handles, so nothing leaks when construction fails half-way.
class Buffer {
 public:
  Buffer() = default;
  Buffer(const VkContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage);

  VkBuffer handle() const { return buffer_.get(); }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }
  void upload(const void* data, size_t bytes, size_t offset = 0);

 private:
  BufferHandle buffer_;
  MemoryHandle memory_;  // freed after the buffer (members are destroyed in reverse order)
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;  // unmapped implicitly when the memory is freed
};

// The aspects of a format: colour, depth, or depth and stencil (views and
// barriers of a combined depth/stencil image must name both).
VkImageAspectFlags aspects_of(VkFormat format);

// A 2D optimal-tiling image in device-local memory with one view over all
// mips (none for transfer-only images).
class Image2D {
 public:
  Image2D() = default;
  Image2D(const VkContext& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
          uint32_t mip_levels = 1, VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);

  VkImage handle() const { return image_.get(); }
  VkImageView view() const { return view_.get(); }
  VkFormat format() const { return format_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  uint32_t mip_levels() const { return mips_; }
  VkImageAspectFlags aspect() const { return aspect_; }
  VkImageUsageFlags usage() const { return usage_; }

 private:
  MemoryHandle memory_;  // declared first: destroyed after the image and its view
  ImageHandle image_;
  ImageViewHandle view_;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  uint32_t width_ = 0, height_ = 0, mips_ = 1;
  VkImageAspectFlags aspect_ = VK_IMAGE_ASPECT_COLOR_BIT;
  VkImageUsageFlags usage_ = 0;
};

// Records a layout transition of all mips with a conservative full barrier.
void transition(VkCommandBuffer cmd, const Image2D& img, VkImageLayout from, VkImageLayout to,
                VkPipelineStageFlags src_stage, VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                VkAccessFlags dst_access);

// Bytes per pixel of the float formats the renderer uses (RGBA32F, RGBA16F, R32F).
uint32_t bytes_per_pixel(VkFormat format);

// Row pitch used for readback copies: rows are padded to `alignment` bytes,
// as a driver's linear layouts are; readback removes the padding.
VkDeviceSize padded_row_pitch(uint32_t width, VkFormat format, VkDeviceSize alignment = 256);

// Channels of the float formats the renderer uses.
uint32_t channel_count(VkFormat format);

// Readback inside a caller's command buffer: a host-visible buffer sized for
// `img`, the copy of mip 0 (image in TRANSFER_SRC layout) followed by a
// transfer -> host barrier, and after the submission has completed, the
// pixels as tightly packed 32-bit floats (RGBA16F is widened exactly).
Buffer make_readback_buffer(const VkContext& ctx, const Image2D& img);
void record_readback(VkCommandBuffer cmd, const Image2D& img, const Buffer& staging);
NoFillVector<float> unpack_readback(const Image2D& img, const Buffer& staging);

// Copies mip 0 of a colour image (in TRANSFER_SRC layout) to host memory as
// tightly packed 32-bit floats (RGBA16F is widened). Honours the padded row pitch.
NoFillVector<float> read_back(const VkContext& ctx, const Image2D& img, VkImageLayout current_layout);

// Uploads tightly packed RGBA32F pixels into the given mip of an RGBA32F image
// and leaves every mip in SHADER_READ_ONLY layout after the last call.
void upload_rgba32f_mips(const VkContext& ctx, Image2D& img, const std::vector<std::vector<float>>& mips);

}  // namespace glintlab::core
