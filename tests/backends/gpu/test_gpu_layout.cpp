// SPDX-License-Identifier: MIT
// The GPU layout (gpu/gpu_layout.h) without a GPU: the hash lookup finds every grey cell and
// nothing else, the atlas holds every sample of every layer where the shader reads it, a model
// with more face layers than a device has array layers still fits, and a scene beyond the
// limits is refused with an error that names the model and the limit; RayEntry::Fastest keeps the
// entry the device's clock finds faster.
#include <cctype>
#include <gtest/gtest.h>

#include <set>

#include <cellrelief/core/procedural.h>
#include <cellrelief/gpu/gpu_frame.h>
#include <cellrelief/gpu/gpu_layout.h>
#include <cellrelief/gpu/shader_preamble.h>
#include <cellrelief/relief/convert.h>

namespace cellrelief::gpu {
namespace {

std::shared_ptr<const relief::ReliefModel> torusModel(int grid, int texels) {
  return std::make_shared<relief::ReliefModel>(
      relief::convert(makeTorus(1.0f, 0.35f, 96, 48), {.gridSize = grid, .texels = texels}));
}

TEST(GpuLayout, TheHashLookupFindsEveryGreyCellAndNothingElse) {
  const auto model = torusModel(16, 9);
  const GpuScene gpu = packScene(render::Scene::of(model), {}, true);
  std::set<std::uint32_t> grey;
  int worstProbes = 0;
  for (std::size_t i = 0; i < model->cells.size(); ++i) {
    int probes = 0;
    EXPECT_EQ(findCell(gpu, 0, model->cells[i].ijk(), &probes), int(i));
    worstProbes = std::max(worstProbes, probes);
    grey.insert(relief::CellRecord::packIjk(model->cells[i].ijk()));
  }
  int misses = 0;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        if (!grey.count(relief::CellRecord::packIjk({i, j, k}))) {
          EXPECT_EQ(findCell(gpu, 0, {i, j, k}), -1);
          ++misses;
        }
  EXPECT_GT(misses, 0);
  // Load factor <= 1/2: memory in proportion to the grey cells, short probe sequences.
  EXPECT_LE(gpu.hashSlots.size() / 2, std::max<std::size_t>(16, 4 * model->cells.size()));
  EXPECT_LT(worstProbes, 32);
}

TEST(GpuLayout, EverySampleLiesInItsTileWhereTheShaderReadsIt) {
  const auto model = torusModel(8, 17);
  DeviceLimits limits;
  limits.maxTextureSize = 128;  // forces several rows and array layers
  const GpuScene gpu = packScene(render::Scene::of(model), limits, true);
  const ModelInfo& info = gpu.models[0];
  ASSERT_GT(gpu.distances.layers, 1);
  EXPECT_LE(gpu.distances.width, 128);
  for (int layer = 0; layer < model->layerCount(); ++layer) {
    const int r = layer % info.tilesPerLayer;
    const int x0 = (r % info.tilesPerRow) * model->texels, y0 = (r / info.tilesPerRow) * model->texels;
    const int z = info.layerBase + layer / info.tilesPerLayer;
    ASSERT_LT(z, gpu.distances.layers);
    for (int b = 0; b < model->texels; ++b)
      for (int a = 0; a < model->texels; ++a) {
        const std::size_t texel =
            (std::size_t(z) * gpu.distances.height + std::size_t(y0 + b)) * gpu.distances.width + std::size_t(x0 + a);
        ASSERT_EQ(gpu.distances.texels[texel], model->distanceCode(layer, a, b)) << layer << " " << a << " " << b;
      }
  }
}

TEST(GpuLayout, MoreFaceLayersThanTheDeviceHasArrayLayersStillFit) {
  const auto model = torusModel(32, 9);
  DeviceLimits limits;
  limits.maxArrayLayers = 16;
  ASSERT_GT(model->layerCount(), limits.maxArrayLayers);
  const GpuScene gpu = packScene(render::Scene::of(model), limits, true);
  EXPECT_LE(gpu.distances.layers, 16);
  EXPECT_GE(std::size_t(gpu.distances.width) * gpu.distances.height * gpu.distances.layers,
            std::size_t(model->layerCount()) * 81);
}

TEST(GpuLayout, AScenePastTheLimitsIsRefusedWithTheModelAndTheLimitNamed) {
  const auto model = torusModel(32, 9);
  DeviceLimits limits;
  limits.maxTextureSize = 64;
  limits.maxArrayLayers = 2;
  try {
    packScene(render::Scene::of(model), limits, true);
    FAIL() << "a scene past the device's limits was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::ResourceLimit);
    const std::string what = e.what();
    EXPECT_NE(what.find("scene model 0"), std::string::npos) << what;
    EXPECT_NE(what.find("beyond the device's 2"), std::string::npos) << what;
  }
  limits = {};
  limits.maxTotalBytes = 1000;
  EXPECT_THROW(packScene(render::Scene::of(model), limits, true), Error);
}

TEST(GpuFrame, TheLayoutHoldsTheWrittenChannelsAndAFrameBeyondTheBufferIsRefused) {
  render::RenderOptions o;
  o.width = 300;
  o.height = 200;
  o.channels = render::kColor | render::kNormal;
  const FrameLayout l = frameLayout(o, render::kColor | render::kNormal | render::kMask, std::size_t(1) << 30);
  const std::size_t pixels = 300 * 200;
  EXPECT_EQ(l.color, 0u);
  EXPECT_EQ(l.normal, pixels);
  EXPECT_EQ(l.mask, 4 * pixels);
  EXPECT_EQ(l.words, 5 * pixels);
  std::size_t missWords = 0;
  for (const WordFill& f : missFills(l, render::Scene{})) missWords += f.words;
  EXPECT_EQ(missWords, l.words) << "every written word has a miss value";
  try {
    frameLayout(o, render::kAllChannels, std::size_t(1) << 20);
    ADD_FAILURE() << "a 300x200 frame of every channel fit in 1 MiB";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::ResourceLimit);
    EXPECT_NE(std::string(e.what()).find("300x200"), std::string::npos) << e.what();
  }
}

TEST(ShaderPreamble, TheConstantsComeFromTheCppValues) {
  const std::string constants = traversalConstants();
  EXPECT_NE(constants.find("#define CR_EMPTY_FIELD (4.000000000e+00)"), std::string::npos) << constants;
  EXPECT_NE(constants.find("#define CR_CENTRE_INSIDE_BIT " + std::to_string(relief::CellRecord::kCentreInside) + "u"),
            std::string::npos);
  // The GLSL body uses the names, never the values: no literal of a shared constant is typed there.
  const std::string body(kReliefTraceComp);
  for (const char* name : {"CR_EMPTY_FIELD", "CR_NEAR_FACE_SAMPLES", "CR_FOOTPRINT_PROBES", "CR_SKIP_PROGRESS",
                           "CR_ROOT_BISECTIONS", "CR_QUADRATIC_EPSILON", "CR_SHADE_SEARCH_RADIUS",
                           "CR_SURFACE_OFFSET_SAMPLES", "CR_GAMMA3", "CR_CENTRE_INSIDE_BIT"}) {
    EXPECT_NE(body.find(name), std::string::npos) << name << " is not used by the shader";
    EXPECT_EQ(body.find(std::string("#define ") + name), std::string::npos) << name << " is redefined in the shader";
  }
}

TEST(ShaderPreamble, AVariantHoldsOnlyWhatTheSceneUses) {
  SceneFeatures perspectiveOnly;
  perspectiveOnly.perspective = true;
  const ShaderVariant v = ShaderVariant::specialized(perspectiveOnly, {}, true, false, render::kColor);
  const std::string constants = variantConstants(v);
  EXPECT_NE(constants.find("const bool CR_PERSPECTIVE = true;"), std::string::npos) << constants;
  EXPECT_NE(constants.find("const bool CR_SHADOWS = true;"), std::string::npos);
  for (const char* absent : {"CR_PARALLEL", "CR_PLANAR", "CR_AXIAL", "CR_SKIP", "CR_OCT_NORMALS", "CR_COLORS",
                             "CR_REFLECTIONS", "CR_OUT_DEPTH"})
    EXPECT_NE(constants.find(std::string("const bool ") + absent + " = false;"), std::string::npos) << absent;
}

TEST(ShaderPreamble, VulkanSpecializationIdsFollowTheSwitchTable) {
  const std::string spec = variantSpecializationConstants();
  for (int i = 0; i < kVariantSwitchCount; ++i)
    EXPECT_NE(spec.find("layout(constant_id = " + std::to_string(i) + ") const bool " + kVariantSwitchNames[i] + " ="),
              std::string::npos)
        << kVariantSwitchNames[i];
  // Every switch is used by the body: one that is not would be a variant that changes nothing.
  const std::string body(kReliefTraceComp);
  auto usesToken = [&](const std::string& name) {
    for (std::size_t at = body.find(name); at != std::string::npos; at = body.find(name, at + 1)) {
      const char next = at + name.size() < body.size() ? body[at + name.size()] : ' ';
      if (!std::isalnum(static_cast<unsigned char>(next)) && next != '_') return true;
    }
    return false;
  };
  for (const char* name : kVariantSwitchNames) EXPECT_TRUE(usesToken(name)) << name;
  EXPECT_EQ(body.find("#ifdef CR_OUT"), std::string::npos) << "variant switches are constants, not macros";
}

// The choice of RayEntry::Fastest, driven by device times as a backend reports them: each entry
// tried once per variant and size, the faster kept; no trials where the device has no clock or
// the rasterized entry cannot serve; explicit entries obeyed.
class EntryChooser : public TraversalControls {
 public:
  bool frame(const ShaderVariant& v, int width, int height, double rasterizedSeconds, double computeSeconds,
             bool possible = true, bool timed = true) {
    render::RenderOptions o;
    o.width = width;
    o.height = height;
    const bool rasterized = takeRasterized(v, o, possible, timed);
    entryTimed(rasterized, rasterized ? rasterizedSeconds : computeSeconds);
    return rasterized;
  }
  void newScene() { forgetEntryTimes(); }
};

TEST(RayEntryChoice, FastestTriesEachEntryOncePerVariantAndSizeAndKeepsTheFaster) {
  EntryChooser c;
  ASSERT_EQ(c.rayEntry(), RayEntry::Fastest);  // the default
  const ShaderVariant primary = ShaderVariant::general(), shaded = [] {
    ShaderVariant v = ShaderVariant::general();
    v.shadows = false;
    return v;
  }();
  // Fragment pass 19x slower (an H100): rasterized trial, compute trial, then compute for good.
  EXPECT_TRUE(c.frame(primary, 640, 480, 0.019, 0.001));
  EXPECT_FALSE(c.frame(primary, 640, 480, 0.019, 0.001));
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(c.frame(primary, 640, 480, 0.019, 0.001));
  // Another size and another variant are judged anew: here the fragment pass wins.
  EXPECT_TRUE(c.frame(primary, 80, 60, 0.0005, 0.0008));
  EXPECT_FALSE(c.frame(primary, 80, 60, 0.0005, 0.0008));
  EXPECT_TRUE(c.frame(primary, 80, 60, 0.0005, 0.0008));
  EXPECT_TRUE(c.frame(shaded, 640, 480, 0.002, 0.003));
  EXPECT_FALSE(c.frame(shaded, 640, 480, 0.002, 0.003));
  EXPECT_TRUE(c.frame(shaded, 640, 480, 0.002, 0.003));
  EXPECT_FALSE(c.frame(primary, 640, 480, 0.019, 0.001));  // the first verdict stands
  // A new scene (an upload) is timed anew.
  c.newScene();
  EXPECT_TRUE(c.frame(primary, 640, 480, 0.001, 0.019));
  EXPECT_FALSE(c.frame(primary, 640, 480, 0.001, 0.019));
  EXPECT_TRUE(c.frame(primary, 640, 480, 0.001, 0.019));
}

TEST(RayEntryChoice, FastestRasterizesWithoutAClockAndNeverWhereRasterizingCannotServe) {
  EntryChooser c;
  const ShaderVariant v = ShaderVariant::general();
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(c.frame(v, 64, 64, 0.01, 0.001, true, false));  // llvmpipe
  EXPECT_FALSE(c.frame(v, 64, 64, 0.001, 0.01, false, true));                              // eye inside
  // A trial that reads no time (0) is tried again rather than judged.
  EXPECT_TRUE(c.frame(v, 32, 32, 0.0, 0.001));
  EXPECT_TRUE(c.frame(v, 32, 32, 0.002, 0.001));
  EXPECT_FALSE(c.frame(v, 32, 32, 0.002, 0.001));
  EXPECT_FALSE(c.frame(v, 32, 32, 0.002, 0.001));
  c.setRayEntry(RayEntry::Rasterized);
  EXPECT_TRUE(c.frame(v, 32, 32, 0.002, 0.001));
  EXPECT_FALSE(c.frame(v, 32, 32, 0.002, 0.001, false));
  c.setRayEntry(RayEntry::Compute);
  EXPECT_FALSE(c.frame(v, 64, 64, 0.0001, 0.01));
}

}  // namespace
}  // namespace cellrelief::gpu
