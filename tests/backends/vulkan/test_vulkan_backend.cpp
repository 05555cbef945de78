// SPDX-License-Identifier: MIT
// What is particular to the Vulkan backend: the validation layer is on for this whole test
// program and any message it reports fails the test that caused it (each ctest test is its own
// process, so the check at tear-down names the test); device selection by name; limits taken
// from the device; timestamps that measure the frame; pipelines cached per variant. What both
// GPU backends share is tested in gpu/test_gpu_backends.cpp. Under CI a Vulkan that does not
// come up fails these tests instead of skipping them.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>

#include "test_support.h"

namespace cellrelief::vulkan {
namespace {

/// Turns validation on before any test creates an instance (unless CELLRELIEF_VULKAN_VALIDATION
/// is set already, e.g. to 0 for a quick local run), and fails the program's run when the
/// layer reported anything: leaks are reported when objects are destroyed, so this is checked
/// after every test has released its backends.
class ValidationEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { setenv("CELLRELIEF_VULKAN_VALIDATION", "1", 0); }
  void TearDown() override {
    const std::vector<std::string> messages = ValidationLog::instance().take();
    EXPECT_TRUE(messages.empty()) << messages.size() << " Vulkan validation message(s), the first: " << messages.front();
  }
};
[[maybe_unused]] ::testing::Environment* const kValidation =
    ::testing::AddGlobalTestEnvironment(new ValidationEnvironment);

class VulkanBackendTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const render::Availability a = probeAvailability();
    if (!a && test::inCI()) FAIL() << "Vulkan must run under CI: " << a.reason;
    if (!a) GTEST_SKIP() << a.reason;
  }
};

std::shared_ptr<const relief::ReliefModel> torus(int grid, int texels) {
  return std::make_shared<relief::ReliefModel>(
      relief::convert(makeTorus(1.0f, 0.35f, 192, 96), {.gridSize = grid, .texels = texels}));
}

TEST_F(VulkanBackendTest, ValidationIsOnAndReportsMisuse) {
  const VulkanContext context;
  ASSERT_TRUE(context.validating());
  EXPECT_NE(context.description().find("validation on"), std::string::npos) << context.description();
  // Anisotropic filtering without enabling the feature is invalid usage the layer must report
  // (and every driver tolerates); the messages are taken so that this test's own is not a failure.
  ValidationLog::instance().take();
  auto info = make<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
  info.anisotropyEnable = VK_TRUE;
  info.maxAnisotropy = 16.0f;
  VkSampler sampler = VK_NULL_HANDLE;
  const VkResult r = context.api().vkCreateSampler(context.device(), &info, nullptr, &sampler);
  if (r == VK_SUCCESS) context.api().vkDestroySampler(context.device(), sampler, nullptr);
  const std::vector<std::string> messages = ValidationLog::instance().take();
  ASSERT_FALSE(messages.empty()) << "the validation layer reported nothing";
  EXPECT_NE(messages.front().find("anisotropy"), std::string::npos) << messages.front();
}

TEST_F(VulkanBackendTest, ADeviceIsPickedByNameAndAnUnknownNameListsTheDevices) {
  const std::string name = probe().device;
  const std::string part = name.substr(0, name.find(' '));  // "llvmpipe", "NVIDIA", ...
  const VulkanContext named({.device = part});
  EXPECT_NE(named.name().find(part), std::string::npos);
  try {
    const VulkanContext missing({.device = "no-such-gpu-42"});
    ADD_FAILURE() << "a device named no-such-gpu-42 was found";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument) << what;
    EXPECT_NE(what.find("no-such-gpu-42"), std::string::npos) << what;
    EXPECT_NE(what.find(name), std::string::npos) << "the message lists the devices: " << what;
  }
  setenv("CELLRELIEF_VULKAN_DEVICE", "no-such-gpu-42", 1);
  EXPECT_THROW(VulkanBackend{}, Error);
  unsetenv("CELLRELIEF_VULKAN_DEVICE");
}

TEST_F(VulkanBackendTest, LimitsAreTheDevicesAndTimestampsMeasureTheFrame) {
  VulkanBackend vk;
  const VkPhysicalDeviceLimits& device = vk.context().limits();
  EXPECT_EQ(vk.limits().maxArrayLayers, int(device.maxImageArrayLayers));
  EXPECT_EQ(vk.limits().maxTextureSize, int(device.maxImageDimension2D));
  EXPECT_EQ(vk.limits().maxStorageBytes, std::min<std::size_t>(device.maxStorageBufferRange, std::size_t(1) << 31));
  EXPECT_GT(vk.limits().maxTotalBytes, std::size_t(0));
  const render::Scene scene = render::Scene::of(torus(16, 9));
  vk.upload(scene);
  const render::Camera camera = render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal());
  render::RenderOptions options;
  options.width = options.height = 128;
  vk.renderFrame(camera, options);  // builds the pipeline
  const std::size_t pipelines = vk.pipelineCount();
  const auto t0 = std::chrono::steady_clock::now();
  const render::Frame frame = vk.renderFrame(camera, options);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(vk.pipelineCount(), pipelines) << "the variant's pipeline is cached";
  std::size_t hits = 0;
  for (std::uint8_t m : frame.mask.levelData()) hits += m != 0;
  EXPECT_GT(hits, std::size_t(128 * 128 / 10));
  if (vk.context().timestampBits() == 0) GTEST_SKIP() << "the queue has no timestamps";
  EXPECT_GT(vk.deviceSeconds(), 0.0);
  EXPECT_LE(vk.deviceSeconds(), wall) << "the device cannot take longer than the host waited";
}

TEST_F(VulkanBackendTest, TheRasterizedEntryIsTheDefaultWhereTheDeviceDraws) {
  VulkanBackend vk;
  const render::Scene scene = render::Scene::of(torus(8, 9));
  vk.upload(scene);
  const render::Camera camera = render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal());
  render::RenderOptions options;
  options.width = options.height = 64;
  vk.renderFrame(camera, options);
  EXPECT_EQ(vk.lastRayEntry(), vk.context().canRasterize() ? RayEntry::Rasterized : RayEntry::Compute);
  if (probe().software) EXPECT_TRUE(vk.context().canRasterize()) << "lavapipe draws: " << vk.description();
}

}  // namespace
}  // namespace cellrelief::vulkan
