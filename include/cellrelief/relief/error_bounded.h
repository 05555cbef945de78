// SPDX-License-Identifier: MIT
/// @file error_bounded.h
/// Error-bounded conversion (beyond the paper): choose the grid size N and the texels T that meet
/// a geometric error bound with the least memory. Candidates (N, T) are ordered by their predicted
/// bytes (domain faces of the complex at N times T^2 times the bytes of a sample, which needs only
/// the cheap cell complex); each is converted and reconstructed in that order and its error against
/// the original measured (metrics/geometric_error.h); the first that meets the bound is the answer.
/// The error is a fraction of the bounding box diagonal, RMS (default) or Hausdorff.
#pragma once

#include <algorithm>
#include <map>
#include <optional>
#include <vector>

#include "cellrelief/metrics/geometric_error.h"
#include "cellrelief/relief/convert.h"
#include "cellrelief/relief/reconstruct.h"

namespace cellrelief::relief {

enum class ErrorMetric { Rms, Hausdorff };

struct ErrorBoundOptions {
  double maxError = 0.001;  ///< fraction of the mesh's bounding-box diagonal
  ErrorMetric metric = ErrorMetric::Rms;
  std::vector<int> gridSizes{2, 4, 8, 16, 32, 64, 128};
  std::vector<int> texelCounts{5, 9, 17, 33, 65};
  std::size_t samplesPerSide = 100000;  ///< points per surface for the error measurement
  ConvertOptions convert = {};          ///< gridSize and texels are chosen; the rest is used
};

struct ErrorBoundCandidate {
  int gridSize = 0, texels = 0;
  std::size_t predictedBytes = 0, bytes = 0;
  double rms = 0, hausdorff = 0;  ///< fractions of the diagonal; 0 when not converted
  bool converted = false, meets = false;
  double seconds = 0;
};

struct ErrorBoundResult {
  ReliefModel model;
  ErrorBoundCandidate chosen;
  std::vector<ErrorBoundCandidate> candidates;  ///< in the order tried (by predicted bytes)
  bool met = false;  ///< false: no candidate met the bound; the most accurate one tried is returned
};

inline ErrorBoundResult convertWithErrorBound(const TriangleMesh& input, const ErrorBoundOptions& o) {
  if (!(o.maxError > 0)) throw Error(ErrorKind::InvalidArgument, "the error bound must be positive");
  const double diagonal = input.bounds().diagonal();
  // A flat mesh is modelled as a slab (flat_mesh.h); the error is still measured against the input.
  const std::optional<TriangleMesh> slab = slabIfFlat(input);
  const TriangleMesh& mesh = slab ? *slab : input;
  const std::size_t bytesPerSample = DistanceCodec{.bits = o.convert.distanceBits}.bytesPerCode() +
                                     (o.convert.normals != NormalFormat::None && mesh.hasNormals() ? 4 : 0) +
                                     (o.convert.colors && mesh.hasColors() ? 4 : 0);
  // One BVH and one complex per N serve every candidate (each N is tried with several T).
  const MeshBvh meshBvh(mesh);
  std::optional<MeshBvh> ownInputBvh;
  const MeshBvh& inputBvh = slab ? ownInputBvh.emplace(input) : meshBvh;
  std::map<int, cells::CellComplex> complexes;
  std::vector<ErrorBoundCandidate> candidates;
  for (const int n : o.gridSizes) {
    const cells::CellComplex& complex =
        complexes
            .emplace(n, cells::CellComplex::build(
                            mesh, {.gridSize = n, .memoryLimitBytes = o.convert.memoryLimitBytes}))
            .first->second;
    std::size_t faces = 0;
    for (const cells::GreyCell& g : complex.greyCells()) faces += std::popcount(unsigned(g.domainFaces()));
    for (const int t : o.texelCounts)
      candidates.push_back({n, t, faces * std::size_t(t) * t * bytesPerSample + complex.greyCells().size() * 24});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.predictedBytes < b.predictedBytes; });
  ErrorBoundResult result;
  double bestError = std::numeric_limits<double>::infinity();
  for (ErrorBoundCandidate& c : candidates) {
    if (c.predictedBytes > o.convert.memoryLimitBytes) break;
    const auto start = std::chrono::steady_clock::now();
    ConvertOptions co = o.convert;
    co.gridSize = c.gridSize;
    co.texels = c.texels;
    co.progress = nullptr;
    ReliefModel model;
    try {
      model = convert(mesh, complexes.at(c.gridSize), meshBvh, co);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::ResourceLimit) throw;
      continue;  // over the memory limit after all: skip it, keep what was measured
    }
    // The maps' own sampling error: the per-face mesh's vertices are the samples.
    const TriangleMesh rebuilt = reconstructPerFace(model);
    const metrics::SurfaceError e = metrics::surfaceError(input, inputBvh, rebuilt, o.samplesPerSide);
    c.converted = true;
    c.bytes = model.byteSize();
    c.rms = e.rms() / diagonal;
    c.hausdorff = e.hausdorff() / diagonal;
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double err = o.metric == ErrorMetric::Rms ? c.rms : c.hausdorff;
    c.meets = err <= o.maxError;
    result.candidates.push_back(c);
    if (c.meets || err < bestError) {
      bestError = std::min(bestError, err);
      result.model = std::move(model);
      result.chosen = c;
    }
    if (c.meets) {
      result.met = true;
      break;
    }
  }
  if (result.candidates.empty())
    throw Error(ErrorKind::ResourceLimit, "no grid size and texel count fits the memory limit");
  return result;
}

}  // namespace cellrelief::relief
