// SPDX-License-Identifier: MIT
// Geometry textures: charts, boxes and maps; the ray caster against the meshes they come from
// (the core BVH on the original triangles) and against analytic shapes; the .cgt file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include <cellrelief/core/bvh.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/geotex/charts.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/geotex/geotex_file.h>
#include <cellrelief/geotex/reconstruct.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/geometric_error.h>
#include <cellrelief/trace/geotex_tracer.h>

#include "geotex/geotex_test_meshes.h"
#include "test_support.h"

namespace cellrelief::geotex {
namespace {

using trace::GeoTexTracer;

TEST(GeoTexCharts, TheRingAddsTheFacesAroundEachRegion) {
  const TriangleMesh cube = test::makeCube(-1, 1, 1);
  VsaOptions o;
  o.proxies = 6;
  const VsaPartition p = partitionVsa(cube, o);
  const auto none = chartFaces(cube, p, 0), one = chartFaces(cube, p, 1);
  ASSERT_EQ(one.size(), 6u);
  for (std::size_t c = 0; c < 6; ++c) {
    EXPECT_EQ(none[c].faces.size(), none[c].ownCount);
    EXPECT_EQ(one[c].ownCount, none[c].ownCount);
    // The ring, by brute force: every other face with a corner at a position of a region face.
    std::set<std::uint32_t> expected(none[c].faces.begin(), none[c].faces.end());
    for (std::uint32_t f = 0; f < cube.triangles.size(); ++f)
      for (const std::uint32_t g : none[c].faces)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            if (cube.positions[cube.triangles[f][a]] == cube.positions[cube.triangles[g][b]]) expected.insert(f);
    EXPECT_EQ(std::set<std::uint32_t>(one[c].faces.begin(), one[c].faces.end()), expected) << "chart " << c;
    EXPECT_GT(one[c].faces.size(), one[c].ownCount);
    std::vector<std::uint32_t> sorted = one[c].faces;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a face twice";
  }
}

TEST(GeoTexCharts, FramesAreRightHandedAndBoxesHoldTheirVertices) {
  const TriangleMesh torus = makeTorus(1.0f, 0.4f, 64, 32);
  GeoTexOptions o;
  o.vsa.proxies = 30;
  o.maxTexels = 32;
  const GeoTexConversion r = convertMesh(torus, o);
  ASSERT_EQ(r.model.charts.size(), 30u);
  const auto faces = chartFaces(torus, r.partition, o.rings);
  for (std::size_t c = 0; c < r.model.charts.size(); ++c) {
    const ChartBox& b = r.model.charts[c];
    EXPECT_NEAR(glm::dot(glm::cross(b.axisWS[0], b.axisWS[1]), b.axisWS[2]), 1.0, 1e-12);
    EXPECT_TRUE(std::has_single_bit(b.width) && std::has_single_bit(b.height));
    EXPECT_LE(std::max(b.width, b.height), 32u);
    for (const std::uint32_t f : faces[c].faces)
      for (int k = 0; k < 3; ++k) {
        const Vec3d p = b.toChart(Vec3d(torus.positions[torus.triangles[f][k]]));
        EXPECT_GE(p.x, -1e-9);
        EXPECT_LE(p.x, b.width + 1e-9);
        EXPECT_GE(p.y, -1e-9);
        EXPECT_LE(p.y, b.height + 1e-9);
        EXPECT_GE(p.z, -1e-9);
        EXPECT_LE(p.z, b.sizeWS.z + 1e-9);
      }
  }
  // The median normal is the chart's own normal on a torus (no folds with 30 charts).
  EXPECT_EQ(r.foldedFaces(), 0u);
}

/// Hit/miss disagreement and depth error of the geometry textures against the mesh's own BVH.
struct Agreement {
  std::size_t rays = 0, bothHit = 0, onlyReference = 0, onlyOurs = 0, interiorMisses = 0;
  std::size_t backFaces = 0;  // reference hits on the inner side, seen through a hole
  std::vector<double> depthError;  // |t - t_ref|, rays both hit
  double median() {
    std::sort(depthError.begin(), depthError.end());
    return depthError.empty() ? 0 : depthError[depthError.size() / 2];
  }
  double quantile(double q) {
    std::sort(depthError.begin(), depthError.end());
    return depthError.empty() ? 0 : depthError[std::size_t(q * (depthError.size() - 1))];
  }
};

Agreement compare(const TriangleMesh& mesh, const GeoTexModel& model, int side, int views) {
  const std::vector<Vec3d> positions(mesh.positions.begin(), mesh.positions.end());
  const TriangleBvh<double> reference(positions, mesh.triangles);
  const GeoTexTracer<double> tracer(model);
  const auto rays = test::viewRays(mesh.surfaceBounds(), side, views);
  std::vector<Hitd> ours(rays.size()), ref(rays.size());
  parallelFor(0, rays.size(), [&](std::size_t i) {
    ours[i] = tracer.intersect(rays[i]);
    ref[i] = reference.closestHit(rays[i]);
  });
  Agreement a;
  a.rays = rays.size();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (ours[i].valid() && ref[i].valid()) {
      ++a.bothHit;
      a.depthError.push_back(std::abs(ours[i].t - ref[i].t));
    } else if (ref[i].valid() && glm::dot(rays[i].direction, ref[i].geometricNormal) > 0) {
      // A one-sided representation (a solid below each height field) has no inner side.
      ++a.backFaces;
    } else if (ref[i].valid()) {
      ++a.onlyReference;
      // A miss whose eight neighbours all hit the mesh: a crack, not a silhouette.
      const std::size_t pixel = i % std::size_t(side * side), x = pixel % side, y = pixel / side;
      bool interior = x > 0 && y > 0 && x + 1 < std::size_t(side) && y + 1 < std::size_t(side);
      for (int dy = -1; dy <= 1 && interior; ++dy)
        for (int dx = -1; dx <= 1 && interior; ++dx)
          interior = ref[i + dy * side + dx].valid();
      a.interiorMisses += interior;
    } else if (ours[i].valid()) {
      ++a.onlyOurs;
    }
  }
  return a;
}

TEST(GeoTexTracer, SphereMatchesItsMeshWithoutCracks) {
  const TriangleMesh sphere = makeIcosphere(4);
  GeoTexOptions o;
  o.vsa.proxies = 24;
  o.maxTexels = 64;
  const GeoTexConversion r = convertMesh(sphere, o);
  Agreement a = compare(sphere, r.model, 96, 6);
  const double texel = 2.0 / 64;  // the largest chart spans at most the diameter
  EXPECT_EQ(a.interiorMisses, 0u);
  EXPECT_LT(a.median(), 0.1 * texel);
  EXPECT_LT(a.quantile(0.99), texel);
  // Silhouette pixels may go either way; they are a thin ring of the image.
  EXPECT_LT(double(a.onlyReference + a.onlyOurs) / a.rays, 0.01);
}

TEST(GeoTexTracer, WithoutTheRingCracksOpenBetweenCharts) {
  // The ring is what closes the surface: the same conversion without it misses rays inside the
  // silhouette, along the charts' borders.
  const TriangleMesh sphere = makeIcosphere(4);
  GeoTexOptions o;
  o.vsa.proxies = 24;
  o.maxTexels = 64;
  o.rings = 0;
  Agreement a = compare(sphere, convertMesh(sphere, o).model, 96, 6);
  EXPECT_GT(a.interiorMisses, 0u);
}

TEST(GeoTexTracer, CubeFacesAreFlatChartsHitExactly) {
  const TriangleMesh cube = test::makeCube(-1, 1, 2);
  GeoTexOptions o;
  o.vsa.proxies = 6;
  o.maxTexels = 16;
  const GeoTexConversion r = convertMesh(cube, o);
  const GeoTexTracer<double> tracer(r.model);
  // Straight down onto the top face, and slanted rays onto two sides.
  for (int i = 0; i < 50; ++i) {
    const double x = -0.9 + 1.8 * i / 49.0;
    const Hitd top = tracer.intersect(Rayd(Vec3d(x, 0.3, 5), Vec3d(0, 0, -1)));
    ASSERT_TRUE(top.valid()) << x;
    EXPECT_NEAR(top.t, 4.0, 1e-4);
    // Vertex normals are averaged across the cube's edges: only the face's inner part is flat.
    if (std::abs(x) <= 0.5) EXPECT_NEAR(top.geometricNormal.z, 1.0, 1e-3) << x;
    const Rayd slanted(Vec3d(3, x, 0.2), glm::normalize(Vec3d(-1, 0, 0.3)));
    const Hitd side = tracer.intersect(slanted);
    ASSERT_TRUE(side.valid()) << x;
    EXPECT_NEAR(slanted.at(side.t).x, 1.0, 1e-4);
  }
  EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(0, 0, 5), Vec3d(0, 0, 1))).valid());
  EXPECT_TRUE(tracer.occluded(Rayd(Vec3d(0, 0, 5), Vec3d(0, 0, -1))));
  // A ray starting inside the solid, going out, crosses no surface from above.
  EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(0, 0, 0), Vec3d(0, 0, 1))).valid());
}

