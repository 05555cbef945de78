// SPDX-License-Identifier: MIT
// Polycube-mapped meshes on the CPU reference: a rounded box whose texture positions are known
// exactly (its own polycube's surface, warped into world space) textured with a smooth signal.
// Each pixel's colour is the signal at the pixel's texture position within the filter's blur, and
// no two neighbouring pixels differ by more than the signal changes between their texture
// positions: a seam (a wrong border texel, a squarelet read from the wrong tile) would jump.
// The backend-switching check: the same scene of polycube meshes on OpenGL and Vulkan, per pixel
// against the CPU reference.
#include <gtest/gtest.h>

#include <cmath>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/render/frame_comparison.h>

#include "backends/failure_images.h"
#include "test_support.h"

namespace cellrelief::render {
namespace {

/// 0.6 + 0.35 sin(2 pi a_k.p / 2) per channel: smooth, away from 0 (where display gamma is steep).
constexpr double kPeriod = 2.0;
constexpr double kAxes[3][3] = {{0.8, 0.5, 0.33}, {-0.3, 0.9, 0.3}, {0.45, -0.4, 0.8}};
/// Its Lipschitz constant per channel, in cubes: 0.35 * 2 pi * |a| / period, |a| <= 1.03.
const double kGradient = 0.35 * 2 * M_PI * 1.03 / kPeriod;

Vec3d signalAt(const Vec3d& p) {
  Vec3d c;
  for (int k = 0; k < 3; ++k)
    c[k] = 0.6 + 0.35 * std::sin(2 * M_PI * (kAxes[k][0] * p.x + kAxes[k][1] * p.y + kAxes[k][2] * p.z) / kPeriod);
  return c;
}

// Bounds of the GPU comparison. Measured on llvmpipe and lavapipe (two views, 8,726 and 12,181
// pixels hit): no mask disagreement, depth p95 under 2e-7 and at most 4e-6 diagonals (float
// rounding), normals identical, colour mean 0.04-0.09 and p99 1 of 255 (the hardware's bilinear
// weights are 8-bit fixed point). The bounds leave room for another driver's rounding while
// catching a wrong texel, squarelet or level, which moves colours by tens of levels.
constexpr double kMaskBound = 1e-3, kDepthBound = 1e-2, kNormalBound = 0.05;
constexpr double kMeanColourBound = 0.5, kP99ColourBound = 3;

/// A 3 x 2 x 2 box of cubes, its surface subdivided and pushed halfway to an ellipsoid: world
/// positions curve, texture positions stay exactly on the polycube's surface.
std::shared_ptr<const polycube::TexturedMesh> roundedBox(int texels) {
  std::vector<Vec3i> cubes;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) cubes.push_back({x, y, z});
  auto surface = std::make_shared<const polycube::PolycubeSurface>(polycube::Polycube(cubes));
  // Midpoints of small integers, exact in float: the texture positions stay on the surface.
  TriangleMesh faces = surface->polycube().surfaceMesh();
  splitTrianglesInFour(faces, 4, [](const Vec3f& a, const Vec3f& b) { return 0.5f * (a + b); });
  auto out = std::make_shared<polycube::TexturedMesh>();
  const Vec3d centre(1.5, 1.0, 1.0);
  for (const Vec3f& corner : faces.positions) {
    const Vec3d p(corner);
    const Vec3d d = p - centre;
    const Vec3d ellipsoid = glm::normalize(d / Vec3d(1.5, 1, 1)) * Vec3d(1.5, 1, 1) * 1.2;
    out->mesh.positions.push_back(Vec3f(0.5 * (d + ellipsoid)));
    out->texture.push_back(Vec3f(p));
  }
  out->mesh.triangles = faces.triangles;
  const polycube::SurfaceSignal signal = [](const Vec3d& p, const Vec3d&) { return Vec4f(Vec3f(signalAt(p)), 1.0f); };
  out->t2 = std::make_shared<const polycube::PolycubeTexture>(surface, signal, polycube::TextureOptions{texels});
  return out;
}

/// Lit by ambient light alone, so a pixel's colour is the texel's (before display gamma).
Scene unlit(std::shared_ptr<const polycube::TexturedMesh> mesh) {
  Scene scene;
  scene.polycubeMeshes.push_back(std::move(mesh));
  scene.lights.clear();
  scene.ambient = Vec3f(1.0f);
  return scene;
}

double linear(std::uint8_t display) { return std::pow(display / 255.0, 2.2); }

TEST(PolycubeRendering, PixelsShowTheSignalAndNeighboursNeverJumpAcrossSquarelets) {
  const int texels = 16;
  const auto mesh = roundedBox(texels);
  const Scene scene = unlit(mesh);
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  const Aabbd bounds = scene.boundsWS();
  RenderOptions options;
  options.width = options.height = 240;
  options.channels = FrameChannel::kColor | FrameChannel::kMask;
  std::size_t hits = 0, sharp = 0, pairs = 0, tested = 0;
  double worstExcess = -1, worstPixel = 0;
  for (double yaw : {35.0, 125.0, 250.0}) {
    const Camera camera = Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), yaw, 25);
    const Frame frame = cpu.renderFrame(camera, options);
    // The texture position and the level of every pixel, from the tracer itself.
    const trace::PolycubeTracer tracer(mesh);
    const Camera::FloatFrame rays = camera.floatFrame(options.width, options.height);
    const float spread = 2.0f * glm::length(rays.up) / float(options.height);
    std::vector<trace::PolycubeTracer::Hit> at(std::size_t(options.width) * options.height);
    for (int y = 0; y < options.height; ++y)
      for (int x = 0; x < options.width; ++x) at[std::size_t(y) * options.width + x] = tracer.intersect(rays.ray(x, y), spread);
    const auto colour = [&](int x, int y) {
      return Vec3d(linear(frame.color.at(x, y, 0)), linear(frame.color.at(x, y, 1)), linear(frame.color.at(x, y, 2)));
    };
    for (int y = 0; y < options.height; ++y)
      for (int x = 0; x < options.width; ++x) {
        const trace::PolycubeTracer::Hit& h = at[std::size_t(y) * options.width + x];
        ASSERT_EQ(frame.mask.at(x, y, 0) != 0, h.valid());
        if (!h.valid()) continue;
        ++hits;
        // Within a texel of the level read: the blur of a sine is at most its gradient times that.
        const double texel = std::exp2(std::clamp(double(h.lod), 0.0, 4.0)) * 0.5 / texels;
        if (h.lod <= 1) ++sharp;
        const Vec3d error = glm::abs(colour(x, y) - signalAt(Vec3d(h.texture)));
        const double allowed = kGradient * 1.5 * texel + 0.012;
        const double excess = std::max({error.x, error.y, error.z}) - allowed;
        if (excess > worstExcess) worstExcess = excess, worstPixel = y * options.width + x;
        EXPECT_LE(excess, 0) << "pixel (" << x << ", " << y << "), lod " << h.lod;
        // Neighbours: the colour changes no more than the signal between their texture positions.
        for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
          if (x + dx >= options.width || y + dy >= options.height) continue;
          const trace::PolycubeTracer::Hit& n = at[std::size_t(y + dy) * options.width + x + dx];
          if (!n.valid()) continue;
          ++pairs;
          const double texelBoth = std::exp2(std::clamp(double(std::max(h.lod, n.lod)), 0.0, 4.0)) * 0.5 / texels;
          const double bound = kGradient * (glm::length(Vec3d(h.texture - n.texture)) + 3 * texelBoth) + 0.012;
          const Vec3d jump = glm::abs(colour(x, y) - colour(x + dx, y + dy));
          ++tested;
          EXPECT_LE(std::max({jump.x, jump.y, jump.z}), bound) << "a jump between pixels (" << x << ", " << y << ") and ("
                                                              << x + dx << ", " << y + dy << ")";
        }
      }
  }
  std::printf("%zu pixels hit, %zu at lod <= 1, %zu neighbour pairs; worst colour error %.4f under its bound (pixel %g)\n",
              hits, sharp, pairs, -worstExcess, worstPixel);
  EXPECT_GT(hits, 3 * 240u * 240u / 4);
  EXPECT_GT(sharp, hits / 2) << "most pixels should read the finest levels";
  EXPECT_GT(tested, hits);
}

