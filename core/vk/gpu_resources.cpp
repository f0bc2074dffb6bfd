#include "core/vk/gpu_resources.h"

#include <cstring>
#include <utility>

namespace glintlab::core {

// ---------------------------------------------------------------- Buffer
Buffer::Buffer(const VkContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage) : size_(size) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size > 0 ? size : 4;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer b;
  vk_check(vkCreateBuffer(ctx.device(), &bi, nullptr, &b), "vkCreateBuffer");
  buffer_ = BufferHandle(ctx.device(), b);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), b, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.find_memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                                     VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  VkDeviceMemory m;
  vk_check(vkAllocateMemory(ctx.device(), &ai, nullptr, &m), "vkAllocateMemory(buffer)");
  memory_ = MemoryHandle(ctx.device(), m);
  vk_check(vkBindBufferMemory(ctx.device(), b, m, 0), "vkBindBufferMemory");
  vk_check(vkMapMemory(ctx.device(), m, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
}

void Buffer::upload(const void* data, size_t bytes, size_t offset) {
  if (offset + bytes > size_) throw VulkanError("Buffer::upload: " + std::to_string(bytes) + " bytes at offset " +
                                                std::to_string(offset) + " exceed the buffer size " +
                                                std::to_string(size_));
  std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
}

// ---------------------------------------------------------------- Image2D
VkImageAspectFlags aspects_of(VkFormat format) {
  switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_D32_SFLOAT: return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT: return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    default: return VK_IMAGE_ASPECT_COLOR_BIT;
  }
}

Image2D::Image2D(const VkContext& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                 uint32_t mip_levels, VkImageAspectFlags aspect)
    : format_(format), width_(width), height_(height), mips_(mip_levels), aspect_(aspect), usage_(usage) {
  if (width == 0 || height == 0) throw VulkanError("Image2D: zero-sized image requested");
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {width, height, 1};
  ii.mipLevels = mip_levels;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = usage;
  ii.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage img;
  vk_check(vkCreateImage(ctx.device(), &ii, nullptr, &img), "vkCreateImage");
  image_ = ImageHandle(ctx.device(), img);
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx.device(), img, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.find_memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkDeviceMemory m;
  vk_check(vkAllocateMemory(ctx.device(), &ai, nullptr, &m), "vkAllocateMemory(image)");
  memory_ = MemoryHandle(ctx.device(), m);
  vk_check(vkBindImageMemory(ctx.device(), img, m, 0), "vkBindImageMemory");
  // Transfer-only images get no view (Vulkan forbids it).
  const VkImageUsageFlags viewable = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  if ((usage & viewable) == 0) return;
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = img;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {aspect, 0, mip_levels, 0, 1};
  VkImageView v;
  vk_check(vkCreateImageView(ctx.device(), &vi, nullptr, &v), "vkCreateImageView");
  view_ = ImageViewHandle(ctx.device(), v);
}

// ---------------------------------------------------------------- helpers
void transition(VkCommandBuffer cmd, const Image2D& img, VkImageLayout from, VkImageLayout to,
                VkPipelineStageFlags src_stage, VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                VkAccessFlags dst_access) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.oldLayout = from;
  b.newLayout = to;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = img.handle();
  b.subresourceRange = {img.aspect(), 0, img.mip_levels(), 0, 1};
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

uint32_t bytes_per_pixel(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R32G32B32A32_SFLOAT: return 16;
    case VK_FORMAT_R16G16B16A16_SFLOAT: return 8;
    case VK_FORMAT_R32G32_SFLOAT: return 8;
    case VK_FORMAT_R32_SFLOAT: return 4;
    default: throw VulkanError("bytes_per_pixel: format " + std::to_string(int(format)) + " is not a renderer format");
  }
}

uint32_t channel_count(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R16G16B16A16_SFLOAT: return 4;
    case VK_FORMAT_R32G32_SFLOAT: return 2;
    case VK_FORMAT_R32_SFLOAT: return 1;
    default: throw VulkanError("channel_count: unsupported format");
  }
}

VkDeviceSize padded_row_pitch(uint32_t width, VkFormat format, VkDeviceSize alignment) {
  VkDeviceSize tight = VkDeviceSize(width) * bytes_per_pixel(format);
  return (tight + alignment - 1) / alignment * alignment;
}

