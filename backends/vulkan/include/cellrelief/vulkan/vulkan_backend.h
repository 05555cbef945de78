// SPDX-License-Identifier: MIT
/// @file vulkan_backend.h
/// The Vulkan 1.3 backend: the scene in the GPU layout the OpenGL backend uploads
/// (gpu/gpu_layout.h: cell table and hash lookup in storage buffers, maps in integer array-image
/// atlases) and the same GLSL traversal (backends/shaders/relief_trace.comp), compiled to SPIR-V
/// at build time. A scene pays only for what it uses: its variant (gpu/shader_preamble.h) is a
/// set of specialization constants, so the driver removes what the scene lacks when it builds
/// the pipeline; pipelines are cached per variant.
///
/// As in OpenGL, the traversal reaches the pixels the paper's way, the grey cells and chart boxes
/// drawn into a stencil and the traversal run as a fragment pass on the covered pixels only
/// (RayEntry::Rasterized, with dynamic rendering), or as a compute pass over every pixel, which is
/// also what runs when the eye is inside the scene's bounds or the device cannot draw. The default
/// (RayEntry::Fastest) takes the fragment pass on lavapipe and on a GPU whichever its timestamps
/// find faster.
///
/// Uploads go through a staging buffer into device-local memory; the frame is written to a
/// storage buffer read back through host-visible memory (where the device's memory is the host's
/// and cached, as on lavapipe and integrated GPUs, the shader writes it there directly); a
/// timestamp query pair gives the GPU time of each frame. Every Vulkan error is an Error naming
/// the call, a lost device (VK_ERROR_DEVICE_LOST) included; after one, the backend refuses work.
#pragma once

#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellrelief/gpu/gpu_frame.h"
#include "cellrelief/gpu/gpu_layout.h"
#include "cellrelief/gpu/shader_preamble.h"
#include "cellrelief/render/backend.h"
#include "cellrelief/vulkan/spirv_modules.h"
#include "cellrelief/vulkan/vulkan_context.h"

namespace cellrelief::vulkan {

using gpu::RayEntry;

class VulkanBackend final : public render::Backend, public gpu::TraversalControls {
 public:
  explicit VulkanBackend(const ContextOptions& options = {}) : mContext(std::make_unique<VulkanContext>(options)) {
    try {
      queryLimits();
      createFixedObjects();
    } catch (...) {
      destroyAll();
      throw;
    }
  }
  VulkanBackend(const VulkanBackend&) = delete;
  VulkanBackend& operator=(const VulkanBackend&) = delete;
  ~VulkanBackend() override { destroyAll(); }

  render::BackendKind kind() const override { return render::BackendKind::Vulkan; }
  std::string description() const override { return "Vulkan: " + mContext->description(); }
  const VulkanContext& context() const { return *mContext; }
  const gpu::DeviceLimits& limits() const { return mLimits; }

  void upload(const render::Scene& scene) override {
    checkAlive();
    waitForFrame();
    releaseScene();
    forgetEntryTimes();  // another scene: the entries' times were its own
    gpu::checkSceneSupported(scene, "the Vulkan backend");
    mScene = scene;
    mGpu = gpu::packScene(scene, mLimits, true);
    guard([&] { uploadScene(); });
    mGpuBytes = mGpu.bytes();
    mGpu.dropTexels();
    mUploaded = true;
  }

  void render(const render::Camera& camera, const render::RenderOptions& options) override {
    checkAlive();
    if (!mUploaded) throw Error(ErrorKind::InvalidArgument, "Vulkan backend: render() before upload()");
    if (options.width < 1 || options.height < 1) throw Error(ErrorKind::InvalidArgument, "Vulkan backend: empty frame size");
    waitForFrame();
    mRendered = false;  // a render that fails leaves nothing to read back
    checkFrameSize(options);
    const gpu::ShaderVariant variant = variantFor(options);
    // A frame larger than a framebuffer renders by compute, the same frame.
    const bool rasterized = takeRasterized(
        variant, options, mContext->canRasterize() && drawFits(options) && gpu::rasterizedEntryServes(mScene, camera),
        !mContext->isSoftware() && mContext->timestampBits() > 0);
    guard([&] {
      const VkPipeline pipeline = pipelineFor(variant, rasterized);
      const gpu::FrameLayout layout = gpu::frameLayout(options, variant.channels, mLimits.maxStorageBytes);
      ensureFrameBuffer(layout.words);
      if (rasterized) ensureStencil(options.width, options.height);
      const gpu::FrameParams params = gpu::frameParams(mScene, camera, options, layout);
      std::memcpy(mParams.mapped, &params, sizeof params);
      mContext->flush(mParams);
      recordFrame(camera, options, layout, pipeline, rasterized);
      submitFrame();
      mLayout = layout;
    });
    mLastEntry = rasterized ? RayEntry::Rasterized : RayEntry::Compute;
    mRendered = true;
  }

