// SPDX-License-Identifier: MIT
/// @file grid_size.h
/// Automatic grid size (Apaza & Andujar, 3.3.3). A cell's projection is one-to-one only where no
/// two pieces of its surface fall on the same texel at different depths. The occlusion ratio is the
/// fraction of surface area that lands on a texel already covered by nearer surface of the same
/// cell: that area cannot be represented. Doubling N shrinks cells until each holds a nearly
/// height-field piece; the search stops when the ratio falls below a threshold or N reaches N_max.
///
/// Estimate: the surface of every grey cell is sampled (surface_samples.h) at about
/// `samplesPerTexel` samples per texel of a T x T map. A sample is occluded when the segment from
/// it to its projection on the domain face (every projection line is straight: parallel, planar,
/// from a centre, or perpendicular to an axis) crosses another triangle: the segment lies inside
/// the cell, so any triangle it meets is surface of that cell covering the sample's texel. Testing the segment, rather than comparing depths within a texel,
/// keeps a single sheet seen at a grazing angle from counting as occluded.
///
/// Open surfaces (beyond the paper): along a hole's rim, or an open sheet's border, a band about
/// one sample wide is lost (a bilinear texel with an empty corner reads no surface) and the
/// search can step over the thin rim it leaves. A mesh with a long boundary at a coarse grid
/// loses a share of its area there that the occlusion ratio does not see (head_open_with_holes
/// at N = 1: 3.3%, and 7.6e-3 of the rays disagreed with Embree). The search doubles N also while
/// that share, rimBandRatio(), is above the threshold and a finer grid still samples finer.
#pragma once

#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "cellrelief/cells/cell_complex.h"
#include "cellrelief/core/bvh.h"
#include "cellrelief/core/mesh_topology.h"
#include "cellrelief/projection/choice.h"
#include "cellrelief/relief/centre_search.h"
#include "cellrelief/relief/surface_samples.h"

