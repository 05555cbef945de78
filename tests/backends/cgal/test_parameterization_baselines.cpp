// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL's LSCM and discrete conformal maps as baselines: a near-conformal map of a spherical cap, a
// closed mesh cut into a disk and flattened, and the polycube map compared with them on spot.
#include <gtest/gtest.h>

#include <cellrelief/cgal/reference_parameterization.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/from_mesh.h>
#include <cellrelief/polycube/parameterization.h>

#include "test_support.h"

namespace cellrelief::cgal {
namespace {

/// A spherical cap of polar angle up to 60 degrees in rings and sectors: its border is a circle
/// of evenly spaced vertices, so the conformal map to the disk spaces them evenly too and both
/// LSCM (free border) and DCP (border fixed by arc length) should find it.
TriangleMesh sphericalCap() {
  constexpr int kRings = 24, kSectors = 96;
  constexpr double kMaxPolar = 1.0471975511965976;
  TriangleMesh cap;
  cap.positions.push_back(Vec3f(0, 0, 1));
  for (int i = 1; i <= kRings; ++i)
    for (int j = 0; j < kSectors; ++j) {
      const double polar = kMaxPolar * i / kRings, azimuth = 2 * 3.141592653589793 * j / kSectors;
      cap.positions.push_back(
          Vec3f(float(std::sin(polar) * std::cos(azimuth)), float(std::sin(polar) * std::sin(azimuth)), float(std::cos(polar))));
    }
  const auto at = [](int ring, int sector) { return std::uint32_t(1 + (ring - 1) * kSectors + (sector % kSectors)); };
  for (int j = 0; j < kSectors; ++j) cap.triangles.push_back({0, at(1, j), at(1, j + 1)});
  for (int i = 1; i < kRings; ++i)
    for (int j = 0; j < kSectors; ++j) {
      cap.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      cap.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  cap.sourcePolygons = cap.triangles.size();
  return cap;
}

TEST(CgalParameterization, FlattensASphericalCapNearlyConformallyWithoutFlips) {
  const TriangleMesh cap = sphericalCap();
  for (DiskParameterizer which : {DiskParameterizer::Lscm, DiskParameterizer::DiscreteConformal}) {
    const DiskMap map = parameterizeDisk(cap, which);
    EXPECT_EQ(map.seamEdges, 0u);  // already a disk
    const polycube::Distortion d = polycube::measurePlanarDistortion(cap, map.corners);
    std::printf("spherical cap, %s: area %.4f, angle %.4f, %zu flipped\n", toString(which), d.area, d.angle,
                d.flipped);
    EXPECT_EQ(d.flipped, 0u) << toString(which);
    EXPECT_LT(d.angle, 1.02) << toString(which);  // conformal up to discretization
    EXPECT_GT(d.area, 1.0 + 1e-4) << toString(which);  // a cap cannot keep its areas in the plane
  }
}

TEST(CgalParameterization, CutsAClosedRealMeshIntoADiskAndFlattensIt) {
  const auto path = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  const polycube::PolycubeResult cubes = polycube::polycubeOfMesh(mesh);
  const polycube::PolycubeSurface surface(cubes.polycube);
  const polycube::PolycubeParameterization ours = polycube::parameterize(mesh, surface, cubes.frame);
  for (DiskParameterizer which : {DiskParameterizer::Lscm, DiskParameterizer::DiscreteConformal}) {
    const DiskMap map = parameterizeDisk(mesh, which);
    EXPECT_GT(map.seamEdges, 0u);
    for (const Vec2d& c : map.corners) ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y));
    const polycube::Distortion d = polycube::measurePlanarDistortion(mesh, map.corners);
    EXPECT_LT(d.flipped, mesh.triangles.size()) << toString(which);
    std::printf("spot, %s: %zu seam edges, area %.4f, angle %.4f, stretch efficiency %.4f, %zu flipped, %.2f s; "
                "polycube map: area %.4f, angle %.4f\n", toString(which), map.seamEdges, d.area, d.angle,
                d.stretchEfficiency, d.flipped, map.seconds, ours.final.area, ours.final.angle);
    // The paper's claim: a polycube keeps areas far better than a disk cut of a closed mesh.
    EXPECT_LT(ours.final.area, d.area) << toString(which);
  }
}

}  // namespace
}  // namespace cellrelief::cgal
