// SPDX-License-Identifier: MIT
// Conversion and reconstruction on analytic shapes, the file format's round trip and its errors.
#include <cstring>

#include <gtest/gtest.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/metrics/geometric_error.h>
#include <cellrelief/relief/atlas.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/model_file.h>
#include <cellrelief/relief/reconstruct.h>

#include "test_support.h"

namespace cellrelief::relief {
namespace {

/// The deepest point of a tessellated unit sphere below the sphere: 1 - the nearest face plane.
double sagittaOf(const TriangleMesh& sphere) {
  double sagitta = 0;
  for (const Vec3u& t : sphere.triangles) {
    const Vec3d a(sphere.positions[t[0]]), b(sphere.positions[t[1]]), c(sphere.positions[t[2]]);
    sagitta = std::max(sagitta, 1.0 - std::abs(glm::dot(a, glm::normalize(glm::cross(b - a, c - a)))));
  }
  return sagitta;
}

TEST(Conversion, SphereDistancesAreExactPerSample) {
  // A finely tessellated unit sphere: every reconstructed vertex lies on it, within the
  // tessellation's sagitta and the 16-bit quantization.
  TriangleMesh sphere = makeIcosphere(6);
  sphere.normals.clear();
  const double sagitta = sagittaOf(sphere);
  ConvertReport report;
  const ReliefModel model = convert(sphere, {.gridSize = 8, .texels = 17, .centreSamples = false}, &report);
  EXPECT_EQ(model.gridSize, 8);
  EXPECT_GT(report.filledSamples, 0u);
  // The per-face method: its vertices are the samples themselves.
  const TriangleMesh rebuilt = reconstruct(model, {0, ReconstructionMethod::PerFace});
  ASSERT_GT(rebuilt.triangleCount(), 10000u);
  double worst = 0;
  for (const Vec3f& p : rebuilt.positions) worst = std::max(worst, std::abs(double(glm::length(p)) - 1.0));
  EXPECT_LT(worst, sagitta + model.quantizationError() * model.cellSizeWS + 1e-6);
  EXPECT_GT(worst, 0.5 * sagitta);  // the bound is tight: samples do reach the flat faces' middles
  // The sphere lacks normals and colors: neither is stored.
  EXPECT_EQ(model.normalFormat, NormalFormat::None);
  EXPECT_EQ(model.colorFormat, ColorFormat::None);
  EXPECT_EQ(model.byteSize(), model.cells.size() * 24 + std::size_t(model.layerCount()) * 17 * 17 * 2);
}

TEST(Conversion, InteriorCellsStoreWhereTheSurfaceCrossesAnEmptyLineBeforeTheFace) {
  // A thick shell (the sphere at N = 8 has interior cells, case 0). Every sample of their layers
  // has a value: next to a filled sample, an empty line's continuation outwards meets the sphere
  // at the stored negative distance, or not within beforeFace(T) (stored at the limit); farther
  // from the surface's samples, the limit without a cast. The reference is analytic: the
  // tessellation lies between the unit sphere and the sphere 1 - sagitta, so the distance lies
  // between theirs (lines that graze one and miss the other are left out and counted).
  TriangleMesh sphere = makeIcosphere(6);
  sphere.normals.clear();
  const double sagitta = sagittaOf(sphere);
  // The first s > 0 with |origin + s u| = radius, or infinity.
  auto sphereHit = [](const Vec3d& origin, const Vec3d& u, double radius) {
    const double pb = glm::dot(origin, u), c = glm::dot(origin, origin) - radius * radius;
    const double disc = pb * pb - c;
    if (disc < 0) return std::numeric_limits<double>::infinity();
    const double s0 = -pb - std::sqrt(disc), s1 = -pb + std::sqrt(disc);
    return s0 > 0 ? s0 : (s1 > 0 ? s1 : std::numeric_limits<double>::infinity());
  };
  for (const int bits : {16, 8}) {
    const int T = 9;
    const ReliefModel model = convert(sphere, {.gridSize = 8, .texels = T, .distanceBits = bits});
    const DistanceCodec& codec = model.distanceCodec;
    ASSERT_GT(codec.zeroCode, 0u);
    const double reach = detail::beforeFace(T), h = model.cellSizeWS;
    const double tolerance = 2 * codec.quantizationError() + 1e-6;
    std::size_t interiorCells = 0, before = 0, atLimit = 0, grazing = 0, notCast = 0;
    double worst = 0;
    for (const CellRecord& r : model.cells) {
      if (r.configuration != 0) continue;
      ++interiorCells;
      const auto proj = r.projection<double>();
      const Vec3d cellMin = model.originWS + h * Vec3d(r.ijk());
      for (int f = 0; f < 6; ++f) {
        const int layer = r.layerOf(f);
        if (layer < 0) continue;
        for (int b = 0; b < T; ++b)
          for (int a = 0; a < T; ++a) {
            const std::uint32_t code = model.distanceCode(layer, a, b);
            ASSERT_FALSE(codec.isEmpty(code)) << "an interior cell's present face has an empty sample";
            if (codec.hasSurface(code)) continue;
            ++before;
            bool nextToFilled = false;
            for (int y = std::max(0, b - 1); y <= std::min(T - 1, b + 1); ++y)
              for (int x = std::max(0, a - 1); x <= std::min(T - 1, a + 1); ++x)
                nextToFilled = nextToFilled || codec.hasSurface(model.distanceCode(layer, x, y));
            if (!nextToFilled) {
              ++notCast;
              EXPECT_NEAR(model.distance(layer, a, b), -reach, codec.quantizationError() + 1e-7);
              continue;
            }
            const Vec3d onFace = projection::facePoint(f, Vec2d(double(a) / (T - 1), double(b) / (T - 1)));
            const Vec3d origin = cellMin + h * onFace;
            const Vec3d outwards = glm::normalize(onFace - proj.lineEnd(f, onFace));
            const double outer = std::min(sphereHit(origin, outwards, 1.0) / h, reach);
            const double inner = std::min(sphereHit(origin, outwards, 1.0 - sagitta) / h, reach);
            if ((outer < reach) != (inner < reach)) {
              ++grazing;
              continue;
            }
            atLimit += outer >= reach;
            const double d = -double(model.distance(layer, a, b));
            worst = std::max(worst, std::max(std::min(outer, inner) - d, d - std::max(outer, inner)));
          }
      }
    }
    std::printf("%d bits: %zu interior cells, %zu samples before their faces (%zu not next to a filled one; of "
                "the others %zu at the limit, %zu grazing); worst %.2e cell units outside the bracket "
                "(tolerance %.2e)\n", bits, interiorCells, before, notCast, atLimit, grazing, worst, tolerance);
    EXPECT_GT(interiorCells, 0u);
    EXPECT_GT(notCast, 0u);
    EXPECT_GT(before - notCast, atLimit + grazing);  // most meet the sphere within reach
    EXPECT_GT(atLimit, 0u);
    EXPECT_LT(grazing, (before - notCast) / 20);
    EXPECT_LT(worst, tolerance);
  }
}

TEST(Conversion, CentredSamplesCentreTheInterpolationErrorOnTheSurface) {
  // One cell, coarse samples: between samples the per-face reconstruction's triangles (and the
  // tracer's bilinear reading) are chords of the sphere, inside it unless the samples move out by
  // half the chords' depth (convert.h, centreInterpolationError).
  TriangleMesh sphere = makeIcosphere(6);
  sphere.normals.clear();
  for (int texels : {9, 17}) {
    struct Deviation {
      double meanSigned = 0, meanAbs = 0, worst = 0;  ///< |p| - 1 over the rebuilt surface, in spacings
    };
    Deviation e[2];
    for (bool centre : {false, true}) {
      const ReliefModel model = convert(sphere, {.gridSize = 1, .texels = texels, .centreSamples = centre});
      const TriangleMesh rebuilt = reconstruct(model, {0, ReconstructionMethod::PerFace});
      const double spacing = model.sampleSpacingWS();
      const std::vector<Vec3d> points = metrics::sampleSurface(rebuilt, 40000);
      Deviation& r = e[centre];
      for (const Vec3d& p : points) {
        const double d = (glm::length(p) - 1.0) / spacing;
        r.meanSigned += d, r.meanAbs += std::abs(d), r.worst = std::max(r.worst, std::abs(d));
      }
      r.meanSigned /= double(points.size()), r.meanAbs /= double(points.size());
    }
    std::printf("T = %d, in sample spacings: exact samples mean %.4f, mean |e| %.4f, worst %.4f; centred "
                "%.4f, %.4f, %.4f\n", texels, e[0].meanSigned, e[0].meanAbs, e[0].worst, e[1].meanSigned,
                e[1].meanAbs, e[1].worst);
    // Measured: T = 9: -0.025, 0.025, 0.059 -> -0.005, 0.009, 0.045; T = 17: -0.013, 0.013,
    // 0.031 -> -0.002, 0.004, 0.023.
    EXPECT_LT(e[0].meanSigned, -0.9 * e[0].meanAbs);  // exact samples: chords, inside the sphere
    EXPECT_LT(std::abs(e[1].meanSigned), 0.3 * std::abs(e[0].meanSigned));
    EXPECT_LT(e[1].meanAbs, 0.5 * e[0].meanAbs);
    EXPECT_LT(e[1].worst, e[0].worst);
  }
}

TEST(Conversion, CentringMovesSamplesByTheirCurvatureOnlyAlongFilledSmoothAxes) {
  // A parabola along a (second difference 2 / 64 per sample), constant along b; T = 9.
  constexpr int T = 9;
  const double secondDifference = 2.0 / 64;
  std::vector<float> d(T * T);
  for (int b = 0; b < T; ++b)
    for (int a = 0; a < T; ++a) d[b * T + a] = float(0.3 + (a - 4) * (a - 4) / 64.0);
  d[6 * T + 2] = std::numeric_limits<float>::quiet_NaN();  // an empty line in row b = 6
  for (int a = 6; a < T; ++a) d[3 * T + a] += 0.5f;         // a depth jump in row b = 3
  std::vector<float> moved = d;
  detail::centreInterpolationError(moved.data(), T);
  auto shift = [&](int a, int b) { return double(moved[b * T + a]) - double(d[b * T + a]); };
  const double expected = -detail::kInterpolationCentring * secondDifference;
  EXPECT_NEAR(shift(4, 4), expected, 1e-7);  // inside the face
  EXPECT_NEAR(shift(4, 0), expected, 1e-7);  // on the edge b = 0, which runs along a
  EXPECT_EQ(shift(0, 4), 0.0);               // on the edge a = 0: constant along it
  EXPECT_EQ(shift(0, 0), 0.0);               // a corner has no neighbour on either axis
  EXPECT_TRUE(std::isnan(moved[6 * T + 2]));
  EXPECT_EQ(shift(1, 6), 0.0);  // next to the empty line
  EXPECT_EQ(shift(3, 6), 0.0);
  EXPECT_NEAR(shift(4, 6), expected, 1e-7);
  EXPECT_EQ(shift(5, 3), 0.0);  // on either side of the jump: not a curvature
  EXPECT_EQ(shift(6, 3), 0.0);
  EXPECT_NEAR(shift(7, 3), expected, 1e-7);  // past it, a parabola again
}

TEST(Conversion, SignalsAreSampledWhenPresent) {
  DisplacedSphereOptions o;
  o.subdivisions = 5;
  const TriangleMesh rock = makeDisplacedSphere(o);  // has normals and colors
  const ReliefModel model = convert(rock, {.gridSize = 4, .texels = 9});
  EXPECT_EQ(model.normalFormat, NormalFormat::Octahedral16);
  EXPECT_EQ(model.colorFormat, ColorFormat::Rgba8);
  // Normals point away from the centre, colors are the mesh's palette (not black).
  int checked = 0;
  for (const CellRecord& r : model.cells)
    for (int f = 0; f < 6; ++f) {
      const int layer = r.layerOf(f);
      if (layer < 0) continue;
      const double d = model.distance(layer, 4, 4);
      if (std::isnan(d)) continue;
      const Vec3d p = model.toWorld(r.ijk(), r.projection<double>().unproject(f, Vec2d(0.5), d));
      EXPECT_GT(glm::dot(Vec3d(model.normal(layer, 4, 4)), glm::normalize(p)), 0.3);
      EXPECT_GT(int(model.colors.at(4, 4, layer, 0)) + model.colors.at(4, 4, layer, 1), 50);
      ++checked;
    }
  EXPECT_GT(checked, 20);
  const ReliefModel plain = convert(rock, {.gridSize = 4, .texels = 9, .normals = NormalFormat::None, .colors = false});
  EXPECT_LT(plain.byteSize(), model.byteSize() / 3);
}

TEST(Conversion, OctahedralNormalsRoundTrip) {
  std::uint32_t s = 5;
  auto rnd = [&] { return ((s = s * 1664525u + 1013904223u) >> 8) / double(1 << 24) * 2 - 1; };
  for (int i = 0; i < 10000; ++i) {
    const Vec3f n = glm::normalize(Vec3f(float(rnd()), float(rnd()), float(rnd())));
    const Vec2f e = octahedralEncode(n);
    const Vec2f q(dequantizeUnorm<std::uint16_t>(quantizeUnorm<std::uint16_t>(e.x)),
                  dequantizeUnorm<std::uint16_t>(quantizeUnorm<std::uint16_t>(e.y)));
    // The angle from the cross product: accurate for small angles, unlike acos of a float dot.
    const Vec3d x = glm::normalize(Vec3d(octahedralDecode(q))), y = glm::normalize(Vec3d(n));
    const double angle = std::atan2(glm::length(glm::cross(x, y)), glm::dot(x, y));
    EXPECT_LT(angle, 1e-4);
  }
}

TEST(Reconstruction, LevelsOfDetailAndCracksStaySmall) {
  const TriangleMesh torus = makeTorus(1.0f, 0.4f, 256, 128);
  const ReliefModel model = convert(torus, {.gridSize = 8, .texels = 17});
  EXPECT_EQ(maxLevelOfDetail(model), 4);
  std::size_t previous = std::numeric_limits<std::size_t>::max();
  const metrics::DistanceField original(torus);
  for (int lod = 0; lod <= 2; ++lod) {
    // The per-face method's levels (the closed one's: test_closed_reconstruction.cpp).
    const TriangleMesh m = reconstruct(model, {lod, ReconstructionMethod::PerFace});
    EXPECT_LT(m.triangleCount(), previous);
    previous = m.triangleCount();
    const metrics::SurfaceError e = metrics::surfaceError(torus, original, m, 50000);
    // Two-sided: the reconstruction lies on the torus and covers it (no large crack or hole).
    EXPECT_LT(e.bToA.max, 0.01) << "lod " << lod;
    EXPECT_LT(e.aToB.max, 0.05 * (1 << lod)) << "lod " << lod;
  }
  EXPECT_THROW(reconstruct(model, 5), Error);
  EXPECT_THROW(reconstruct(model, -1), Error);
}

TEST(DistanceCodec, CodesRoundTripWithinHalfAStepAndTheLargestMeansEmpty) {
  for (const int bits : {8, 16}) {
    const DistanceCodec codec{.bits = bits, .distanceMax = 0.8f};
    EXPECT_TRUE(DistanceCodec::supports(bits));
    EXPECT_EQ(codec.emptyCode(), (1u << bits) - 1);
    EXPECT_EQ(codec.maxCode(), codec.emptyCode() - 1);
    EXPECT_EQ(codec.bytesPerCode(), std::size_t(bits / 8));
    EXPECT_TRUE(codec.isEmpty(codec.emptyCode()));
    EXPECT_FALSE(codec.isEmpty(codec.maxCode()));
    EXPECT_TRUE(std::isnan(codec.decode(codec.emptyCode())));
    EXPECT_EQ(codec.encode(0.8), codec.maxCode());
    EXPECT_EQ(codec.encode(5.0), codec.maxCode());  // clamped, never the empty code
    EXPECT_EQ(codec.encode(-1.0), 0u);
    EXPECT_EQ(codec.encode(std::numeric_limits<double>::quiet_NaN()), 0u);
    double worst = 0;
    for (int i = 0; i <= 1000; ++i) {
      const double d = 0.8 * i / 1000;
      worst = std::max(worst, std::abs(double(codec.decode(codec.encode(d))) - d));
    }
    EXPECT_LE(worst, codec.quantizationError() + 1e-7) << bits;  // + the float the decoded value is
    EXPECT_GT(worst, 0.5 * codec.quantizationError()) << bits;  // the bound is tight
  }
  EXPECT_FALSE(DistanceCodec::supports(12));
  EXPECT_EQ((DistanceCodec{.bits = 16, .distanceMax = 0}.scale()), 0.0);
}

TEST(DistanceCodec, CodesBelowTheZeroCodeAreDistancesBeforeTheFace) {
  for (const int bits : {8, 16}) {
    const double before = 0.25;
    const std::uint32_t zero = DistanceCodec::zeroCodeFor(bits, 0.8, before);
    const DistanceCodec codec{.bits = bits, .distanceMax = 0.8f, .zeroCode = zero};
    ASSERT_GT(zero, 0u);
    EXPECT_LE(codec.distanceMin(), -before);                     // -before is representable
    EXPECT_GT(codec.distanceMin(), -before - 2 * codec.scale());  // with no more than a step to spare
    EXPECT_EQ(codec.encode(0.0), zero);
    EXPECT_EQ(codec.decode(zero), 0.0f);
    EXPECT_EQ(codec.encode(0.8), codec.maxCode());
    EXPECT_EQ(codec.encode(-5.0), 0u);  // clamped to distanceMin
    // However small, a negative distance stays before the face, a positive one at or after it.
    EXPECT_LT(codec.encode(-1e-9), zero);
    EXPECT_GE(codec.encode(1e-9), zero);
    EXPECT_FALSE(codec.hasSurface(codec.encode(-1e-9)));
    EXPECT_TRUE(codec.hasSurface(codec.encode(0.0)));
    EXPECT_TRUE(codec.hasSurface(codec.maxCode()));
    EXPECT_FALSE(codec.hasSurface(codec.emptyCode()));
    double worst = 0;
    for (int i = 0; i <= 1000; ++i) {
      const double d = -before + (0.8 + before) * i / 1000;
      if (d < 0 && d > -codec.scale()) continue;  // moved below the zero code on purpose
      worst = std::max(worst, std::abs(double(codec.decode(codec.encode(d))) - d));
    }
    EXPECT_LE(worst, codec.quantizationError() + 1e-7) << bits;
  }
  // Without distances before the face the zero code is 0 and codes are as before.
  EXPECT_EQ(DistanceCodec::zeroCodeFor(16, 0.8, 0.0), 0u);
  const DistanceCodec plain{.bits = 16, .distanceMax = 0.8f};
  EXPECT_EQ(plain.distanceMin(), 0.0);
  EXPECT_EQ(plain.encode(-1e-9), 0u);
  EXPECT_TRUE(plain.hasSurface(0));
}

TEST(DistanceCodec, EveryWayOfReadingTheCodesAgrees) {
  for (const int bits : {8, 16}) {
    const ReliefModel m = convert(makeIcosphere(3), {.gridSize = 4, .texels = 5, .distanceBits = bits});
    ASSERT_GT(m.layerCount(), 0);
    EXPECT_EQ(m.distanceCodec.bits, bits);
    EXPECT_EQ(m.visitDistances([](const auto& maps) { return int(sizeof(maps.at(0, 0, 0, 0))); }), bits / 8);
    std::size_t checked = 0, empty = 0;
    m.visitDistanceCodes([&](const auto& codes) {
      for (int l = 0; l < m.layerCount(); ++l)
        for (int b = 0; b < m.texels; ++b)
          for (int a = 0; a < m.texels; ++a) {
            ASSERT_EQ(codes(l, a, b), m.distanceCode(l, a, b));
            const float d = m.distance(l, a, b);
            empty += std::isnan(d);
            if (!std::isnan(d)) EXPECT_EQ(d, m.distanceCodec.decode(codes(l, a, b)));
            ++checked;
          }
    });
    EXPECT_EQ(checked, std::size_t(m.layerCount()) * m.texels * m.texels);
    EXPECT_LT(empty, checked);
  }
}

ReliefModel smallModel() {
  DisplacedSphereOptions o;
  o.subdivisions = 4;
  return convert(makeDisplacedSphere(o), {.gridSize = 4, .texels = 9});
}

TEST(ModelFile, SaveThenLoadIsBitExact) {
  test::TempDir dir;
  const ReliefModel a = smallModel();
  ASSERT_NE(a.normalFormat, NormalFormat::None);
  writeRelief(a, dir / "m.crm");
  const ReliefModel b = readRelief(dir / "m.crm");
  EXPECT_EQ(b.gridSize, a.gridSize);
  EXPECT_EQ(b.texels, a.texels);
  EXPECT_EQ(b.originWS, a.originWS);
  EXPECT_EQ(b.cellSizeWS, a.cellSizeWS);
  EXPECT_EQ(b.distanceCodec.distanceMax, a.distanceCodec.distanceMax);
  EXPECT_EQ(b.distanceCodec.bits, a.distanceCodec.bits);
  EXPECT_EQ(b.distanceCodec.zeroCode, a.distanceCodec.zeroCode);
  ASSERT_EQ(b.cells.size(), a.cells.size());
  EXPECT_EQ(std::memcmp(b.cells.data(), a.cells.data(), a.cells.size() * sizeof(CellRecord)), 0);
  auto same = [](const auto& x, const auto& y) {
    return x.levelData(0).size() == y.levelData(0).size() &&
           std::equal(x.levelData(0).begin(), x.levelData(0).end(), y.levelData(0).begin());
  };
  EXPECT_TRUE(same(a.distances16, b.distances16));
  EXPECT_TRUE(same(a.normals16, b.normals16));
  EXPECT_TRUE(same(a.colors, b.colors));
  // Writing the loaded model again gives the same bytes.
  writeRelief(b, dir / "again.crm");
  EXPECT_EQ(test::readBytes(dir / "m.crm"), test::readBytes(dir / "again.crm"));
  // 8-bit distances too.
  const ReliefModel c = convert(makeIcosphere(3), {.gridSize = 4, .texels = 5, .distanceBits = 8});
  writeRelief(c, dir / "c8.crm");
  EXPECT_TRUE(same(c.distances8, readRelief(dir / "c8.crm").distances8));
  // A model with interior cells keeps distances before their faces: its zero code travels too.
  const ReliefModel d = convert(makeIcosphere(4), {.gridSize = 8, .texels = 5});
  ASSERT_GT(d.distanceCodec.zeroCode, 0u);
  writeRelief(d, dir / "d.crm");
  const ReliefModel e = readRelief(dir / "d.crm");
  EXPECT_EQ(e.distanceCodec.zeroCode, d.distanceCodec.zeroCode);
  EXPECT_EQ(e.distanceCodec.distanceMin(), d.distanceCodec.distanceMin());
  EXPECT_TRUE(same(d.distances16, e.distances16));
}

void expectBadFile(const std::filesystem::path& path, const std::string& words) {
  try {
    readRelief(path);
    FAIL() << "no error for " << path;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(ModelFile, TruncatedCorruptedAndWrongVersionFilesAreRejected) {
  test::TempDir dir;
  writeRelief(smallModel(), dir / "m.crm");
  const std::string bytes = test::readBytes(dir / "m.crm");
  for (std::size_t cut : {std::size_t(0), std::size_t(5), std::size_t(60), std::size_t(200),
                          bytes.size() / 2, bytes.size() - 1}) {
    test::writeBytes(dir / "cut.crm", bytes.substr(0, cut));
    expectBadFile(dir / "cut.crm", cut < 12 ? "too short" : "truncated");
  }
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x40;
  test::writeBytes(dir / "flipped.crm", flipped);
  expectBadFile(dir / "flipped.crm", "checksum mismatch");
  std::string version = bytes;
  version[8] = 4;
  test::writeBytes(dir / "v4.crm", version);
  expectBadFile(dir / "v4.crm", "version 4, this build reads version 3");
  version[8] = 2;  // before the zero code: its distances would read shifted
  test::writeBytes(dir / "v2.crm", version);
  expectBadFile(dir / "v2.crm", "version 2, this build reads version 3");
  std::string magic = bytes;
  magic[0] = 'X';
  test::writeBytes(dir / "magic.crm", magic);
  expectBadFile(dir / "magic.crm", "not a cellrelief model");
  test::writeBytes(dir / "long.crm", bytes + "xyz");
  expectBadFile(dir / "long.crm", "trailing bytes");
  std::string counts = bytes;
  counts[16] = char(counts[16] + 1);  // grid size changes: the checksum catches it
  test::writeBytes(dir / "counts.crm", counts);
  expectBadFile(dir / "counts.crm", "checksum");
  expectBadFile(dir / "absent.crm", "no such file");
}

TEST(ModelFile, CraftedTablesWithAValidChecksumAreRejected) {
  // A hostile file passes the CRC (it is recomputed) but its cell table would index out of range.
  test::TempDir dir;
  writeRelief(smallModel(), dir / "m.crm");
  std::string bytes = test::readBytes(dir / "m.crm");
  auto recrc = [](std::string& b) {
    const std::uint32_t crc = io::detail::crc32(b.data(), b.size() - 4);
    std::memcpy(b.data() + b.size() - 4, &crc, 4);
  };
  std::string axis = bytes;
  axis[120 + 6] = char(255);  // faceOrAxis of the first cell
  recrc(axis);
  test::writeBytes(dir / "axis.crm", axis);
  expectBadFile(dir / "axis.crm", "corrupted look-up table at cell 0");
  std::string point = bytes;
  const float nan = std::nanf("");
  std::memcpy(point.data() + 120 + 12, &nan, 4);
  recrc(point);
  test::writeBytes(dir / "point.crm", point);
  expectBadFile(dir / "point.crm", "corrupted look-up table at cell 0");
  std::string layers = bytes;
  const std::uint64_t huge = (std::uint64_t(1) << 32) + 1;
  std::memcpy(layers.data() + 72, &huge, 8);
  recrc(layers);
  test::writeBytes(dir / "layers.crm", layers);
  expectBadFile(dir / "layers.crm", "corrupted header");
  std::string zero = bytes;
  const std::uint32_t above = 40000;  // more than half the codes below zero: not a file we write
  std::memcpy(zero.data() + 112, &above, 4);
  recrc(zero);
  test::writeBytes(dir / "zero.crm", zero);
  expectBadFile(dir / "zero.crm", "corrupted header");
}

TEST(ModelFile, FailedWritesLeaveNothing) {
  test::TempDir dir;
  EXPECT_THROW(writeRelief(smallModel(), dir / "no/such/dir/m.crm"), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(Atlas, WritesOneTilePerLayer) {
  test::TempDir dir;
  const ReliefModel m = smallModel();
  const auto files = writeAtlases(m, dir / "atlas");
  ASSERT_EQ(files.size(), 3u);  // distance, normal, color
  for (const auto& f : files) EXPECT_TRUE(std::filesystem::exists(f));
}

}  // namespace
}  // namespace cellrelief::relief