namespace cellrelief::relief {

struct OcclusionOptions {
  int texels = 16;                 ///< T: sets the sampling density with samplesPerTexel
  double samplesPerTexel = 0.25;
  projection::CentreOfProjection centre = projection::CentreOfProjection::CellCentre;
};

struct OcclusionEstimate {
  double ratio = 0;         ///< occluded area / total area
  double totalArea = 0;     ///< in cell units squared
  double occludedArea = 0;
  std::size_t samples = 0;
};

/// The mesh's BVH for segment queries; built once, used for every N.
using MeshRayQuery = MeshBvh;

/// Estimates the occlusion ratio of a cell complex built from `mesh`.
inline OcclusionEstimate estimateOcclusion(const TriangleMesh& mesh,
                                           const cells::CellComplex& complex,
                                           const OcclusionOptions& options,
                                           const MeshRayQuery& query) {
  const int T = options.texels;
  // Samples per unit of area (cell units): the texel density, but at least kMinSamples in all so
  // that coarse grids (few, large cells) are estimated as well as fine ones.
  constexpr double kMinSamples = 20000;
  const double areaInCells = surfaceArea(mesh) / (complex.cellSizeWS() * complex.cellSizeWS());
  const double density = std::max(options.samplesPerTexel * T * T, kMinSamples / std::max(areaInCells, 1e-30));
  // Along the segment: past the 2^-21-cell snapping of sample positions, so a sample on an edge
  // shared with the next triangle does not see that triangle as occluding it.
  constexpr double kSelfOffset = 1e-6;
  struct Scratch {
    std::vector<SurfaceSample> samples;
  };
  // Per-cell sums, added in cell order afterwards: the estimate does not depend on scheduling.
  std::vector<OcclusionEstimate> perCell(complex.greyCells().size());
  tbb::enumerable_thread_specific<Scratch> scratch;
  const auto greyCells = complex.greyCells();
  const double h = complex.cellSizeWS();
  parallelFor(0, greyCells.size(), [&](std::size_t i) {
    Scratch& s = scratch.local();
    OcclusionEstimate& sum = perCell[i];
    const cells::GreyCell& cell = greyCells[i];
    s.samples.clear();
    sampleCellSurface(complex, mesh.triangles, cell, density, 16 * T * T, s.samples);
    if (s.samples.empty()) return;
    const Vec3d cellMinWS = complex.cellMinWS(cell.ijk);
    const TrianglesInBox<double> surface(query.bvh, complex.cellBoxWS(cell.ijk));
    auto occludedArea = [&](const projection::CellProjection<double>& proj) {
      double area = 0;
      for (const SurfaceSample& sample : s.samples) {
        const projection::FacePoint<double> fp = proj.project(sample.p);
        const Vec3d target = projection::facePoint(fp.face, fp.uv);
        const Vec3d dir = target - sample.p;
        if (glm::dot(dir, dir) == 0) continue;
        // The segment from the sample to its face point, in world space (t in (0, 1]).
        const Rayd segment(cellMinWS + h * sample.p, h * dir, kSelfOffset, 1.0);
        if (surface.anyHit(segment, sample.triangle)) area += sample.weight;
      }
      return area;
    };
    for (const SurfaceSample& sample : s.samples) sum.totalArea += sample.weight;
    if (options.centre == projection::CentreOfProjection::FewestCrossings) {
      // As the conversion chooses: the canonical projection unless some of its lines cross twice.
      sum.occludedArea = occludedArea(projection::chooseProjection<double>(cell.configuration));
      if (sum.occludedArea > 0)
        sum.occludedArea = std::min(sum.occludedArea,
                                    occludedArea(fewestCrossingsProjection(cell.configuration, surface, cellMinWS, h)));
    } else {
      sum.occludedArea = occludedArea(
          projection::chooseProjection<double>(cell.configuration, options.centre, sampleCentroid(s.samples)));
    }
    sum.samples += s.samples.size();
  }, 16);
  OcclusionEstimate total;
  for (const OcclusionEstimate& c : perCell) {
    total.totalArea += c.totalArea;
    total.occludedArea += c.occludedArea;
    total.samples += c.samples;
  }
  total.ratio = total.totalArea > 0 ? total.occludedArea / total.totalArea : 0.0;
  return total;
}

/// The default T for grid size N: 512 sample spacings across the bounding cube (T = 512 / N + 1),
/// at least 9 samples per face side. Coarse grids used to stop at T = 65, which sampled a mesh
/// with little occlusion 8 times coarser than the rest (Igea gets N = 1: 505 disagreements per
/// million rays against Embree at T = 65, 25 at T = 513). A compact model asks for a smaller T.
inline int defaultTexels(int n) { return std::max(512 / std::max(1, n), 8) + 1; }

struct GridSizeOptions {
  double threshold = 0.01;  ///< stop when the occlusion ratio (and rim band ratio) falls below this
  int maxGridSize = 128;    ///< N_max
  OcclusionOptions occlusion = {};
  std::size_t memoryLimitBytes = std::size_t(4) << 30;
  int texels = 0;              ///< the T the model will have (0: defaultTexels(N)): sets the spacing
  double rimBandSamples = 2.0;  ///< width of the band lost along a boundary, in sample spacings
};

/// The share of a surface's area (`area`) within `samples` sample spacings of its boundary
/// (`boundaryLength`; 0 for a closed mesh), capped at 1.
inline double rimBandRatio(double boundaryLength, double area, double spacing, double samples) {
  return area > 0 ? std::min(1.0, boundaryLength * samples * spacing / area) : 0.0;
}

/// The summed length of the mesh's boundary edges (mesh_topology.h), world units.
inline double boundaryLength(const TriangleMesh& mesh) {
  double length = 0;
  for (const auto& [a, b] : boundaryEdges(mesh))
    length += glm::length(Vec3d(mesh.positions[a]) - Vec3d(mesh.positions[b]));
  return length;
}

struct GridSizeTrial {
  int gridSize = 0;
  double occlusionRatio = 0;
  double rimBandRatio = 0;  ///< rimBandRatio() at this N's sample spacing (0 for a closed mesh)
  std::size_t greyCells = 0;
  double seconds = 0;
  /// The model's measured Hausdorff distance to the input over its diagonal, where the search is
  /// by error (a flat mesh, convert.h); -1 where it is by occlusion.
  double hausdorff = -1;
};

struct GridSizeChoice {
  int gridSize = 0;
  /// false when N_max was reached first, or the rim band ratio stayed above the threshold at the
  /// finest sampling the texel rule allows
  bool metThreshold = false;
  std::vector<GridSizeTrial> trials;
  std::shared_ptr<const cells::CellComplex> complex;  ///< the complex at the chosen N, for reuse
};

/// Doubles N from 1 until the occlusion ratio is below the threshold, and the rim band ratio is
/// too or a finer grid would not sample finer (T falls as N grows), or N reaches N_max; reports
/// the ratios of every N tried. `query` is the mesh's ray query (built when absent).
inline GridSizeChoice chooseGridSize(const TriangleMesh& mesh, const GridSizeOptions& options = {},
                                     const MeshRayQuery* query = nullptr) {
  if (options.maxGridSize < 1 || options.maxGridSize > cells::kMaxGridSize)
    throw Error(ErrorKind::InvalidArgument,
                "N_max = " + std::to_string(options.maxGridSize) + " is out of range (1 to " +
                    std::to_string(cells::kMaxGridSize) + ")");
  if (!(options.threshold > 0 && options.threshold < 1))
    throw Error(ErrorKind::InvalidArgument, "the occlusion threshold must lie in (0, 1)");
  GridSizeChoice choice;
  std::optional<MeshRayQuery> own;
  if (!query) query = &own.emplace(mesh);
  const double rim = boundaryLength(mesh), area = surfaceArea(mesh);
  // Sample spacings across the bounding cube at grid size n.
  auto spacings = [&](int n) { return n * ((options.texels != 0 ? options.texels : defaultTexels(n)) - 1); };
  for (int n = 1;; n *= 2) {
    n = std::min(n, options.maxGridSize);
    if (cells::CellComplex::estimateMemory(mesh.triangles.size(), n) > options.memoryLimitBytes) {
      if (choice.trials.empty())
        throw Error(ErrorKind::ResourceLimit, "even N = 1 exceeds the memory limit");
      break;  // the largest N that fits is the answer
    }
    const auto start = std::chrono::steady_clock::now();
    auto complex = std::make_shared<const cells::CellComplex>(
        cells::CellComplex::build(mesh, {.gridSize = n, .memoryLimitBytes = options.memoryLimitBytes}));
    const OcclusionEstimate est = estimateOcclusion(mesh, *complex, options.occlusion, *query);
    const double spacing = complex->cellSizeWS() * n / spacings(n);  // the cube's side over its samples
    const double band = rimBandRatio(rim, area, spacing, options.rimBandSamples);
    choice.trials.push_back(
        {.gridSize = n, .occlusionRatio = est.ratio, .rimBandRatio = band, .greyCells = complex->stats().grey,
         .seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
    choice.gridSize = n;
    choice.complex = std::move(complex);
    const bool finerNext = n < options.maxGridSize && spacings(std::min(2 * n, options.maxGridSize)) > spacings(n);
    if (est.ratio < options.threshold && (band < options.threshold || !finerNext)) {
      choice.metThreshold = band < options.threshold;
      break;
    }
    if (n >= options.maxGridSize) break;
  }
  return choice;
}

}  // namespace cellrelief::relief