  void readBack(render::Frame& frame) override {
    checkAlive();
    if (!mRendered) throw Error(ErrorKind::InvalidArgument, "Vulkan backend: readBack() before render()");
    guard([&] {
      waitForFrame();
      const Buffer& source = mReadback ? mReadback : mFrame;
      mContext->invalidate(source);
      gpu::unpackFrame(static_cast<const std::uint32_t*>(source.mapped), mLayout, frame);
      mGpuSeconds = frameSeconds();
      entryTimed(mLastEntry == RayEntry::Rasterized, mGpuSeconds);
    });
  }

  std::size_t sceneBytes() const override { return mUploaded ? mGpuBytes : 0; }
  /// GPU time of the last frame (a timestamp pair around its commands), known after readBack().
  double deviceSeconds() const override { return mGpuSeconds; }

  /// The variant the next render with these options uses.
  gpu::ShaderVariant variantFor(const render::RenderOptions& options) const { return variantOf(mGpu.features, options); }
  /// Seconds spent building pipelines (the driver compiling the variants) so far.
  double compileSeconds() const { return mCompileSeconds; }
  /// Pipelines built so far (one per variant and entry).
  std::size_t pipelineCount() const { return mPipelines.size(); }

 private:
  // ---- setup ------------------------------------------------------------------------------------

  void queryLimits() {
    const VkPhysicalDeviceLimits& l = mContext->limits();
    mLimits.maxTextureSize = int(std::min<std::uint32_t>(l.maxImageDimension2D, 1u << 30));
    mLimits.maxArrayLayers = int(std::min<std::uint32_t>(l.maxImageArrayLayers, 1u << 30));
    // The shader indexes buffers with 32-bit ints: no buffer beyond 2^31 bytes, whatever the device.
    mLimits.maxStorageBytes = std::min<std::size_t>(l.maxStorageBufferRange, std::size_t(1) << 31);
    mLimits.maxTotalBytes = mContext->deviceMemoryBytes();
  }