TEST(PolycubeRendering, NormalMapsReplaceTheVertexNormals) {
  auto mesh = std::make_shared<polycube::TexturedMesh>(*roundedBox(8));
  // T2 of one constant normal: every pixel's normal buffer shows it.
  const Vec3f up = glm::normalize(Vec3f(0.2f, 1.0f, 0.1f));
  mesh->t2 = std::make_shared<const polycube::PolycubeTexture>(
      mesh->t2->sharedSurface(), [&](const Vec3d&, const Vec3d&) { return Vec4f(0.5f + 0.5f * up, 1.0f); },
      polycube::TextureOptions{8});
  mesh->use = polycube::TextureUse::Normal;
  Scene scene = unlit(mesh);
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  RenderOptions options;
  options.width = options.height = 64;
  options.channels = FrameChannel::kNormal | FrameChannel::kMask;
  const Aabbd bounds = scene.boundsWS();
  const Camera camera = Camera::framing(bounds.center(), 0.5 * bounds.diagonal());
  const Frame frame = cpu.renderFrame(camera, options);
  std::size_t hits = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (!frame.mask.at(x, y, 0)) continue;
      ++hits;
      const Vec3f n(frame.normal.at(x, y, 0), frame.normal.at(x, y, 1), frame.normal.at(x, y, 2));
      EXPECT_GT(std::abs(glm::dot(n, up)), 0.999f) << "pixel (" << x << ", " << y << ")";
    }
  EXPECT_GT(hits, 1000u);
}

