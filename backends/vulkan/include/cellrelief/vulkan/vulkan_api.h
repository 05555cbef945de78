// SPDX-License-Identifier: MIT
/// @file vulkan_api.h
/// The Vulkan entry points the backend calls, loaded at run time from the loader (libvulkan.so.1)
/// rather than linked: a program built with the Vulkan backend still starts on a machine without
/// libvulkan1, and the backend then answers "no Vulkan loader (libvulkan1)" instead of the
/// program failing to start. Device functions are taken from the device (no loader dispatch).
#pragma once

#ifndef VK_NO_PROTOTYPES
#define VK_NO_PROTOTYPES
#endif
#include <vulkan/vulkan.h>

#include <dlfcn.h>

#include <string>

#include "cellrelief/core/error.h"

namespace cellrelief::vulkan {

// clang-format off
#define CELLRELIEF_VK_GLOBAL_FUNCTIONS(X) \
  X(vkCreateInstance) X(vkEnumerateInstanceLayerProperties) X(vkEnumerateInstanceExtensionProperties) \
  X(vkEnumerateInstanceVersion)
#define CELLRELIEF_VK_INSTANCE_FUNCTIONS(X) \
  X(vkDestroyInstance) X(vkEnumeratePhysicalDevices) X(vkGetPhysicalDeviceProperties) \
  X(vkGetPhysicalDeviceFeatures) X(vkGetPhysicalDeviceFeatures2) X(vkGetPhysicalDeviceQueueFamilyProperties) \
  X(vkGetPhysicalDeviceMemoryProperties) X(vkGetPhysicalDeviceFormatProperties) X(vkCreateDevice) \
  X(vkGetDeviceProcAddr) X(vkEnumerateDeviceExtensionProperties)
#define CELLRELIEF_VK_DEBUG_FUNCTIONS(X) X(vkCreateDebugUtilsMessengerEXT) X(vkDestroyDebugUtilsMessengerEXT)
#define CELLRELIEF_VK_DEVICE_FUNCTIONS(X) \
  X(vkDestroyDevice) X(vkGetDeviceQueue) X(vkDeviceWaitIdle) X(vkQueueSubmit) X(vkQueueWaitIdle) \
  X(vkCreateCommandPool) X(vkDestroyCommandPool) X(vkAllocateCommandBuffers) X(vkFreeCommandBuffers) \
  X(vkBeginCommandBuffer) X(vkEndCommandBuffer) X(vkResetCommandBuffer) \
  X(vkCreateFence) X(vkDestroyFence) X(vkWaitForFences) X(vkResetFences) \
  X(vkCreateBuffer) X(vkDestroyBuffer) X(vkGetBufferMemoryRequirements) X(vkBindBufferMemory) \
  X(vkCreateImage) X(vkDestroyImage) X(vkGetImageMemoryRequirements) X(vkBindImageMemory) \
  X(vkCreateImageView) X(vkDestroyImageView) X(vkCreateSampler) X(vkDestroySampler) \
  X(vkAllocateMemory) X(vkFreeMemory) X(vkMapMemory) X(vkUnmapMemory) X(vkInvalidateMappedMemoryRanges) \
  X(vkFlushMappedMemoryRanges) \
  X(vkCreateShaderModule) X(vkDestroyShaderModule) X(vkCreateDescriptorSetLayout) X(vkDestroyDescriptorSetLayout) \
  X(vkCreatePipelineLayout) X(vkDestroyPipelineLayout) X(vkCreateComputePipelines) X(vkCreateGraphicsPipelines) \
  X(vkDestroyPipeline) X(vkCreateDescriptorPool) X(vkDestroyDescriptorPool) X(vkAllocateDescriptorSets) \
  X(vkUpdateDescriptorSets) X(vkCreateQueryPool) X(vkDestroyQueryPool) X(vkGetQueryPoolResults) \
  X(vkCmdResetQueryPool) X(vkCmdWriteTimestamp) X(vkCmdBindPipeline) X(vkCmdBindDescriptorSets) X(vkCmdDispatch) \
  X(vkCmdCopyBuffer) X(vkCmdCopyBufferToImage) X(vkCmdPipelineBarrier) X(vkCmdFillBuffer) \
  X(vkCmdBeginRendering) X(vkCmdEndRendering) X(vkCmdSetViewport) X(vkCmdSetScissor) X(vkCmdDraw) \
  X(vkCmdPushConstants)
// clang-format on

/// The function table of one instance and device.
struct Api {
#define CELLRELIEF_VK_MEMBER(name) PFN_##name name = nullptr;
  PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr = nullptr;
  CELLRELIEF_VK_GLOBAL_FUNCTIONS(CELLRELIEF_VK_MEMBER)
  CELLRELIEF_VK_INSTANCE_FUNCTIONS(CELLRELIEF_VK_MEMBER)
  CELLRELIEF_VK_DEBUG_FUNCTIONS(CELLRELIEF_VK_MEMBER)
  CELLRELIEF_VK_DEVICE_FUNCTIONS(CELLRELIEF_VK_MEMBER)
#undef CELLRELIEF_VK_MEMBER