TEST(GeoTexTracer, GrazingRaysTakeMoreStepsThanSteepOnes) {
  // One chart (a gentle DEM): a steep ray crosses few texels and takes few linear steps, a
  // grazing one takes about one per texel it passes.
  Image<std::uint16_t> dem(64, 64, 1);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) dem.at(i, j, 0) = quantizeUnorm<std::uint16_t>(0.5 + 0.2 * std::sin(0.2 * i + 0.1 * j));
  const GeoTexModel model = heightMapModel(dem, {.width = 2, .depth = 2, .height = 0.2});
  const GeoTexTracer<double> tracer(model, {.skipSteps = false});  // the paper's search alone
  trace::GeoTexTraceStats steep, grazing;
  EXPECT_TRUE(tracer.intersect(Rayd(Vec3d(1, 1, 5), glm::normalize(Vec3d(0.01, 0, -1))), &steep).valid());
  // Level, just above the highest point: it crosses the whole map.
  EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(-1, 1, 0.17), Vec3d(1, 0, 0)), &grazing).valid());
  EXPECT_EQ(steep.boxes, 1u);
  EXPECT_LE(steep.samples, 3u + 1u + 8u);  // the fewest linear steps, the binary search
  EXPECT_GT(grazing.samples, 4 * steep.samples);
}