/// Four cubes in a skew path, so that one vertex, (1, 1, 1), is of case 6b. The texture
/// positions are pushed off the surface by a smooth field of up to 0.26 cubes: there P is not the
/// identity (as it is on the rounded boxes, whose positions lie on the surface), so every pixel
/// checks the backends' P against the CPU's.
std::shared_ptr<const polycube::TexturedMesh> skewPathOffTheSurface(int texels) {
  const std::vector<Vec3i> cubes{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
  auto surface = std::make_shared<const polycube::PolycubeSurface>(polycube::Polycube(cubes));
  EXPECT_FALSE(polycube::verticesOfCase(surface->polycube(), polycube::VertexCase::k6b).empty());
  TriangleMesh faces = surface->polycube().surfaceMesh();
  splitTrianglesInFour(faces, 3, [](const Vec3f& a, const Vec3f& b) { return 0.5f * (a + b); });
  auto out = std::make_shared<polycube::TexturedMesh>();
  for (const Vec3f& corner : faces.positions) {
    const Vec3d p(corner);
    out->mesh.positions.push_back(corner);
    const Vec3d offset(std::sin(2.1 * p.y + 0.3), std::sin(1.7 * p.z + 1.0), std::sin(2.3 * p.x + 2.0));
    out->texture.push_back(Vec3f(p + 0.15 * offset));
  }
  out->mesh.triangles = faces.triangles;
  // The signal four times finer (a period of half a cube): a point P puts a tenth of a cube
  // astray reads a colour tens of levels off.
  const polycube::SurfaceSignal signal = [](const Vec3d& p, const Vec3d&) {
    return Vec4f(Vec3f(signalAt(4.0 * p)), 1.0f);
  };
  out->t2 = std::make_shared<const polycube::PolycubeTexture>(surface, signal, polycube::TextureOptions{texels});
  return out;
}

/// Three boxes side by side: T2 as colour read trilinearly, the same T2 read bilinearly (one
/// texture shared by two meshes), and a normal map read by nearest texel; default light, shadows.
Scene threeBoxes() {
  const auto colour = roundedBox(16);
  auto bilinear = std::make_shared<polycube::TexturedMesh>(*colour);
  bilinear->filter = polycube::TextureFilter::Bilinear;
  for (Vec3f& p : bilinear->mesh.positions) p += Vec3f(3.2f, 0.0f, 0.0f);
  auto normals = std::make_shared<polycube::TexturedMesh>(*colour);
  normals->filter = polycube::TextureFilter::Nearest;
  normals->use = polycube::TextureUse::Normal;
  normals->t2 = std::make_shared<const polycube::PolycubeTexture>(
      colour->t2->sharedSurface(),
      [](const Vec3d& p, const Vec3d& n) {
        const Vec3d bumped = glm::normalize(n + 0.3 * Vec3d(std::sin(4 * p.y), std::sin(4 * p.z), std::sin(4 * p.x)));
        return Vec4f(Vec3f(0.5 + 0.5 * bumped), 1.0f);
      },
      polycube::TextureOptions{8});
  for (Vec3f& p : normals->mesh.positions) p += Vec3f(-3.2f, 0.0f, 0.0f);
  Scene scene;
  scene.polycubeMeshes = {colour, bilinear, normals};
  return scene;
}

// Measured on llvmpipe and lavapipe (2 views of 240 x 160): see the bounds' comment above.
TEST(PolycubeRendering, GpuBackendsAgreeWithTheCpuReferencePerPixel) {
  const Scene scene = threeBoxes();
  RenderOptions options;
  options.width = 240;
  options.height = 160;
  const Aabbd bounds = scene.boundsWS();
  const Camera cameras[2] = {Camera::framing(bounds.center(), 0.3 * bounds.diagonal(), 20, 25),
                             Camera::framing(bounds.center(), 0.35 * bounds.diagonal(), 160, -20)};
  const test::AgreementBounds agreement{.minHits = 5000, .mask = kMaskBound, .depthP95 = kDepthBound,
                                        .normalP95 = kNormalBound, .meanColour = kMeanColourBound,
                                        .p99Colour = kP99ColourBound, .sameCells = true};
  if (test::expectGpuBackendsAgree(scene, cameras, options, 1e-3 * bounds.diagonal(), agreement, "polycube") == 0 &&
      !test::inCI())
    GTEST_SKIP() << "no GPU backend runs here";
}

// Close to the case-6b vertex, from its empty side: most pixels' texture positions fall in its
// dual cell, off the surface on either side, so they check the GLSL P of case 6b. Measured on
// llvmpipe and lavapipe (2 views of 160 x 160, 22,836 and 22,829 pixels hit): colour mean 0.24
// and p99 1 of 255, depth and normals as above. With the empty side's rotation written wrong in
// the shader, the mean is 5.1-6.8 and the p99 42-53.
TEST(PolycubeRendering, GpuBackendsAgreeWithTheCpuReferenceAroundACase6bVertex) {
  Scene scene;
  scene.polycubeMeshes = {skewPathOffTheSurface(16)};
  RenderOptions options;
  options.width = options.height = 160;
  const Vec3d saddle(1.0, 1.0, 1.0);
  const Camera cameras[2] = {Camera::framing(saddle, 0.6, -45, 20), Camera::framing(saddle, 0.6, -60, -25)};
  const test::AgreementBounds agreement{.minHits = 5000, .mask = kMaskBound, .depthP95 = kDepthBound,
                                        .normalP95 = kNormalBound, .meanColour = kMeanColourBound,
                                        .p99Colour = kP99ColourBound, .sameCells = true};
  if (test::expectGpuBackendsAgree(scene, cameras, options, 1e-3 * scene.boundsWS().diagonal(), agreement,
                                   "polycube 6b") == 0 &&
      !test::inCI())
    GTEST_SKIP() << "no GPU backend runs here";
}

}  // namespace
}  // namespace cellrelief::render