  /// The loader's global functions; throws Error (Unsupported) "no Vulkan loader (libvulkan1)".
  static Api global() {
    Api api;
    api.vkGetInstanceProcAddr = loaderEntry();
#define CELLRELIEF_VK_LOAD(name) api.name = reinterpret_cast<PFN_##name>(api.vkGetInstanceProcAddr(nullptr, #name));
    CELLRELIEF_VK_GLOBAL_FUNCTIONS(CELLRELIEF_VK_LOAD)
#undef CELLRELIEF_VK_LOAD
    if (!api.vkCreateInstance || !api.vkEnumerateInstanceVersion)
      throw Error(ErrorKind::Unsupported, "the Vulkan loader (libvulkan1) lacks vkCreateInstance");
    return api;
  }

  void loadInstance(VkInstance instance) {
#define CELLRELIEF_VK_LOAD(name) name = reinterpret_cast<PFN_##name>(vkGetInstanceProcAddr(instance, #name));
    CELLRELIEF_VK_INSTANCE_FUNCTIONS(CELLRELIEF_VK_LOAD)
    CELLRELIEF_VK_DEBUG_FUNCTIONS(CELLRELIEF_VK_LOAD)  // null without VK_EXT_debug_utils
#undef CELLRELIEF_VK_LOAD
#define CELLRELIEF_VK_REQUIRE(name) \
  if (!name) throw Error(ErrorKind::Unsupported, "the Vulkan instance lacks " #name);
    CELLRELIEF_VK_INSTANCE_FUNCTIONS(CELLRELIEF_VK_REQUIRE)
#undef CELLRELIEF_VK_REQUIRE
  }

  void loadDevice(VkDevice device) {
#define CELLRELIEF_VK_LOAD(name) name = reinterpret_cast<PFN_##name>(vkGetDeviceProcAddr(device, #name));
    CELLRELIEF_VK_DEVICE_FUNCTIONS(CELLRELIEF_VK_LOAD)
#undef CELLRELIEF_VK_LOAD
#define CELLRELIEF_VK_REQUIRE(name) \
  if (!name) throw Error(ErrorKind::Unsupported, "the Vulkan device lacks " #name " (Vulkan 1.3)");
    CELLRELIEF_VK_DEVICE_FUNCTIONS(CELLRELIEF_VK_REQUIRE)
#undef CELLRELIEF_VK_REQUIRE
  }

 private:
  /// libvulkan.so.1, opened once and never closed (drivers keep threads and handlers in it).
  static PFN_vkGetInstanceProcAddr loaderEntry() {
    static void* const library = [] {
      void* handle = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
      if (!handle) handle = dlopen("libvulkan.so", RTLD_NOW | RTLD_LOCAL);
      return handle;
    }();
    if (!library) throw Error(ErrorKind::Unsupported, "no Vulkan loader (libvulkan1)");
    auto entry = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library, "vkGetInstanceProcAddr"));
    if (!entry) throw Error(ErrorKind::Unsupported, "the Vulkan loader (libvulkan1) lacks vkGetInstanceProcAddr");
    return entry;
  }
};

/// A Vulkan info struct with its sType set and everything else zero.
template <class T>
T make(VkStructureType type) {
  T value{};
  value.sType = type;
  return value;
}

/// The name of a VkResult, for messages.
inline const char* resultName(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default: return "VkResult";
  }
}

/// The Error of a failed Vulkan call, carrying its VkResult (a lost device is told by it).
class VulkanError : public Error {
 public:
  VulkanError(ErrorKind kind, const std::string& message, VkResult result) : Error(kind, message), mResult(result) {}
  VkResult result() const { return mResult; }

 private:
  VkResult mResult;
};

/// Throws a VulkanError for a failed call: out of memory is a ResourceLimit, a lost device or
/// anything else Unsupported, each with the call and the result's name.
inline void check(VkResult result, const char* what) {
  if (result == VK_SUCCESS) return;
  const bool memory = result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY;
  std::string message = std::string("Vulkan: ") + what + " failed: " + resultName(result);
  if (result == VK_ERROR_DEVICE_LOST) message += " (the device was lost: a driver reset or a fault)";
  if (std::string(resultName(result)) == "VkResult") message += " " + std::to_string(int(result));
  throw VulkanError(memory ? ErrorKind::ResourceLimit : ErrorKind::Unsupported, message, result);
}

}  // namespace cellrelief::vulkan
