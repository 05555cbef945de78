// SPDX-License-Identifier: MIT
// The backend-switching suite: the backend table (names, availability, reasons), then one scene
// rendered on every backend and checked against analytic answers. A backend that cannot run
// here is skipped with its reason, never passed silently.
#include <gtest/gtest.h>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>

#include "test_support.h"

namespace cellrelief::render {
namespace {

/// Exact first intersection of a ray with a sphere, or infinity.
double raySphere(const Rayd& ray, const Vec3d& centre, double radius) {
  const Vec3d o = ray.origin - centre;
  const double b = glm::dot(o, ray.direction), c = glm::dot(o, o) - radius * radius;
  const double disc = b * b - c;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  const double t = -b - std::sqrt(disc);
  return t > 0 ? t : std::numeric_limits<double>::infinity();
}

TEST(BackendTable, NamesRoundTripAndUnknownNamesListTheValidOnes) {
  for (BackendKind k : kBackendKinds) EXPECT_EQ(parseBackendKind(backendName(k)), k);
  try {
    parseBackendKind("metal");
    FAIL() << "an unknown name was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("metal"), std::string::npos) << what;
    for (BackendKind k : kBackendKinds)
      EXPECT_NE(what.find(std::string(backendName(k))), std::string::npos) << what;
  }
}

TEST(BackendTable, UnavailableBackendsSayWhyAndAutoResolvesToOneThatRuns) {
  EXPECT_TRUE(backends::isAvailable(BackendKind::Cpu));
  for (BackendKind k : kBackendKinds) {
    const Availability a = backends::isAvailable(k);
    if (a) {
      EXPECT_NO_THROW(backends::createBackend(k)) << backendName(k);
    } else {
      EXPECT_FALSE(a.reason.empty()) << backendName(k);
      try {
        backends::createBackend(k);
        FAIL() << "created an unavailable backend " << backendName(k);
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(a.reason), std::string::npos) << e.what();
      }
    }
  }
  EXPECT_TRUE(backends::isAvailable(backends::resolve(BackendKind::Auto)));
  EXPECT_EQ(backends::createBackend("auto")->kind(), backends::resolve(BackendKind::Auto));
}

TEST(BackendTable, AutoTakesAHardwareGpuElseOpenGLOnASoftwareRasterizer) {
  const BackendKind chosen = backends::resolve(BackendKind::Auto);
  bool hardware = false, softwareGl = false;
#ifdef CELLRELIEF_HAS_VULKAN
  hardware |= vulkan::probe().availability && !vulkan::probe().software;
#endif
#ifdef CELLRELIEF_HAS_OPENGL
  hardware |= gl::probe().availability && !gl::probe().software;
  softwareGl = gl::probe().availability && gl::probe().software;
#endif
  if (hardware) {
    EXPECT_NE(chosen, BackendKind::Cpu);
#ifdef CELLRELIEF_HAS_VULKAN
    if (chosen == BackendKind::Vulkan) EXPECT_FALSE(vulkan::probe().software);
#endif
#ifdef CELLRELIEF_HAS_OPENGL
    if (chosen == BackendKind::OpenGL) EXPECT_FALSE(gl::probe().software);
#endif
  } else if (softwareGl) {
    EXPECT_EQ(chosen, BackendKind::OpenGL) << "measured: OpenGL on llvmpipe, shaders cached on disk";
  }
}

/// The suite that every backend runs.
class EveryBackend : public ::testing::TestWithParam<BackendKind> {
 protected:
  void SetUp() override {
    const Availability a = backends::isAvailable(GetParam());
    // OpenGL and Vulkan come up on every Debian machine this project supports (llvmpipe and
    // lavapipe without a GPU): under CI their absence is a failure, not a skip.
    if (!a && GetParam() != BackendKind::Cpu && test::inCI())
      FAIL() << backendName(GetParam()) << " must run under CI: " << a.reason;
    if (!a) GTEST_SKIP() << backendName(GetParam()) << ": " << a.reason;
    mBackend = backends::createBackend(GetParam());
  }
  std::unique_ptr<Backend> mBackend;
};

std::shared_ptr<const relief::ReliefModel> sphereModel(const Vec3f& centre, float radius) {
  TriangleMesh mesh = makeIcosphere(6, radius);
  for (Vec3f& p : mesh.positions) p += centre;
  return std::make_shared<relief::ReliefModel>(relief::convert(mesh, {.gridSize = 4, .texels = 33}));
}

TEST_P(EveryBackend, SphereMaskDepthAndNormalsMatchTheAnalyticSphere) {
  const Scene scene = Scene::of(sphereModel(Vec3f(0), 1.0f));
  mBackend->upload(scene);
  const Camera camera = Camera::framing(Vec3d(0), 1.0, 30, 20);
  RenderOptions options;
  options.width = options.height = 96;
  const Frame frame = mBackend->renderFrame(camera, options);
  ASSERT_EQ(frame.width, 96);
  int disagreements = 0, hits = 0, badNormals = 0;
  double worstDepth = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const Rayd ray = camera.primaryRay(x, y, 96, 96);
      const double exact = raySphere(ray, Vec3d(0), 1.0);
      const double b = glm::dot(ray.origin, ray.direction);
      const double miss = std::sqrt(std::max(0.0, glm::dot(ray.origin, ray.origin) - b * b));
      if (std::abs(miss - 1.0) < 0.01) continue;  // silhouette: a sample spacing either way
      const bool hit = frame.mask.at(x, y, 0) != 0;
      if (hit != std::isfinite(exact)) {
        ++disagreements;
        continue;
      }
      EXPECT_EQ(frame.color.at(x, y, 3), hit ? 255 : 0);
      if (!hit) {
        EXPECT_TRUE(std::isinf(frame.depth.at(x, y, 0)));
        continue;
      }
      ++hits;
      worstDepth = std::max(worstDepth, std::abs(frame.depth.at(x, y, 0) - exact));
      const Vec3d n(frame.normal.at(x, y, 0), frame.normal.at(x, y, 1), frame.normal.at(x, y, 2));
      badNormals += glm::dot(n, glm::normalize(ray.at(exact))) < 0.99;
    }
  std::printf("%s: %d hits, %d disagreements, worst depth %.2e, %d normals off by > 8 degrees\n",
              std::string(backendName(GetParam())).c_str(), hits, disagreements, worstDepth, badNormals);
  EXPECT_GT(hits, 2000);
  EXPECT_EQ(disagreements, 0);
  EXPECT_LT(worstDepth, 1e-3);
  EXPECT_LE(badNormals, hits / 200);
}

