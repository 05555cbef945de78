// SPDX-License-Identifier: MIT
/// @file vulkan_context.h
/// A Vulkan 1.3 instance, one physical device and its queue, with what the backend needs around
/// them: memory types, buffers and images with their memory, one-shot command submission, and
/// the validation layer's messages.
///
/// The device: the one named by ContextOptions::device or CELLRELIEF_VULKAN_DEVICE (a
/// case-insensitive part of its name, e.g. "llvmpipe" or "H200"), else the first of discrete,
/// integrated, virtual and CPU devices (lavapipe) that offers Vulkan 1.3 and a compute queue.
/// Validation (ContextOptions::validation or CELLRELIEF_VULKAN_VALIDATION=1) creates the
/// instance with VK_LAYER_KHRONOS_validation and collects every warning and error it reports
/// into validationMessages(); the tests fail on any.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "cellrelief/vulkan/vulkan_api.h"

namespace cellrelief::vulkan {

struct ContextOptions {
  std::string device;       ///< part of the device's name; empty: CELLRELIEF_VULKAN_DEVICE, else the ranking
  bool validation = false;  ///< VK_LAYER_KHRONOS_validation (also CELLRELIEF_VULKAN_VALIDATION=1)
};

/// The validation layer's warnings and errors since the process started (or the last take).
class ValidationLog {
 public:
  static ValidationLog& instance() {
    static ValidationLog log;
    return log;
  }
  void add(std::string message) {
    std::lock_guard lock(mMutex);
    std::fprintf(stderr, "cellrelief vulkan validation: %s\n", message.c_str());
    mMessages.push_back(std::move(message));
  }
  std::vector<std::string> messages() const {
    std::lock_guard lock(mMutex);
    return mMessages;
  }
  std::vector<std::string> take() {
    std::lock_guard lock(mMutex);
    return std::exchange(mMessages, {});
  }

 private:
  mutable std::mutex mMutex;
  std::vector<std::string> mMessages;
};
inline std::vector<std::string> validationMessages() { return ValidationLog::instance().messages(); }

/// A buffer and its own memory (the backend holds a handful, so no sub-allocation).
struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  ///< host-visible buffers stay mapped
  bool coherent = true;
  explicit operator bool() const { return buffer != VK_NULL_HANDLE; }
};

/// A 2D array image, its memory and a view of all its layers.
struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  int width = 0, height = 0, layers = 0;
  explicit operator bool() const { return image != VK_NULL_HANDLE; }
};

enum class Memory {
  DeviceLocal,  ///< the device's own memory
  Upload,       ///< host-visible, written by the host (staging, uniforms)
  Readback,     ///< host-visible, read by the host: cached when the device offers it
  Shared,       ///< device-local and host-visible and cached (unified memory: lavapipe, integrated GPUs)
};

class VulkanContext {
 public:
  explicit VulkanContext(const ContextOptions& options = {}) {
    try {
      mApi = Api::global();
      createInstance(options);
      selectDevice(options);
      createDevice();
    } catch (...) {
      destroy();
      throw;
    }
  }
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;
  ~VulkanContext() { destroy(); }

