// SPDX-License-Identifier: MIT
// Polycube maps of real meshes: every vertex on the polycube's surface, no flipped triangle after
// optimization, distortion lowered, and the paper's Fig. 8 ordering of the energies; the mesh's
// own normals baked into T2 through the map and read back at its vertices.
#include <gtest/gtest.h>

#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/from_mesh.h>
#include <cellrelief/polycube/mesh_signal.h>
#include <cellrelief/polycube/parameterization.h>

#include "test_support.h"

namespace cellrelief::polycube {
namespace {

struct MappedMesh {
  TriangleMesh mesh;
  PolycubeResult polycube;
};

MappedMesh load(const std::string& relative) {
  const std::filesystem::path path = test::dataDir() / relative;
  MappedMesh m;
  m.mesh = io::readMesh(path);
  m.polycube = polycubeOfMesh(m.mesh);
  return m;
}

void expectOnTheSurface(const PolycubeSurface& surface, std::span<const Vec3d> texture) {
  std::size_t off = 0;
  for (const Vec3d& u : texture) off += surface.lut().locate(u, 1e-9) ? 0 : 1;
  EXPECT_EQ(off, 0u);
}

class PolycubeMapOfRealMesh : public testing::TestWithParam<std::string> {};

TEST_P(PolycubeMapOfRealMesh, HasNoFlipsLowersDistortionAndExtendedMipsKeepsAreasBetterThanMips) {
  CELLRELIEF_REQUIRE_FILE(test::dataDir() / GetParam());
  const MappedMesh m = load(GetParam());
  const PolycubeSurface surface(m.polycube.polycube);
  PolycubeParameterization maps[3];
  const PolycubeEnergy energies[3] = {PolycubeEnergy::ExtendedMips, PolycubeEnergy::Mips, PolycubeEnergy::MeanValue};
  for (int e = 0; e < 3; ++e) {
    maps[e] = parameterize(m.mesh, surface, m.polycube.frame, {.energy = energies[e]});
    const PolycubeParameterization& p = maps[e];
    expectOnTheSurface(surface, p.texture);
    EXPECT_LT(p.final.angle, p.initial.angle) << toString(energies[e]);
    std::printf("%s, %s: %zu cubes; projected: area %.4f angle %.4f stretch %.3f flipped %zu; optimized: area %.4f "
                "angle %.4f stretch %.3f flipped %zu; %d sweeps, %.2f s\n",
                GetParam().c_str(), std::string(toString(energies[e])).c_str(), m.polycube.polycube.size(),
                p.initial.area, p.initial.angle, p.initial.stretchEfficiency, p.initial.flipped, p.final.area,
                p.final.angle, p.final.stretchEfficiency, p.final.flipped, p.sweeps, p.seconds);
  }
  const PolycubeParameterization& extended = maps[0];
  EXPECT_EQ(extended.final.flipped, 0u);
  EXPECT_LT(extended.final.area, extended.initial.area);
  // Fig. 8: MIPS keeps angles and lets areas go; extended MIPS trades a little angle for area.
  EXPECT_LT(extended.final.area, maps[1].final.area);
  EXPECT_LE(maps[1].final.angle, extended.final.angle);
}

INSTANTIATE_TEST_SUITE_P(Meshes, PolycubeMapOfRealMesh,
                         testing::Values("meshes/small/3holes__cinolib.obj", "meshes/small/spot__common-3d-test-models.obj"),
                         [](const testing::TestParamInfo<std::string>& param) {
                           return test::testNameOfPath(param.param);
                         });

TEST(PolycubeMap, StartsALargeMeshFromItsDecimationWithoutFlips) {
  const std::string relative = "meshes/small/spot__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(test::dataDir() / relative);
  const MappedMesh m = load(relative);
  const PolycubeSurface surface(m.polycube.polycube);
  const PolycubeParameterization p =
      parameterize(m.mesh, surface, m.polycube.frame, {.coarseVertices = m.mesh.positions.size() / 3});
  EXPECT_GT(p.coarseVertices, 0u);
  EXPECT_LE(p.coarseVertices, m.mesh.positions.size() / 3 + 10);
  EXPECT_EQ(p.final.flipped, 0u);
  expectOnTheSurface(surface, p.texture);
  // Starting from the coarse map is already close: fewer flips than the projection leaves.
  const std::vector<Vec3d> lattice = latticePositions(m.mesh, m.polycube.frame);
  const PolycubeParameterizer projected(m.mesh.triangles, lattice, surface,
                                        projectAlongNormals(m.mesh, lattice, surface));
  EXPECT_LT(p.initial.flipped, projected.distortion().flipped);
}

// Fertility's automatic polycube (N = 24, four handles) has a case-6b vertex on whose concave
// crease the sweeps leave one triangle flipped: none of its corners alone has a place where all
// its triangles face out. optimize's second attempt, which moves such a triangle's corners and
// their neighbours together (repairFolds), undoes it; the first attempt keeps that 1 flip.
TEST(PolycubeMap, FertilityMapsWithoutFlips) {
  const std::string relative = "meshes/small/fertility_9k__libigl-tutorial-data.off";
  CELLRELIEF_REQUIRE_FILE(test::dataDir() / relative);
  const MappedMesh m = load(relative);
  ASSERT_EQ(m.polycube.cubesPerSide, 24);
  const PolycubeSurface surface(m.polycube.polycube);
  const PolycubeParameterization p = parameterize(m.mesh, surface, m.polycube.frame);
  std::printf("fertility: %zu cubes; projected: flipped %zu; optimized: area %.4f angle %.4f stretch %.3f flipped %zu; "
              "%d sweeps, %.2f s\n",
              m.polycube.polycube.size(), p.initial.flipped, p.final.area, p.final.angle, p.final.stretchEfficiency,
              p.final.flipped, p.sweeps, p.seconds);
  EXPECT_EQ(p.final.flipped, 0u);
  expectOnTheSurface(surface, p.texture);
  // The premise: without the second attempt the map keeps its flip.
  const PolycubeParameterization first = parameterize(m.mesh, surface, m.polycube.frame, {.repairFolds = false});
  EXPECT_GE(first.final.flipped, 1u);
  // The repair leaves no lasting cost in distortion: the sweeps after it restore the energy
  // (area 1.011 and angle 1.050 measured; the first attempt, with its flip, 1.011 and 1.044).
  EXPECT_LT(p.final.area, 1.03);
  EXPECT_LT(p.final.angle, 1.1);
}

TEST(PolycubeMap, TransferToADecimationKeepsEveryVertexOnTheSurface) {
  const std::string relative = "meshes/small/3holes__cinolib.obj";
  CELLRELIEF_REQUIRE_FILE(test::dataDir() / relative);
  const MappedMesh m = load(relative);
  const PolycubeSurface surface(m.polycube.polycube);
  const PolycubeParameterization p = parameterize(m.mesh, surface, m.polycube.frame);
  const TriangleMesh coarse = decimate(m.mesh, 500);
  EXPECT_LE(coarse.positions.size(), 520u);
  const std::vector<Vec3d> texture =
      transferTexturePositions(latticePositions(m.mesh, m.polycube.frame), m.mesh.triangles, p.texture,
                               latticePositions(coarse, m.polycube.frame), surface);
  expectOnTheSurface(surface, texture);
  // A vertex the decimation kept in place takes its own texture position back.
  const std::vector<Vec3d> fine = latticePositions(m.mesh, m.polycube.frame);
  const std::vector<Vec3d> kept = latticePositions(coarse, m.polycube.frame);
  std::size_t matched = 0;
  for (std::size_t v = 0; v < kept.size(); ++v)
    for (std::size_t w = 0; w < fine.size(); ++w)
      if (glm::length(kept[v] - fine[w]) < 1e-6) {
        EXPECT_LT(glm::length(texture[v] - p.texture[w]), 1e-6);
        ++matched;
        break;
      }
  EXPECT_GT(matched, 0u);
}

TEST(PolycubeMap, NormalsBakedThroughTheMapReadBackAtTheVertices) {
  const std::string relative = "meshes/small/spot__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(test::dataDir() / relative);
  const MappedMesh m = load(relative);
  const auto surface = std::make_shared<const PolycubeSurface>(m.polycube.polycube);
  const PolycubeParameterization p = parameterize(m.mesh, *surface, m.polycube.frame);
  ASSERT_EQ(p.final.flipped, 0u);
  const auto inverse = std::make_shared<const InverseMap>(m.mesh, p.texture);
  const PolycubeTexture t(surface, meshSignal(inverse, MeshSignalKind::Normal), {16});
  const std::vector<Vec3f> normals = computeVertexNormals(m.mesh);
  std::vector<double> degrees;
  for (std::size_t v = 0; v < p.texture.size(); ++v) {
    const std::optional<Vec4f> c = t.sampleNear(p.texture[v], TextureFilter::Bilinear);
    ASSERT_TRUE(c);
    const Vec3f n = glm::normalize(2.0f * Vec3f(*c) - 1.0f);
    degrees.push_back(glm::degrees(std::acos(std::clamp(double(glm::dot(n, normals[v])), -1.0, 1.0))));
  }
  std::sort(degrees.begin(), degrees.end());
  const double median = degrees[degrees.size() / 2], p95 = degrees[degrees.size() * 95 / 100];
  std::printf("%s: baked normals at the vertices, %zu cubes, S = 16: median %.2f, 95th percentile %.2f, worst %.2f "
              "degrees\n", relative.c_str(), m.polycube.polycube.size(), median, p95, degrees.back());
  // 8-bit texels hold a direction to about 0.5 degrees; a texel spans a few triangles here.
  EXPECT_LT(median, 1.0);  // measured 0.29 and 3.2 degrees
  EXPECT_LT(p95, 6.0);
  EXPECT_THROW(meshSignal(inverse, MeshSignalKind::Color), Error) << "spot has no vertex colours";
}

}  // namespace
}  // namespace cellrelief::polycube