TEST(GeoTexHeightMap, ADemIsOneChartAndRaysReadItsHeights) {
  // A synthetic DEM: heights from a smooth function, 16-bit.
  const int w = 96, h = 64;
  Image<std::uint16_t> dem(w, h, 1);
  auto f = [](double x, double y) { return 0.5 + 0.4 * std::sin(6 * x) * std::cos(4 * y); };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) dem.at(i, j, 0) = quantizeUnorm<std::uint16_t>(f((i + 0.5) / w, 1 - (j + 0.5) / h));
  const HeightMapExtent extent{.width = 3, .depth = 2, .height = 0.5};
  const GeoTexModel model = heightMapModel(dem, extent);
  ASSERT_EQ(model.charts.size(), 1u);
  EXPECT_EQ(model.charts[0].width, std::uint32_t(w));
  const GeoTexTracer<double> tracer(model);
  const double pad = 0.5 * std::min(3.0 / w, 2.0 / h);
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    // Vertical rays at texel centres read the stored height exactly (up to 16-bit codes).
    const int i = (k * 37) % w, j = (k * 11) % h;
    const double x = (i + 0.5) / w, y = (j + 0.5) / h;
    const Hitd hit = tracer.intersect(Rayd(Vec3d(3 * x, 2 * y, 10), Vec3d(0, 0, -1)));
    ASSERT_TRUE(hit.valid());
    worst = std::max(worst, std::abs((10 - hit.t) - (pad + 0.5 * f(x, y))));
  }
  EXPECT_LT(worst, 1e-4);
}