  const Api& api() const { return mApi; }
  VkDevice device() const { return mDevice; }
  VkPhysicalDevice physicalDevice() const { return mPhysical; }
  VkQueue queue() const { return mQueue; }
  std::uint32_t queueFamily() const { return mQueueFamily; }
  const VkPhysicalDeviceProperties& properties() const { return mProperties; }
  const VkPhysicalDeviceLimits& limits() const { return mProperties.limits; }
  /// Whether the queue draws too (the rasterized entry needs graphics, fragment stores and
  /// dynamic rendering), and the stencil format it draws into.
  bool canRasterize() const { return mCanRasterize; }
  VkFormat stencilFormat() const { return mStencilFormat; }
  /// Valid bits of the queue's timestamps (0: none) and nanoseconds per tick.
  std::uint32_t timestampBits() const { return mTimestampBits; }
  double timestampPeriod() const { return double(mProperties.limits.timestampPeriod); }
  bool isSoftware() const { return mProperties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  bool validating() const { return mValidating; }
  /// "llvmpipe (LLVM 15.0.6, 256 bits), Vulkan 1.3.230, CPU device, Mesa 22.3.6".
  const std::string& description() const { return mDescription; }
  std::string name() const { return mProperties.deviceName; }

  /// The largest device-local heap: what bounds a scene.
  std::size_t deviceMemoryBytes() const {
    VkDeviceSize best = 0;
    for (std::uint32_t i = 0; i < mMemory.memoryHeapCount; ++i)
      if (mMemory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) best = std::max(best, mMemory.memoryHeaps[i].size);
    return std::size_t(best);
  }
  /// Whether Memory::Shared exists here (then the frame is read where the shader wrote it).
  bool hasSharedMemory() const { return findMemoryType(~0u, sharedFlags()) >= 0; }

  Buffer createBuffer(VkDeviceSize size, VkBufferUsageFlags usage, Memory memory) const {
    Buffer b;
    b.size = std::max<VkDeviceSize>(size, 16);
    auto info = make<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    info.size = b.size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(mApi.vkCreateBuffer(mDevice, &info, nullptr, &b.buffer), "vkCreateBuffer");
    try {
      VkMemoryRequirements req;
      mApi.vkGetBufferMemoryRequirements(mDevice, b.buffer, &req);
      const VkMemoryPropertyFlags flags = allocate(req, memory, b.memory);
      check(mApi.vkBindBufferMemory(mDevice, b.buffer, b.memory, 0), "vkBindBufferMemory");
      if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        check(mApi.vkMapMemory(mDevice, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
        b.coherent = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
      }
    } catch (...) {
      destroy(b);
      throw;
    }
    return b;
  }
  void destroy(Buffer& b) const {
    if (b.buffer) mApi.vkDestroyBuffer(mDevice, b.buffer, nullptr);
    if (b.memory) mApi.vkFreeMemory(mDevice, b.memory, nullptr);  // unmaps
    b = {};
  }
  /// Makes the device's writes visible to the host (non-coherent memory).
  void invalidate(const Buffer& b) const {
    if (b.coherent || !b.mapped) return;
    const VkMappedMemoryRange range = wholeRange(b);
    check(mApi.vkInvalidateMappedMemoryRanges(mDevice, 1, &range), "vkInvalidateMappedMemoryRanges");
  }
  /// Makes the host's writes visible to the device (non-coherent memory).
  void flush(const Buffer& b) const {
    if (b.coherent || !b.mapped) return;
    const VkMappedMemoryRange range = wholeRange(b);
    check(mApi.vkFlushMappedMemoryRanges(mDevice, 1, &range), "vkFlushMappedMemoryRanges");
  }

  /// Uploads through a host-visible staging buffer of `bytes`: `fill` writes it, `record` records
  /// the copies out of it; the commands run to completion, and the staging buffer is released
  /// whatever happens.
  void uploadThroughStaging(std::size_t bytes, const std::function<void(char*)>& fill,
                            const std::function<void(VkCommandBuffer, VkBuffer)>& record) const {
    Buffer staging = createBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Memory::Upload);
    try {
      fill(static_cast<char*>(staging.mapped));
      flush(staging);
      submitAndWait([&](VkCommandBuffer cmd) { record(cmd, staging.buffer); });
    } catch (...) {
      destroy(staging);
      throw;
    }
    destroy(staging);
  }

  /// A 2D array image (optimal tiling, device-local) and a view of all its layers.
  Image createImage(VkFormat format, int width, int height, int layers, VkImageUsageFlags usage,
                    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT) const {
    Image im;
    im.format = format;
    im.width = width, im.height = height, im.layers = layers;
    auto info = make<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {std::uint32_t(width), std::uint32_t(height), 1};
    info.mipLevels = 1;
    info.arrayLayers = std::uint32_t(layers);
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    check(mApi.vkCreateImage(mDevice, &info, nullptr, &im.image), "vkCreateImage");
    try {
      VkMemoryRequirements req;
      mApi.vkGetImageMemoryRequirements(mDevice, im.image, &req);
      allocate(req, Memory::DeviceLocal, im.memory);
      check(mApi.vkBindImageMemory(mDevice, im.image, im.memory, 0), "vkBindImageMemory");
      auto view = make<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
      view.image = im.image;
      view.viewType = (usage & VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT) ? VK_IMAGE_VIEW_TYPE_2D : VK_IMAGE_VIEW_TYPE_2D_ARRAY;
      view.format = format;
      view.subresourceRange = {aspect, 0, 1, 0, std::uint32_t(layers)};
      check(mApi.vkCreateImageView(mDevice, &view, nullptr, &im.view), "vkCreateImageView");
    } catch (...) {
      destroy(im);
      throw;
    }
    return im;
  }
  void destroy(Image& im) const {
    if (im.view) mApi.vkDestroyImageView(mDevice, im.view, nullptr);
    if (im.image) mApi.vkDestroyImage(mDevice, im.image, nullptr);
    if (im.memory) mApi.vkFreeMemory(mDevice, im.memory, nullptr);
    im = {};
  }

  /// Records commands into a fresh command buffer, submits them and waits.
  void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const {
    auto alloc = make<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    alloc.commandPool = mCommandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    check(mApi.vkAllocateCommandBuffers(mDevice, &alloc, &cmd), "vkAllocateCommandBuffers");
    VkFence fence = VK_NULL_HANDLE;
    auto release = [&] {
      if (fence) mApi.vkDestroyFence(mDevice, fence, nullptr);
      mApi.vkFreeCommandBuffers(mDevice, mCommandPool, 1, &cmd);
    };
    try {
      auto begin = make<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
      begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
      check(mApi.vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
      record(cmd);
      check(mApi.vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
      auto fenceInfo = make<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
      check(mApi.vkCreateFence(mDevice, &fenceInfo, nullptr, &fence), "vkCreateFence");
      auto submit = make<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
      submit.commandBufferCount = 1;
      submit.pCommandBuffers = &cmd;
      check(mApi.vkQueueSubmit(mQueue, 1, &submit, fence), "vkQueueSubmit");
      check(mApi.vkWaitForFences(mDevice, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    } catch (...) {
      if (fence) mApi.vkQueueWaitIdle(mQueue);  // never free a command buffer that may still run
      release();
      throw;
    }
    release();
  }

  VkCommandPool commandPool() const { return mCommandPool; }

  /// Devices this instance sees, for messages: "llvmpipe (LLVM 15.0.6, 256 bits) [CPU]".
  const std::vector<std::string>& deviceNames() const { return mDeviceNames; }

 private:
  static VkMappedMemoryRange wholeRange(const Buffer& b) {
    auto range = make<VkMappedMemoryRange>(VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE);
    range.memory = b.memory;
    range.size = VK_WHOLE_SIZE;
    return range;
  }

  static bool envFlag(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
  }

  static VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    const char* level = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
    ValidationLog::instance().add(std::string(level) + ": " + (data && data->pMessage ? data->pMessage : "(no text)"));
    return VK_FALSE;
  }

  void createInstance(const ContextOptions& options) {
    std::uint32_t version = 0;
    check(mApi.vkEnumerateInstanceVersion(&version), "vkEnumerateInstanceVersion");
    if (version < VK_API_VERSION_1_3)
      throw Error(ErrorKind::Unsupported, "the Vulkan loader offers " + versionText(version) + ", the backend needs 1.3");
    mValidating = options.validation || envFlag("CELLRELIEF_VULKAN_VALIDATION");
    std::vector<const char*> layers, extensions;
    if (mValidating) {
      if (!hasLayer("VK_LAYER_KHRONOS_validation"))
        throw Error(ErrorKind::Unsupported,
                    "Vulkan validation was asked for, but VK_LAYER_KHRONOS_validation is not installed "
                    "(Debian: vulkan-validationlayers)");
      if (!hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME))
        throw Error(ErrorKind::Unsupported, "Vulkan validation needs " VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
      layers.push_back("VK_LAYER_KHRONOS_validation");
      extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    auto app = make<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "cellrelief";
    app.pEngineName = "cellrelief";
    app.apiVersion = VK_API_VERSION_1_3;
    auto messenger = make<VkDebugUtilsMessengerCreateInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
    messenger.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger.pfnUserCallback = &VulkanContext::onMessage;
    auto info = make<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    info.pNext = mValidating ? &messenger : nullptr;  // also reports what instance creation finds
    info.pApplicationInfo = &app;
    info.enabledLayerCount = std::uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = std::uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    const VkResult r = mApi.vkCreateInstance(&info, nullptr, &mInstance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER) throw Error(ErrorKind::Unsupported, "no Vulkan device (no driver for Vulkan 1.3)");
    check(r, "vkCreateInstance");
    mApi.loadInstance(mInstance);
    if (mValidating) {
      if (!mApi.vkCreateDebugUtilsMessengerEXT) throw Error(ErrorKind::Unsupported, "Vulkan validation: no vkCreateDebugUtilsMessengerEXT");
      check(mApi.vkCreateDebugUtilsMessengerEXT(mInstance, &messenger, nullptr, &mMessenger),
            "vkCreateDebugUtilsMessengerEXT");
    }
  }

  static int typeRank(VkPhysicalDeviceType type) {
    switch (type) {
      case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
      case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
      case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
      case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
      default: return 4;
    }
  }
  static const char* typeName(VkPhysicalDeviceType type) {
    switch (type) {
      case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
      case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
      case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
      case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU device";
      default: return "other device";
    }
  }
  static std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }
  static std::string versionText(std::uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
           std::to_string(VK_API_VERSION_PATCH(v));
  }

  /// Why a device cannot serve the backend ("" when it can), and its compute queue family.
  std::string unsuitable(VkPhysicalDevice device, std::uint32_t& family) const {
    VkPhysicalDeviceProperties p;
    mApi.vkGetPhysicalDeviceProperties(device, &p);
    if (p.apiVersion < VK_API_VERSION_1_3) return "device lacks Vulkan 1.3 (it offers " + versionText(p.apiVersion) + ")";
    std::uint32_t count = 0;
    mApi.vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    mApi.vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    int best = -1;
    for (std::uint32_t i = 0; i < count; ++i) {
      if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
      const bool graphics = (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
      if (best < 0 || (graphics && !(families[std::size_t(best)].queueFlags & VK_QUEUE_GRAPHICS_BIT))) best = int(i);
    }
    if (best < 0) return "device lacks a compute queue";
    for (VkFormat f : {VK_FORMAT_R16_UINT, VK_FORMAT_R16G16_UINT, VK_FORMAT_R8G8B8A8_UINT}) {
      VkFormatProperties fp;
      mApi.vkGetPhysicalDeviceFormatProperties(device, f, &fp);
      if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        return "device lacks sampled integer images (format " + std::to_string(int(f)) + ")";
    }
    family = std::uint32_t(best);
    return "";
  }

  void selectDevice(const ContextOptions& options) {
    std::uint32_t count = 0;
    check(mApi.vkEnumeratePhysicalDevices(mInstance, &count, nullptr), "vkEnumeratePhysicalDevices");
    std::vector<VkPhysicalDevice> devices(count);
    check(mApi.vkEnumeratePhysicalDevices(mInstance, &count, devices.data()), "vkEnumeratePhysicalDevices");
    if (devices.empty()) throw Error(ErrorKind::Unsupported, "no Vulkan device");
    std::string wanted = options.device;
    if (wanted.empty())
      if (const char* env = std::getenv("CELLRELIEF_VULKAN_DEVICE")) wanted = env;
    std::string reasons;
    int bestRank = 1 << 20;
    for (VkPhysicalDevice d : devices) {
      VkPhysicalDeviceProperties p;
      mApi.vkGetPhysicalDeviceProperties(d, &p);
      mDeviceNames.push_back(std::string(p.deviceName) + " [" + typeName(p.deviceType) + "]");
      if (!wanted.empty() && lower(p.deviceName).find(lower(wanted)) == std::string::npos) continue;
      std::uint32_t family = 0;
      if (const std::string why = unsuitable(d, family); !why.empty()) {
        reasons += (reasons.empty() ? "" : "; ") + std::string(p.deviceName) + ": " + why;
        continue;
      }
      if (typeRank(p.deviceType) < bestRank) {
        bestRank = typeRank(p.deviceType);
        mPhysical = d;
        mQueueFamily = family;
        mProperties = p;
      }
    }
    if (!mPhysical) {
      std::string all;
      for (const std::string& n : mDeviceNames) all += (all.empty() ? "" : ", ") + n;
      if (!reasons.empty()) throw Error(ErrorKind::Unsupported, reasons);
      throw Error(ErrorKind::InvalidArgument, "no Vulkan device named like '" + wanted + "' (devices: " + all + ")");
    }
    mApi.vkGetPhysicalDeviceMemoryProperties(mPhysical, &mMemory);
  }

  void createDevice() {
    auto has13 = make<VkPhysicalDeviceVulkan13Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
    auto has = make<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    has.pNext = &has13;
    mApi.vkGetPhysicalDeviceFeatures2(mPhysical, &has);
    std::uint32_t count = 0;
    mApi.vkGetPhysicalDeviceQueueFamilyProperties(mPhysical, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    mApi.vkGetPhysicalDeviceQueueFamilyProperties(mPhysical, &count, families.data());
    const VkQueueFamilyProperties& family = families[mQueueFamily];
    mTimestampBits = family.timestampValidBits;
    mStencilFormat = pickStencilFormat();
    mCanRasterize = (family.queueFlags & VK_QUEUE_GRAPHICS_BIT) && has.features.fragmentStoresAndAtomics &&
                    has13.dynamicRendering && mStencilFormat != VK_FORMAT_UNDEFINED;

    auto enable13 = make<VkPhysicalDeviceVulkan13Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
    enable13.dynamicRendering = mCanRasterize ? VK_TRUE : VK_FALSE;
    auto enable = make<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    enable.pNext = &enable13;
    enable.features.fragmentStoresAndAtomics = mCanRasterize ? VK_TRUE : VK_FALSE;
    const float priority = 1.0f;
    auto queue = make<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    queue.queueFamilyIndex = mQueueFamily;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    auto info = make<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    info.pNext = &enable;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    check(mApi.vkCreateDevice(mPhysical, &info, nullptr, &mDevice), "vkCreateDevice");
    mApi.loadDevice(mDevice);
    mApi.vkGetDeviceQueue(mDevice, mQueueFamily, 0, &mQueue);
    auto pool = make<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = mQueueFamily;
    check(mApi.vkCreateCommandPool(mDevice, &pool, nullptr, &mCommandPool), "vkCreateCommandPool");
    mDescription = std::string(mProperties.deviceName) + ", Vulkan " + versionText(mProperties.apiVersion) + ", " +
                   typeName(mProperties.deviceType) + (mValidating ? ", validation on" : "");
  }

  VkFormat pickStencilFormat() const {
    for (VkFormat f : {VK_FORMAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_D32_SFLOAT_S8_UINT,
                       VK_FORMAT_D16_UNORM_S8_UINT}) {
      VkFormatProperties fp;
      mApi.vkGetPhysicalDeviceFormatProperties(mPhysical, f, &fp);
      if (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
    }
    return VK_FORMAT_UNDEFINED;
  }

  static VkMemoryPropertyFlags sharedFlags() {
    return VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
  }

  /// A memory type with the `required` flags, one with the `preferred` ones too if any; -1 if none.
  int findMemoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred = 0) const {
    int best = -1;
    for (std::uint32_t i = 0; i < mMemory.memoryTypeCount; ++i) {
      const VkMemoryPropertyFlags f = mMemory.memoryTypes[i].propertyFlags;
      if (!(typeBits & (1u << i)) || (f & required) != required) continue;
      if (best < 0 || ((f & preferred) == preferred && (mMemory.memoryTypes[std::size_t(best)].propertyFlags & preferred) != preferred))
        best = int(i);
    }
    return best;
  }

  VkMemoryPropertyFlags allocate(const VkMemoryRequirements& req, Memory memory, VkDeviceMemory& out) const {
    int type = -1;
    switch (memory) {
      case Memory::DeviceLocal: type = findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT); break;
      case Memory::Upload:
        type = findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                              VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        break;
      case Memory::Readback:
        type = findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                              VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
        break;
      case Memory::Shared: type = findMemoryType(req.memoryTypeBits, sharedFlags()); break;
    }
    if (memory == Memory::DeviceLocal && type < 0) type = findMemoryType(req.memoryTypeBits, 0);
    if (type < 0) throw Error(ErrorKind::Unsupported, "Vulkan: " + name() + " has no memory type for this resource");
    auto info = make<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    info.allocationSize = req.size;
    info.memoryTypeIndex = std::uint32_t(type);
    check(mApi.vkAllocateMemory(mDevice, &info, nullptr, &out), "vkAllocateMemory");
    return mMemory.memoryTypes[std::size_t(type)].propertyFlags;
  }

  bool hasLayer(const char* layer) const {
    std::uint32_t count = 0;
    mApi.vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    mApi.vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, layer) == 0; });
  }
  bool hasInstanceExtension(const char* extension) const {
    std::uint32_t count = 0;
    mApi.vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> all(count);
    mApi.vkEnumerateInstanceExtensionProperties(nullptr, &count, all.data());
    return std::any_of(all.begin(), all.end(), [&](const auto& e) { return std::strcmp(e.extensionName, extension) == 0; });
  }

  void destroy() {
    if (mDevice) {
      mApi.vkDeviceWaitIdle(mDevice);  // a lost device returns at once; what it held goes anyway
      if (mCommandPool) mApi.vkDestroyCommandPool(mDevice, mCommandPool, nullptr);
      mApi.vkDestroyDevice(mDevice, nullptr);
    }
    if (mMessenger) mApi.vkDestroyDebugUtilsMessengerEXT(mInstance, mMessenger, nullptr);
    if (mInstance) mApi.vkDestroyInstance(mInstance, nullptr);
    mDevice = VK_NULL_HANDLE, mCommandPool = VK_NULL_HANDLE, mMessenger = VK_NULL_HANDLE, mInstance = VK_NULL_HANDLE;
  }

  Api mApi;
  VkInstance mInstance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT mMessenger = VK_NULL_HANDLE;
  VkPhysicalDevice mPhysical = VK_NULL_HANDLE;
  VkDevice mDevice = VK_NULL_HANDLE;
  VkQueue mQueue = VK_NULL_HANDLE;
  VkCommandPool mCommandPool = VK_NULL_HANDLE;
  std::uint32_t mQueueFamily = 0, mTimestampBits = 0;
  VkPhysicalDeviceProperties mProperties{};
  VkPhysicalDeviceMemoryProperties mMemory{};
  VkFormat mStencilFormat = VK_FORMAT_UNDEFINED;
  bool mCanRasterize = false, mValidating = false;
  std::string mDescription;
  std::vector<std::string> mDeviceNames;
};

}  // namespace cellrelief::vulkan