  void createFixedObjects() {
    const Api& vk = mContext->api();
    const VkDevice device = mContext->device();
    // One set: 0 the frame's uniforms, 1-4 the scene's tables, 5 the frame, 6-9 the map atlases,
    // 10 the polycube meshes' words, 11 their T2, 12 the geometry textures' words, 13 the relief
    // surfaces' words.
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    const VkShaderStageFlags stages = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    bindings.push_back({0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, stages, nullptr});
    for (std::uint32_t b = 1; b <= 5; ++b) bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr});
    for (std::uint32_t b = 6; b <= 9; ++b)
      bindings.push_back({b, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, stages, nullptr});
    bindings.push_back({10, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr});
    bindings.push_back({11, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, stages, nullptr});
    bindings.push_back({12, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr});
    bindings.push_back({13, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr});
    auto setInfo = make<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    setInfo.bindingCount = std::uint32_t(bindings.size());
    setInfo.pBindings = bindings.data();
    check(vk.vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &mSetLayout), "vkCreateDescriptorSetLayout");
    const VkPushConstantRange cover{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(gpu::CoverParams)};
    auto layoutInfo = make<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &mSetLayout;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &cover;
    check(vk.vkCreatePipelineLayout(device, &layoutInfo, nullptr, &mPipelineLayout), "vkCreatePipelineLayout");
    const VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                           {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 8},
                                           {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 5}};
    auto poolInfo = make<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 3;
    poolInfo.pPoolSizes = sizes;
    check(vk.vkCreateDescriptorPool(device, &poolInfo, nullptr, &mDescriptorPool), "vkCreateDescriptorPool");
    auto alloc = make<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
    alloc.descriptorPool = mDescriptorPool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &mSetLayout;
    check(vk.vkAllocateDescriptorSets(device, &alloc, &mSet), "vkAllocateDescriptorSets");
    // Integer textures are read texel by texel (nearest, clamped), as in OpenGL: the shader
    // filters the 2 x 2 samples itself because it must see each corner's empty code.
    auto sampler = make<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
    sampler.magFilter = VK_FILTER_NEAREST;
    sampler.minFilter = VK_FILTER_NEAREST;
    sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sampler.maxLod = 0.0f;
    check(vk.vkCreateSampler(device, &sampler, nullptr, &mSampler), "vkCreateSampler");
    // T2 of polycube meshes is UNORM and filtered by the hardware: its tiles' borders make bilinear
    // reads seamless (polycube_texture.h); the levels are stacked in it, not a mip chain.
    sampler.magFilter = VK_FILTER_LINEAR;
    sampler.minFilter = VK_FILTER_LINEAR;
    check(vk.vkCreateSampler(device, &sampler, nullptr, &mLinearSampler), "vkCreateSampler");
    mComputeModule = shaderModule(kReliefTraceCompSpv, sizeof kReliefTraceCompSpv);
    if (mContext->canRasterize()) {
      mFragmentModule = shaderModule(kReliefTraceFragSpv, sizeof kReliefTraceFragSpv);
      mCoverModule = shaderModule(kCellCoverVertSpv, sizeof kCellCoverVertSpv);
      mFullScreenModule = shaderModule(kFullScreenVertSpv, sizeof kFullScreenVertSpv);
    }
    mParams = mContext->createBuffer(sizeof(gpu::FrameParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, Memory::Upload);
    auto cmd = make<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cmd.commandPool = mContext->commandPool();
    cmd.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cmd.commandBufferCount = 1;
    check(vk.vkAllocateCommandBuffers(device, &cmd, &mCommands), "vkAllocateCommandBuffers");
    auto fence = make<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    check(vk.vkCreateFence(device, &fence, nullptr, &mFence), "vkCreateFence");
    if (mContext->timestampBits() > 0) {
      auto query = make<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
      query.queryType = VK_QUERY_TYPE_TIMESTAMP;
      query.queryCount = 2;
      check(vk.vkCreateQueryPool(device, &query, nullptr, &mTimestamps), "vkCreateQueryPool");
    }
    // Placeholders for the maps a scene lacks, so every binding is complete.
    mPlaceholder = mContext->createImage(VK_FORMAT_R8G8B8A8_UINT, 1, 1, 1,
                                         VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    const std::uint32_t zero = 0;
    uploadImages({{&mPlaceholder, &zero, sizeof zero}});
  }

  VkShaderModule shaderModule(const std::uint32_t* words, std::size_t bytes) const {
    auto info = make<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    info.codeSize = bytes;
    info.pCode = words;
    VkShaderModule module = VK_NULL_HANDLE;
    check(mContext->api().vkCreateShaderModule(mContext->device(), &info, nullptr, &module), "vkCreateShaderModule");
    return module;
  }

  // ---- the scene ----------------------------------------------------------------------------------

  struct ImageUpload {
    Image* image;
    const void* texels;
    std::size_t bytes;
  };

  void uploadScene() {
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    struct BufferUpload {
      const void* data;
      std::size_t bytes;
    };
    const BufferUpload buffers[kBufferCount] = {
        {mGpu.models.data(), mGpu.models.size() * sizeof(gpu::ModelInfo)},
        {mGpu.cells.data(), mGpu.cells.size() * sizeof(gpu::GpuCell)},
        {mGpu.hashSlots.data(), mGpu.hashSlots.size() * sizeof(std::uint32_t)},
        {mGpu.pyramid.data(), mGpu.pyramid.size() * sizeof(std::uint16_t)},
        {mGpu.polycube.words.data(), mGpu.polycube.words.size() * sizeof(std::uint32_t)},
        {mGpu.geotex.words.data(), mGpu.geotex.words.size() * sizeof(std::uint32_t)},
        {mGpu.parallax.words.data(), mGpu.parallax.words.size() * sizeof(std::uint32_t)}};
    std::size_t offsets[kBufferCount], total = 0;
    for (int i = 0; i < kBufferCount; ++i) {
      offsets[i] = total;
      total += align(buffers[i].bytes);
      mBuffers[i] = mContext->createBuffer(buffers[i].bytes, storage, Memory::DeviceLocal);
    }
    mContext->uploadThroughStaging(
        total,
        [&](char* staging) {
          for (int i = 0; i < kBufferCount; ++i)
            if (buffers[i].bytes) std::memcpy(staging + offsets[i], buffers[i].data, buffers[i].bytes);
        },
        [&](VkCommandBuffer cmd, VkBuffer staging) {
          for (int i = 0; i < kBufferCount; ++i) {
            if (buffers[i].bytes == 0) continue;
            const VkBufferCopy region{offsets[i], 0, buffers[i].bytes};
            mContext->api().vkCmdCopyBuffer(cmd, staging, mBuffers[i].buffer, 1, &region);
          }
          barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kShaderStages,
                  VK_ACCESS_SHADER_READ_BIT);
        });
    std::vector<ImageUpload> images;
    auto atlas = [&](Image& image, const auto& a, VkFormat format) {
      if (a.empty()) return;
      image = mContext->createImage(format, a.width, a.height, a.layers,
                                    VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
      images.push_back({&image, a.texels.data(), a.bytes()});
    };
    atlas(mAtlases[0], mGpu.distances, VK_FORMAT_R16_UINT);
    atlas(mAtlases[1], mGpu.normalsOct, VK_FORMAT_R16G16_UINT);
    atlas(mAtlases[2], mGpu.normalsRgba, VK_FORMAT_R8G8B8A8_UINT);
    atlas(mAtlases[3], mGpu.colors, VK_FORMAT_R8G8B8A8_UINT);
    const gpu::PolycubeGpu& polycube = mGpu.polycube;
    mAtlases[4] = mContext->createImage(VK_FORMAT_R8G8B8A8_UNORM, polycube.width, polycube.height, 1,
                                        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    images.push_back({&mAtlases[4], polycube.t2.data(), polycube.t2.size()});
    uploadImages(images);
    writeSceneDescriptors();
  }

  static std::size_t align(std::size_t bytes) { return (bytes + 15) / 16 * 16; }

  static constexpr VkPipelineStageFlags kShaderStages =
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;

  /// Copies texels into the images through one staging buffer and leaves them shader-readable.
  void uploadImages(const std::vector<ImageUpload>& images) {
    if (images.empty()) return;
    std::vector<std::size_t> offsets;
    std::size_t total = 0;
    for (const ImageUpload& u : images) offsets.push_back(total), total += align(u.bytes);
    const Api& vk = mContext->api();
    mContext->uploadThroughStaging(
        total,
        [&](char* staging) {
          for (std::size_t i = 0; i < images.size(); ++i) std::memcpy(staging + offsets[i], images[i].texels, images[i].bytes);
        },
        [&](VkCommandBuffer cmd, VkBuffer staging) {
          for (std::size_t i = 0; i < images.size(); ++i) {
            const Image& im = *images[i].image;
            transition(cmd, im.image, VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(im.layers), VK_IMAGE_LAYOUT_UNDEFINED,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
            VkBufferImageCopy region{};
            region.bufferOffset = offsets[i];
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, std::uint32_t(im.layers)};
            region.imageExtent = {std::uint32_t(im.width), std::uint32_t(im.height), 1};
            vk.vkCmdCopyBufferToImage(cmd, staging, im.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
            transition(cmd, im.image, VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(im.layers),
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kShaderStages,
                       VK_ACCESS_SHADER_READ_BIT);
          }
        });
  }

  void transition(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, std::uint32_t layers,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                  VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) const {
    auto b = make<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, layers};
    mContext->api().vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
  }

  void barrier(VkCommandBuffer cmd, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
               VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) const {
    auto b = make<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    mContext->api().vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 1, &b, 0, nullptr, 0, nullptr);
  }

  void writeSceneDescriptors() {
    VkDescriptorBufferInfo uniforms{mParams.buffer, 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo tables[kBufferCount];
    for (int i = 0; i < kBufferCount; ++i) tables[i] = {mBuffers[i].buffer, 0, VK_WHOLE_SIZE};
    VkDescriptorImageInfo maps[5];
    for (int i = 0; i < 4; ++i)
      maps[i] = {mSampler, mAtlases[i] ? mAtlases[i].view : mPlaceholder.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    maps[4] = {mLinearSampler, mAtlases[4].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    std::vector<VkWriteDescriptorSet> writes;
    auto write = [&](std::uint32_t binding, VkDescriptorType type, const VkDescriptorBufferInfo* buffer,
                     const VkDescriptorImageInfo* image) {
      auto w = make<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      w.dstSet = mSet;
      w.dstBinding = binding;
      w.descriptorCount = 1;
      w.descriptorType = type;
      w.pBufferInfo = buffer;
      w.pImageInfo = image;
      writes.push_back(w);
    };
    write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &uniforms, nullptr);
    for (std::uint32_t i = 0; i < 4; ++i) write(1 + i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tables[i], nullptr);
    for (std::uint32_t i = 0; i < 4; ++i) write(6 + i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, nullptr, &maps[i]);
    write(10, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tables[4], nullptr);
    write(11, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, nullptr, &maps[4]);
    write(12, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tables[5], nullptr);
    write(13, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &tables[6], nullptr);
    mContext->api().vkUpdateDescriptorSets(mContext->device(), std::uint32_t(writes.size()), writes.data(), 0, nullptr);
  }

  void releaseScene() {
    for (Buffer& b : mBuffers) mContext->destroy(b);
    for (Image& im : mAtlases) mContext->destroy(im);
    mUploaded = false;
    mRendered = false;
    mGpuBytes = 0;
  }

  // ---- pipelines --------------------------------------------------------------------------------

  /// The pipeline of a variant: the traversal's compute pipeline, or (rasterized) its fragment
  /// pipeline behind the stencil test.
  VkPipeline pipelineFor(const gpu::ShaderVariant& variant, bool rasterized) {
    const auto switches = gpu::variantSwitches(variant);
    std::string key = rasterized ? "fragment:" : "compute:";
    for (bool on : switches) key += on ? '1' : '0';
    if (auto it = mPipelines.find(key); it != mPipelines.end()) return it->second;
    const auto t0 = std::chrono::steady_clock::now();
    VkBool32 values[gpu::kVariantSwitchCount];
    VkSpecializationMapEntry entries[gpu::kVariantSwitchCount];
    for (int i = 0; i < gpu::kVariantSwitchCount; ++i) {
      values[i] = switches[std::size_t(i)] ? VK_TRUE : VK_FALSE;
      entries[i] = {std::uint32_t(i), std::uint32_t(i * sizeof(VkBool32)), sizeof(VkBool32)};
    }
    VkSpecializationInfo specialization{};
    specialization.mapEntryCount = gpu::kVariantSwitchCount;
    specialization.pMapEntries = entries;
    specialization.dataSize = sizeof values;
    specialization.pData = values;
    const VkPipeline pipeline = rasterized ? graphicsPipeline(mFullScreenModule, mFragmentModule, &specialization, false)
                                           : computePipeline(specialization);
    mCompileSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    mPipelines[key] = pipeline;
    return pipeline;
  }

  VkPipeline computePipeline(const VkSpecializationInfo& specialization) const {
    auto info = make<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    info.stage = make<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = mComputeModule;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = &specialization;
    info.layout = mPipelineLayout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    check(mContext->api().vkCreateComputePipelines(mContext->device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
          "vkCreateComputePipelines (the traversal)");
    return pipeline;
  }

  /// The cover (vertex shader only: writes 1 into the stencil) or the traversal's fragment pass
  /// (draws where the stencil holds 1). No color attachment: the frame is a storage buffer.
  VkPipeline graphicsPipeline(VkShaderModule vertex, VkShaderModule fragment, const VkSpecializationInfo* specialization,
                              bool cover) const {
    VkPipelineShaderStageCreateInfo stages[2] = {make<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO),
                                                 make<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO)};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vertex;
    stages[0].pName = "main";
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = fragment;
    stages[1].pName = "main";
    stages[1].pSpecializationInfo = specialization;
    auto vertexInput = make<VkPipelineVertexInputStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
    auto assembly = make<VkPipelineInputAssemblyStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    auto viewport = make<VkPipelineViewportStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    auto raster = make<VkPipelineRasterizationStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    auto multisample = make<VkPipelineMultisampleStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    auto depthStencil = make<VkPipelineDepthStencilStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
    depthStencil.stencilTestEnable = VK_TRUE;
    VkStencilOpState stencil{};
    stencil.compareMask = 0xff;
    stencil.reference = 1;
    if (cover) {
      stencil.compareOp = VK_COMPARE_OP_ALWAYS;
      stencil.passOp = VK_STENCIL_OP_REPLACE;
      stencil.writeMask = 0xff;
    } else {
      stencil.compareOp = VK_COMPARE_OP_EQUAL;
      stencil.passOp = VK_STENCIL_OP_KEEP;
      stencil.writeMask = 0;
    }
    stencil.failOp = stencil.depthFailOp = VK_STENCIL_OP_KEEP;
    depthStencil.front = depthStencil.back = stencil;
    auto blend = make<VkPipelineColorBlendStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
    const VkDynamicState dynamic[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    auto dynamicState = make<VkPipelineDynamicStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
    dynamicState.dynamicStateCount = 2;
    dynamicState.pDynamicStates = dynamic;
    auto rendering = make<VkPipelineRenderingCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO);
    rendering.stencilAttachmentFormat = mContext->stencilFormat();
    auto info = make<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
    info.pNext = &rendering;
    info.stageCount = fragment ? 2 : 1;
    info.pStages = stages;
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depthStencil;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamicState;
    info.layout = mPipelineLayout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    check(mContext->api().vkCreateGraphicsPipelines(mContext->device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
          cover ? "vkCreateGraphicsPipelines (the cell cover)" : "vkCreateGraphicsPipelines (the traversal)");
    return pipeline;
  }

  // ---- a frame ------------------------------------------------------------------------------------

  /// A frame the device cannot dispatch in one piece is refused by its size.
  void checkFrameSize(const render::RenderOptions& o) const {
    const VkPhysicalDeviceLimits& l = mContext->limits();
    if (std::uint32_t((o.width + gpu::kGroupWidth - 1) / gpu::kGroupWidth) > l.maxComputeWorkGroupCount[0] ||
        std::uint32_t((o.height + gpu::kGroupHeight - 1) / gpu::kGroupHeight) > l.maxComputeWorkGroupCount[1])
      throw Error(ErrorKind::ResourceLimit, "Vulkan backend: a " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                                                " frame is beyond what " + mContext->name() + " renders in one pass");
  }

  /// Whether the stencil of the rasterized entry can be as large as the frame.
  bool drawFits(const render::RenderOptions& o) const {
    const VkPhysicalDeviceLimits& l = mContext->limits();
    return std::uint32_t(o.width) <= std::min(l.maxFramebufferWidth, l.maxImageDimension2D) &&
           std::uint32_t(o.height) <= std::min(l.maxFramebufferHeight, l.maxImageDimension2D);
  }

  /// The frame's storage buffer, grown when a frame needs more; on unified memory the host
  /// reads it where the shader wrote it, else through a host-visible copy.
  void ensureFrameBuffer(std::size_t words) {
    if (mFrame && mFrame.size >= words * 4) return;
    mContext->destroy(mFrame);
    mContext->destroy(mReadback);
    const VkDeviceSize bytes = words * 4;
    const VkBufferUsageFlags usage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    if (mContext->hasSharedMemory()) {
      mFrame = mContext->createBuffer(bytes, usage, Memory::Shared);
    } else {
      mFrame = mContext->createBuffer(bytes, usage, Memory::DeviceLocal);
      mReadback = mContext->createBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Memory::Readback);
    }
    VkDescriptorBufferInfo frame{mFrame.buffer, 0, VK_WHOLE_SIZE};
    auto w = make<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = mSet;
    w.dstBinding = 5;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = &frame;
    mContext->api().vkUpdateDescriptorSets(mContext->device(), 1, &w, 0, nullptr);
  }

  void ensureStencil(int width, int height) {
    if (!mCoverPipeline) mCoverPipeline = graphicsPipeline(mCoverModule, VK_NULL_HANDLE, nullptr, true);
    if (mStencil && mStencil.width == width && mStencil.height == height) return;
    mContext->destroy(mStencil);
    mStencil = mContext->createImage(mContext->stencilFormat(), width, height, 1,
                                     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, stencilAspect());
  }

  VkImageAspectFlags stencilAspect() const {
    return mContext->stencilFormat() == VK_FORMAT_S8_UINT ? VK_IMAGE_ASPECT_STENCIL_BIT
                                                          : VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
  }

  void recordFrame(const render::Camera& camera, const render::RenderOptions& o, const gpu::FrameLayout& layout,
                   VkPipeline pipeline, bool rasterized) {
    const Api& vk = mContext->api();
    const VkCommandBuffer cmd = mCommands;
    check(vk.vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    auto begin = make<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vk.vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    if (mTimestamps) {
      vk.vkCmdResetQueryPool(cmd, mTimestamps, 0, 2);
      vk.vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, mTimestamps, 0);
    }
    // No barrier against the previous frame: its fence was waited for before this one is recorded.
    VkPipelineStageFlags writer = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    if (rasterized) {
      recordRasterized(cmd, camera, o, layout, pipeline);
      writer = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    } else {
      vk.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
      vk.vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, mPipelineLayout, 0, 1, &mSet, 0, nullptr);
      vk.vkCmdDispatch(cmd, std::uint32_t((o.width + gpu::kGroupWidth - 1) / gpu::kGroupWidth),
                       std::uint32_t((o.height + gpu::kGroupHeight - 1) / gpu::kGroupHeight), 1);
    }
    if (mTimestamps) vk.vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, mTimestamps, 1);
    if (mReadback) {
      barrier(cmd, writer, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
      const VkBufferCopy region{0, 0, layout.words * 4};
      vk.vkCmdCopyBuffer(cmd, mFrame.buffer, mReadback.buffer, 1, &region);
      barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
              VK_ACCESS_HOST_READ_BIT);
    } else {
      barrier(cmd, writer | VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
              VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    }
    check(vk.vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  }

  /// The paper's way: the frame cleared to the miss values, the grey cells and chart boxes into
  /// the stencil, then the traversal on the covered pixels.
  void recordRasterized(VkCommandBuffer cmd, const render::Camera& camera, const render::RenderOptions& o,
                        const gpu::FrameLayout& layout, VkPipeline traversal) {
    const Api& vk = mContext->api();
    for (const gpu::WordFill& f : gpu::missFills(layout, mScene))
      vk.vkCmdFillBuffer(cmd, mFrame.buffer, f.offset * 4, f.words * 4, f.value);
    barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
            VK_ACCESS_SHADER_WRITE_BIT);
    transition(cmd, mStencil.image, stencilAspect(), 1, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
               VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
               VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    auto stencil = make<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    stencil.imageView = mStencil.view;
    stencil.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    stencil.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    stencil.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    stencil.clearValue.depthStencil = {1.0f, 0};
    auto rendering = make<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
    rendering.renderArea = {{0, 0}, {std::uint32_t(o.width), std::uint32_t(o.height)}};
    rendering.layerCount = 1;
    rendering.pStencilAttachment = &stencil;
    vk.vkCmdBeginRendering(cmd, &rendering);
    const VkViewport viewport{0.0f, 0.0f, float(o.width), float(o.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {std::uint32_t(o.width), std::uint32_t(o.height)}};
    vk.vkCmdSetViewport(cmd, 0, 1, &viewport);
    vk.vkCmdSetScissor(cmd, 0, 1, &scissor);
    vk.vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, mPipelineLayout, 0, 1, &mSet, 0, nullptr);
    vk.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, mCoverPipeline);
    const auto drawCover = [&](const gpu::CoverParams& cover, std::size_t instances) {
      if (instances == 0) return;
      vk.vkCmdPushConstants(cmd, mPipelineLayout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof cover, &cover);
      vk.vkCmdDraw(cmd, 36, std::uint32_t(instances), 0, 0);
    };
    for (std::size_t m = 0; m < mScene.models.size(); ++m)
      drawCover(gpu::coverParams(mScene, mGpu, camera, o, m, mCoverDilation, gpu::ClipSpace::Vulkan),
                mScene.models[m]->cells.size());
    for (std::size_t m = 0; m < mScene.geotexModels.size(); ++m)
      drawCover(gpu::chartCoverParams(mScene, camera, o, m, mCoverDilation, gpu::ClipSpace::Vulkan),
                mScene.geotexModels[m]->charts.size());
    vk.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, traversal);
    vk.vkCmdDraw(cmd, 3, 1, 0, 0);
    vk.vkCmdEndRendering(cmd);
  }

  void submitFrame() {
    const Api& vk = mContext->api();
    check(vk.vkResetFences(mContext->device(), 1, &mFence), "vkResetFences");
    auto submit = make<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &mCommands;
    check(vk.vkQueueSubmit(mContext->queue(), 1, &submit, mFence), "vkQueueSubmit");
    mInFlight = true;
  }

  /// Waits for the frame in flight, if any (a failure, a lost device included, is an Error).
  void waitForFrame() {
    if (!mInFlight) return;
    mInFlight = false;
    check(mContext->api().vkWaitForFences(mContext->device(), 1, &mFence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  }

  /// The last frame's GPU time from its timestamp pair (0 without timestamps).
  double frameSeconds() const {
    if (!mTimestamps) return 0;
    std::uint64_t ticks[2] = {0, 0};
    check(mContext->api().vkGetQueryPoolResults(mContext->device(), mTimestamps, 0, 2, sizeof ticks, ticks,
                                                sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const std::uint32_t bits = mContext->timestampBits();
    const std::uint64_t mask = bits >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << bits) - 1;
    const std::uint64_t elapsed = (ticks[1] - ticks[0]) & mask;
    return double(elapsed) * mContext->timestampPeriod() * 1e-9;
  }

  // ---- failure and teardown -------------------------------------------------------------------

  /// Runs Vulkan work; a lost device marks the backend lost before the Error goes on.
  template <class F>
  void guard(F&& work) {
    try {
      work();
    } catch (const VulkanError& e) {
      mLost = mLost || e.result() == VK_ERROR_DEVICE_LOST;
      throw;
    }
  }
  void checkAlive() const {
    if (mLost)
      throw Error(ErrorKind::Unsupported, "Vulkan backend: the device " + mContext->name() +
                                              " was lost (VK_ERROR_DEVICE_LOST); create a new backend");
  }

  void destroyAll() {
    if (!mContext) return;
    const Api& vk = mContext->api();
    const VkDevice device = mContext->device();
    if (!device) return;
    vk.vkDeviceWaitIdle(device);
    releaseScene();
    mContext->destroy(mFrame);
    mContext->destroy(mReadback);
    mContext->destroy(mParams);
    mContext->destroy(mStencil);
    mContext->destroy(mPlaceholder);
    for (auto& [key, pipeline] : mPipelines) vk.vkDestroyPipeline(device, pipeline, nullptr);
    mPipelines.clear();
    if (mCoverPipeline) vk.vkDestroyPipeline(device, mCoverPipeline, nullptr);
    for (VkShaderModule m : {mComputeModule, mFragmentModule, mCoverModule, mFullScreenModule})
      if (m) vk.vkDestroyShaderModule(device, m, nullptr);
    if (mTimestamps) vk.vkDestroyQueryPool(device, mTimestamps, nullptr);
    if (mFence) vk.vkDestroyFence(device, mFence, nullptr);
    if (mCommands) vk.vkFreeCommandBuffers(device, mContext->commandPool(), 1, &mCommands);
    if (mSampler) vk.vkDestroySampler(device, mSampler, nullptr);
    if (mLinearSampler) vk.vkDestroySampler(device, mLinearSampler, nullptr);
    if (mDescriptorPool) vk.vkDestroyDescriptorPool(device, mDescriptorPool, nullptr);  // frees the set
    if (mPipelineLayout) vk.vkDestroyPipelineLayout(device, mPipelineLayout, nullptr);
    if (mSetLayout) vk.vkDestroyDescriptorSetLayout(device, mSetLayout, nullptr);
    mCoverPipeline = VK_NULL_HANDLE;
    mComputeModule = mFragmentModule = mCoverModule = mFullScreenModule = VK_NULL_HANDLE;
    mTimestamps = VK_NULL_HANDLE, mFence = VK_NULL_HANDLE, mCommands = VK_NULL_HANDLE, mSampler = VK_NULL_HANDLE;
    mLinearSampler = VK_NULL_HANDLE;
    mDescriptorPool = VK_NULL_HANDLE, mPipelineLayout = VK_NULL_HANDLE, mSetLayout = VK_NULL_HANDLE;
  }

  std::unique_ptr<VulkanContext> mContext;
  gpu::DeviceLimits mLimits;
  render::Scene mScene;
  gpu::GpuScene mGpu;
  std::size_t mGpuBytes = 0;
  static constexpr int kBufferCount = 7;
  Buffer mBuffers[kBufferCount];  ///< models, cells, hash, pyramid, polycube meshes, geometry textures, relief surfaces
  Image mAtlases[5];   ///< distances, octahedral normals, RGBA normals, colors, polycube T2
  Image mPlaceholder, mStencil;
  Buffer mFrame, mReadback, mParams;
  VkDescriptorSetLayout mSetLayout = VK_NULL_HANDLE;
  VkPipelineLayout mPipelineLayout = VK_NULL_HANDLE;
  VkDescriptorPool mDescriptorPool = VK_NULL_HANDLE;
  VkDescriptorSet mSet = VK_NULL_HANDLE;
  VkSampler mSampler = VK_NULL_HANDLE;
  VkSampler mLinearSampler = VK_NULL_HANDLE;  ///< polycube T2
  VkShaderModule mComputeModule = VK_NULL_HANDLE, mFragmentModule = VK_NULL_HANDLE;
  VkShaderModule mCoverModule = VK_NULL_HANDLE, mFullScreenModule = VK_NULL_HANDLE;
  VkPipeline mCoverPipeline = VK_NULL_HANDLE;
  std::map<std::string, VkPipeline> mPipelines;
  VkCommandBuffer mCommands = VK_NULL_HANDLE;
  VkFence mFence = VK_NULL_HANDLE;
  VkQueryPool mTimestamps = VK_NULL_HANDLE;
  gpu::FrameLayout mLayout;
  bool mUploaded = false, mRendered = false, mInFlight = false, mLost = false;
  double mGpuSeconds = 0, mCompileSeconds = 0;
};

/// What a Vulkan device here runs on, or why none comes up (probed once per process).
struct Probe {
  render::Availability availability;
  std::string device;     ///< e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or the GPU's name
  bool software = false;  ///< a CPU device (lavapipe)
};
inline const Probe& probe() {
  static const Probe result = [] {
    try {
      const VulkanContext context;
      return Probe{{true, ""}, context.name(), context.isSoftware()};
    } catch (const Error& e) {
      return Probe{{false, e.what()}, "", false};
    }
  }();
  return result;
}
inline render::Availability probeAvailability() { return probe().availability; }

}  // namespace cellrelief::vulkan