TEST(GeoTexReconstruct, ADemBecomesItsTexelCentresAtTheHeightsTheTracerReads) {
  const int w = 40, h = 30;
  Image<std::uint16_t> dem(w, h, 1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      dem.at(i, j, 0) = quantizeUnorm<std::uint16_t>(0.5 + 0.4 * std::sin(0.3 * i) * std::cos(0.2 * j));
  const GeoTexModel model = heightMapModel(dem, {.width = 4, .depth = 3, .height = 0.6});
  const TriangleMesh mesh = reconstruct(model);
  ASSERT_EQ(mesh.positions.size(), std::size_t(w * h));
  EXPECT_EQ(mesh.triangles.size(), std::size_t(2 * (w - 1) * (h - 1)));
  const GeoTexTracer<double> tracer(model);
  double worst = 0;
  for (const Vec3f& p : mesh.positions) {
    const Hitd hit = tracer.intersect(Rayd(Vec3d(p.x, p.y, 10), Vec3d(0, 0, -1)));
    ASSERT_TRUE(hit.valid());
    worst = std::max(worst, std::abs((10 - hit.t) - double(p.z)));
  }
  EXPECT_LT(worst, 1e-5);
  for (const Vec3u& t : mesh.triangles) {  // facing up, the box's +z
    const Vec3f n = glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
    ASSERT_GT(n.z, 0.0f);
  }
}

TEST(GeoTexReconstruct, TheChartsOfASphereLieOnItAndCoverIt) {
  // Two-sided: every point of the sphere's mesh is near the charts' surface (the rings close the
  // borders) and every point of the charts near the sphere; a chart missing or misplaced would
  // move the Hausdorff distance by its own size.
  const TriangleMesh sphere = makeIcosphere(4);
  GeoTexOptions o;
  o.vsa.proxies = 24;
  o.maxTexels = 64;
  const TriangleMesh charts = reconstruct(convertMesh(sphere, o).model);
  const double texel = 2.0 / 64;
  const metrics::SurfaceError e = metrics::surfaceError(sphere, metrics::DistanceField(sphere), charts, 20000);
  EXPECT_LT(e.aToB.max, 0.1 * texel);  // measured 0.014 texel each way, RMS 0.002
  EXPECT_LT(e.bToA.max, 0.1 * texel);
  EXPECT_LT(e.rms(), 0.01 * texel);
  // Without its rings the union leaves gaps along chart borders, which the sphere's side sees.
  o.rings = 0;
  const TriangleMesh bare = reconstruct(convertMesh(sphere, o).model);
  EXPECT_GT(metrics::surfaceError(sphere, metrics::DistanceField(sphere), bare, 20000).aToB.max, e.aToB.max);
}

TEST(GeoTexHeightMap, RefusesWhatIsNotAHeightMap) {
  EXPECT_THROW(heightMapModel(Image<std::uint8_t>(1, 5, 1), {}), Error);
  EXPECT_THROW(heightMapModel(Image<std::uint8_t>(8, 8, 1), {.width = 0}), Error);
  EXPECT_THROW(heightMapModel(Image<std::uint8_t>(8, 8, 1), {.height = std::nan("")}), Error);
}

TEST(GeoTexConvert, RefusesBadOptions) {
  const TriangleMesh cube = test::makeCube();
  GeoTexOptions o;
  o.maxTexels = 100;
  EXPECT_THROW(convertMesh(cube, o), Error);
  o = {};
  o.heightBits = 12;
  EXPECT_THROW(convertMesh(cube, o), Error);
}

TEST(GeoTexFile, RoundTripIsBitExact) {
  cellrelief::test::TempDir dir;
  TriangleMesh sphere = makeIcosphere(3);
  sphere.colors.resize(sphere.positions.size());
  for (std::size_t v = 0; v < sphere.positions.size(); ++v)
    sphere.colors[v] = Color8(glm::clamp(Vec3f(127.5f) * (sphere.positions[v] + 1.0f), 0.0f, 255.0f), 255);
  for (const int bits : {8, 16}) {
    GeoTexOptions o;
    o.vsa.proxies = 10;
    o.maxTexels = 32;
    o.heightBits = bits;
    const GeoTexModel model = convertMesh(sphere, o).model;
    ASSERT_TRUE(model.hasColors());
    const auto path = dir / ("sphere" + std::to_string(bits) + ".cgt");
    writeGeoTex(model, path);
    const GeoTexModel back = readGeoTex(path);
    EXPECT_EQ(back.heights, model.heights);
    EXPECT_EQ(back.normals, model.normals);
    EXPECT_EQ(back.colors, model.colors);
    ASSERT_EQ(back.charts.size(), model.charts.size());
    for (std::size_t c = 0; c < model.charts.size(); ++c) {
      EXPECT_EQ(back.charts[c].originWS, model.charts[c].originWS);
      EXPECT_EQ(back.charts[c].sizeWS, model.charts[c].sizeWS);
      EXPECT_EQ(back.charts[c].firstTexel, model.charts[c].firstTexel);
    }
    const auto again = dir / "again.cgt";
    writeGeoTex(back, again);
    EXPECT_EQ(cellrelief::test::readBytes(again), cellrelief::test::readBytes(path));
    EXPECT_EQ(std::filesystem::file_size(path), model.byteSize() + 72 + 4);
  }
}

TEST(GeoTexFile, DamagedFilesAreRefusedWithTheFileAndTheProblem) {
  cellrelief::test::TempDir dir;
  GeoTexOptions o;
  o.vsa.proxies = 6;
  o.maxTexels = 8;
  const auto good = dir / "good.cgt";
  writeGeoTex(convertMesh(test::makeCube(), o).model, good);
  const std::string bytes = cellrelief::test::readBytes(good);
  auto expectRefused = [&](const std::string& name, const std::string& content, const std::string& problem) {
    const auto path = dir / name;
    cellrelief::test::writeBytes(path, content);
    try {
      readGeoTex(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::FileFormat) << name;
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
  };
  expectRefused("short.cgt", bytes.substr(0, 8), "too short");
  expectRefused("magic.cgt", "X" + bytes.substr(1), "magic");
  expectRefused("truncated.cgt", bytes.substr(0, bytes.size() - 10), "truncated");
  expectRefused("trailing.cgt", bytes + "x", "trailing");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  expectRefused("flipped.cgt", flipped, "checksum");
  std::string version = bytes;
  version[8] = 9;
  expectRefused("version.cgt", version, "version");
  EXPECT_THROW(readGeoTex(dir / "missing.cgt"), Error);
  // A write that cannot happen leaves nothing behind.
  EXPECT_THROW(writeGeoTex(readGeoTex(good), dir / "no_such_folder" / "x.cgt"), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "no_such_folder"));
}

TEST(GeoTexTracer, BunnyMatchesItsMesh) {
  const auto path = cellrelief::test::dataDir() / "meshes/medium/stanford-bunny__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh bunny = io::readMesh(path);
  GeoTexOptions o;
  o.vsa.proxies = cellrelief::test::kSlowBuild ? 60 : 200;
  o.maxTexels = 64;
  const GeoTexConversion r = convertMesh(bunny, o);
  Agreement a = compare(bunny, r.model, cellrelief::test::kSlowBuild ? 64 : 160, 6);
  const double texel = bunny.surfaceBounds().diagonal() / 64;
  std::printf("bunny: %zu charts, %zu folded faces, %llu empty texels of %llu; rays %zu, both %zu, only mesh %zu, "
              "only ours %zu, interior misses %zu, back faces %zu, median depth error %.3g texels, p99 %.3g\n",
              r.model.charts.size(), r.foldedFaces(), (unsigned long long)r.emptyTexels(),
              (unsigned long long)r.model.texelCount(), a.rays, a.bothHit, a.onlyReference, a.onlyOurs,
              a.interiorMisses, a.backFaces, a.median() / texel, a.quantile(0.99) / texel);
  EXPECT_LT(a.median(), 0.1 * texel);
  EXPECT_LT(double(a.interiorMisses) / a.rays, 1e-3);
  EXPECT_LT(double(a.onlyReference + a.onlyOurs) / a.rays, 0.02);
}

/// Every ray's hit by the search with and without skipping (t, chart, chart point), and their
/// height evaluations in all.
struct SkipComparison {
  std::size_t rays = 0, hits = 0, differing = 0;
  std::uint64_t samplesWithout = 0, samplesWith = 0, nodes = 0;
};

SkipComparison compareSkipping(const GeoTexModel& model, const std::vector<Rayd>& rays) {
  const GeoTexTracer<double> plain(model, {.skipSteps = false}), skipping(model);
  SkipComparison r;
  r.rays = rays.size();
  for (const Rayd& ray : rays) {
    trace::GeoTexTraceStats a, b;
    const Hitd without = plain.intersect(ray, &a), with = skipping.intersect(ray, &b);
    r.samplesWithout += a.samples;
    r.samplesWith += b.samples;
    r.nodes += b.nodes;
    r.hits += without.valid();
    const bool same = without.valid() == with.valid() &&
                      (!without.valid() || (without.t == with.t && without.primId == with.primId &&
                                            without.u == with.u && without.v == with.v));
    r.differing += !same;
    EXPECT_EQ(plain.occluded(ray), skipping.occluded(ray));
  }
  return r;
}

/// Views of the model, and rays from anywhere around it in any direction (grazing ones, ones
/// starting inside boxes and below surfaces among them).
std::vector<Rayd> viewAndRandomRays(const Aabbd& bounds, int side, std::size_t random) {
  std::vector<Rayd> rays = test::viewRays(Aabbf(Vec3f(bounds.min), Vec3f(bounds.max)), side, 6);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.25, 1.25), n(-1, 1);
  for (std::size_t k = 0; k < random; ++k) {
    const Vec3d o = bounds.min + Vec3d(u(rng), u(rng), u(rng)) * bounds.extent();
    Vec3d d(n(rng), n(rng), n(rng));
    if (k % 4 == 0) d.z *= 1e-3;  // nearly level: long runs above a terrain's surface
    if (glm::length(d) > 0) rays.emplace_back(o, glm::normalize(d));
  }
  return rays;
}