TEST_P(EveryBackend, OnlyTheRequestedBuffersAreProduced) {
  mBackend->upload(Scene::of(sphereModel(Vec3f(0), 1.0f)));
  RenderOptions options;
  options.width = 40;
  options.height = 30;
  options.channels = kDepth | kMask;
  const Frame frame = mBackend->renderFrame(Camera::framing(Vec3d(0), 1.0), options);
  EXPECT_TRUE(frame.color.isEmpty());
  EXPECT_TRUE(frame.normal.isEmpty());
  ASSERT_FALSE(frame.depth.isEmpty());
  EXPECT_EQ(frame.depth.width(), 40);
  EXPECT_EQ(frame.depth.height(), 30);
  EXPECT_EQ(frame.mask.width(), 40);
}

TEST_P(EveryBackend, ShadowsFallWhereTheAnalyticOccluderCastsThem) {
  // A small sphere between a big one and the light: the shadow rays from the big sphere's lit
  // side are blocked exactly where a ray towards the light meets the small sphere.
  const DirectionalLight light;
  const Vec3d towards = glm::normalize(Vec3d(light.direction));
  const Vec3d smallCentre = 1.9 * towards;
  Scene scene;
  scene.models = {sphereModel(Vec3f(0), 1.0f), sphereModel(Vec3f(smallCentre), 0.45f)};
  scene.lights = {light};
  mBackend->upload(scene);
  const Camera camera = Camera::framing(Vec3d(0.3), 1.6, 10, 35);
  RenderOptions options;
  options.width = options.height = 96;
  const Frame lit = mBackend->renderFrame(camera, options);
  options.shadows = false;
  const Frame unshadowed = mBackend->renderFrame(camera, options);
  int shadowed = 0, checked = 0, wrong = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const Rayd ray = camera.primaryRay(x, y, 96, 96);
      const double tBig = raySphere(ray, Vec3d(0), 1.0), tSmall = raySphere(ray, smallCentre, 0.45);
      if (!std::isfinite(tBig) || tSmall < tBig || !lit.mask.at(x, y, 0)) continue;
      const Vec3d p = ray.at(tBig);
      if (glm::dot(glm::normalize(p), towards) < 0.1) continue;  // unlit or grazing anyway
      // Rays passing within a sample of the occluder's rim may go either way.
      const Vec3d toCentre = smallCentre - p;
      const double along = glm::dot(toCentre, towards);
      const double missDistance = glm::length(toCentre - along * towards);
      if (std::abs(missDistance - 0.45) < 0.03) continue;
      const bool inShadow = along > 0 && missDistance < 0.45;
      const bool darker = lit.color.at(x, y, 0) + 8 < unshadowed.color.at(x, y, 0);
      ++checked;
      shadowed += inShadow;
      wrong += inShadow != darker;
    }
  std::printf("%d pixels checked, %d in the analytic shadow, %d disagree\n", checked, shadowed, wrong);
  EXPECT_GT(shadowed, 100);
  EXPECT_LE(wrong, checked / 200);
}

TEST_P(EveryBackend, ReflectionsShowTheOtherObject) {
  Scene scene;
  scene.models = {sphereModel(Vec3f(-1.1f, 0, 0), 1.0f), sphereModel(Vec3f(1.1f, 0, 0), 1.0f)};
  mBackend->upload(scene);
  const Camera camera{Vec3d(0, 0.2, 5), Vec3d(0), Vec3d(0, 1, 0), 40};
  RenderOptions options;
  options.width = options.height = 64;
  const Frame plain = mBackend->renderFrame(camera, options);
  options.reflectionBounces = 1;
  options.reflectivity = 0.5f;
  const Frame mirrored = mBackend->renderFrame(camera, options);
  // Where the mirror ray meets the other sphere, the pixel changes; where it escapes to the
  // white background, it brightens.
  int changed = 0, hits = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (!plain.mask.at(x, y, 0)) continue;
      ++hits;
      changed += plain.color.at(x, y, 0) != mirrored.color.at(x, y, 0);
    }
  EXPECT_GT(hits, 500);
  EXPECT_GT(changed, hits / 2);
}

INSTANTIATE_TEST_SUITE_P(Backends, EveryBackend,
                         ::testing::Values(BackendKind::Cpu, BackendKind::OpenGL, BackendKind::Vulkan),
                         [](const auto& p) { return std::string(backendName(p.param)); });

}  // namespace
}  // namespace cellrelief::render