// IEEE half -> float, exact for every half value (normals, subnormals, inf, NaN).
static float half_to_float(uint16_t h) {
  uint32_t sign = uint32_t(h >> 15) << 31;
  uint32_t exp = (h >> 10) & 0x1f;
  uint32_t man = h & 0x3ff;
  uint32_t bits;
  if (exp == 0) {
    if (man == 0) {
      bits = sign;
    } else {  // subnormal: renormalise
      int e = -1;
      do { ++e; man <<= 1; } while ((man & 0x400) == 0);
      bits = sign | uint32_t(127 - 15 - e) << 23 | (man & 0x3ff) << 13;
    }
  } else if (exp == 31) {
    bits = sign | 0x7f800000u | man << 13;
  } else {
    bits = sign | (exp - 15 + 127) << 23 | man << 13;
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

Buffer make_readback_buffer(const VkContext& ctx, const Image2D& img) {
  return Buffer(ctx, padded_row_pitch(img.width(), img.format()) * img.height(), VK_BUFFER_USAGE_TRANSFER_DST_BIT);
}

void record_readback(VkCommandBuffer cmd, const Image2D& img, const Buffer& staging) {
  const VkDeviceSize pitch = padded_row_pitch(img.width(), img.format());
  VkBufferImageCopy region{};
  region.bufferRowLength = uint32_t(pitch / bytes_per_pixel(img.format()));  // texels per padded row
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {img.width(), img.height(), 1};
  vkCmdCopyImageToBuffer(cmd, img.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1, &region);
  VkBufferMemoryBarrier bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
  bb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  bb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  bb.buffer = staging.handle();
  bb.size = VK_WHOLE_SIZE;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &bb, 0,
                       nullptr);
}

NoFillVector<float> unpack_readback(const Image2D& img, const Buffer& staging) {
  const uint32_t w = img.width(), h = img.height();
  const uint32_t bpp = bytes_per_pixel(img.format());
  const VkDeviceSize pitch = padded_row_pitch(w, img.format());
  const uint32_t nc = channel_count(img.format());
  const auto* base = static_cast<const unsigned char*>(staging.mapped());
  if (img.format() != VK_FORMAT_R16G16B16A16_SFLOAT && pitch == VkDeviceSize(w) * bpp) {
    // Rows without padding: one copy into the vector, not a zero-fill and then a copy.
    const auto* first = reinterpret_cast<const float*>(base);
    return NoFillVector<float>(first, first + size_t(w) * h * nc);
  }
  NoFillVector<float> out(size_t(w) * h * nc);  // every row written below
  for (uint32_t y = 0; y < h; ++y) {
    const unsigned char* row = base + pitch * y;
    float* dst = out.data() + size_t(y) * w * nc;
    if (img.format() == VK_FORMAT_R16G16B16A16_SFLOAT) {
      for (uint32_t i = 0; i < w * nc; ++i) {
        uint16_t hv;
        std::memcpy(&hv, row + 2 * i, 2);
        dst[i] = half_to_float(hv);
      }
    } else {
      std::memcpy(dst, row, size_t(w) * bpp);
    }
  }
  return out;
}

NoFillVector<float> read_back(const VkContext& ctx, const Image2D& img, VkImageLayout current_layout) {
  Buffer staging = make_readback_buffer(ctx, img);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    if (current_layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
      transition(cmd, img, current_layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                 VK_ACCESS_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    record_readback(cmd, img, staging);
    if (current_layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL && current_layout != VK_IMAGE_LAYOUT_UNDEFINED)
      transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, current_layout, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT);
  });
  return unpack_readback(img, staging);
}

void upload_rgba32f_mips(const VkContext& ctx, Image2D& img, const std::vector<std::vector<float>>& mips) {
  if (img.format() != VK_FORMAT_R32G32B32A32_SFLOAT) throw VulkanError("upload_rgba32f_mips: image is not RGBA32F");
  if (mips.size() != img.mip_levels()) throw VulkanError("upload_rgba32f_mips: mip count mismatch");
  VkDeviceSize total = 0;
  for (const auto& m : mips) total += m.size() * sizeof(float);
  Buffer staging(ctx, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  std::vector<VkBufferImageCopy> regions;
  VkDeviceSize offset = 0;
  for (uint32_t level = 0; level < mips.size(); ++level) {
    uint32_t w = std::max(1u, img.width() >> level), h = std::max(1u, img.height() >> level);
    if (mips[level].size() != size_t(w) * h * 4)
      throw VulkanError("upload_rgba32f_mips: mip " + std::to_string(level) + " has the wrong size");
    staging.upload(mips[level].data(), mips[level].size() * sizeof(float), offset);
    VkBufferImageCopy r{};
    r.bufferOffset = offset;
    r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 1};
    r.imageExtent = {w, h, 1};
    regions.push_back(r);
    offset += mips[level].size() * sizeof(float);
  }
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    transition(cmd, img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, staging.handle(), img.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           uint32_t(regions.size()), regions.data());
    transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
               VK_ACCESS_SHADER_READ_BIT);
  });
}

}  // namespace glintlab::core