// The pyramids pass over steps wholly above or wholly below the surface only: the same hits, bit for bit, as the
// paper's search, with fewer height evaluations, on a scanned mesh's charts and on a real DEM
// (2624 x 1756 texels, not a power of two).
TEST(GeoTexTracer, SkippingFindsTheSameHitsWithFewerSamples) {
  const auto bunnyPath = cellrelief::test::dataDir() / "meshes/medium/stanford-bunny__common-3d-test-models.obj";
  const auto demPath = cellrelief::test::dataDir() / "heightmaps/terrain/iceland_heightmap.png";
  CELLRELIEF_REQUIRE_FILE(bunnyPath);
  CELLRELIEF_REQUIRE_FILE(demPath);
  GeoTexOptions o;
  o.vsa.proxies = 60;
  o.maxTexels = 64;
  const GeoTexModel bunny = convertMesh(io::readMesh(bunnyPath), o).model;
  const io::ImageFile image = io::readImage(demPath);
  const GeoTexModel dem = std::visit(
      [](const auto& pixels) { return heightMapModel(pixels, {.width = 2.624, .depth = 1.756, .height = 0.3}); },
      image.pixels);
  const int side = cellrelief::test::kSlowBuild ? 48 : 96;
  struct Case {
    const char* name;
    const GeoTexModel* model;
    double fewer;  // at least this many times fewer samples; measured 1.71x and 36.1x
  };
  for (const auto& [name, model, fewer] : {Case{"bunny", &bunny, 1.5}, Case{"iceland", &dem, 20}}) {
    const SkipComparison r = compareSkipping(*model, viewAndRandomRays(model->boundsWS(), side, side * side));
    std::printf("%s: %zu rays, %zu hits, %zu differ; height samples %llu -> %llu (%.2fx fewer), pyramid nodes %llu\n",
                name, r.rays, r.hits, r.differing, (unsigned long long)r.samplesWithout,
                (unsigned long long)r.samplesWith, double(r.samplesWithout) / double(r.samplesWith),
                (unsigned long long)r.nodes);
    EXPECT_GT(r.hits, r.rays / 10) << name;
    EXPECT_EQ(r.differing, 0u) << name;
    EXPECT_LT(fewer * double(r.samplesWith), double(r.samplesWithout)) << name;
  }
}

}  // namespace
}  // namespace cellrelief::geotex
