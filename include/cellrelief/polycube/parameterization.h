// SPDX-License-Identifier: MIT
/// @file parameterization.h
/// Texture positions for a mesh on its polycube's surface (PolyCube-Maps, section 5): each vertex
/// gets a 3D point of the surface, and a fragment's texture position is the linear interpolation
/// of its triangle's three, which P takes back onto the surface.
///
/// 1. `projectAlongNormals`: each vertex goes to the nearest point of the surface along its
///    normal, either way (the polycube lies in the mesh's own space, warped by the cell complex it
///    was built from, or by the frame a cube file gives), or to the closest point of the surface
///    when no face is within reach along the normal.
/// 2. `PolycubeParameterizer`: the paper's iterative local optimization. Each vertex moves in
///    the tangent plane of the surface to lower the energy of its triangles and P puts it back on
///    the surface; a move is kept only if it lowers the number of flipped triangles around the
///    vertex, or keeps it and lowers the energy, so a map without flips keeps none. Vertices that
///    share no triangle move at the same time (a colouring of the mesh), in parallel.
///    Energies: MIPS (Hormann & Greiner 2000: s1/s2 + s2/s1, angles only), extended MIPS
///    (Degener et al. 2003: MIPS times (s1 s2 + 1/(s1 s2))^theta, theta = 3 as the paper's
///    comparison uses, areas too), and mean value coordinates (Floater 2003: each vertex to the
///    mean-value average of its neighbours, the boundary fixed), the paper's Fig. 8 comparison.
///    Vertices with flipped triangles around them first try the mean-value average, which
///    untangles the folds normal projection leaves at concave creases. Untangling phases run
///    before the sweeps (PolycubeParameterizer::untangle); a map left with a few flips is made
///    again with a last phase that moves each flipped triangle's neighbourhood as one
///    (PolycubeParameterizer::repairFolds).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cellrelief/core/bvh.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/polycube/distortion.h"
#include "cellrelief/polycube/levels_of_detail.h"
#include "cellrelief/polycube/polycube_surface.h"

namespace cellrelief::polycube {

enum class PolycubeEnergy { MeanValue, Mips, ExtendedMips };

constexpr std::string_view toString(PolycubeEnergy e) {
  switch (e) {
    case PolycubeEnergy::MeanValue: return "mvc";
    case PolycubeEnergy::Mips: return "mips";
    case PolycubeEnergy::ExtendedMips: return "extended-mips";
  }
  return "?";
}

inline std::optional<PolycubeEnergy> parsePolycubeEnergy(std::string_view name) {
  for (PolycubeEnergy e : {PolycubeEnergy::MeanValue, PolycubeEnergy::Mips, PolycubeEnergy::ExtendedMips})
    if (toString(e) == name) return e;
  return std::nullopt;
}

struct ParameterizationOptions {
  PolycubeEnergy energy = PolycubeEnergy::ExtendedMips;
  double theta = 3;   ///< extended MIPS: the weight of area against angle
  int maxSweeps = 400;
  /// Stop when a sweep over all vertices lowers the energy by less than this fraction (MIPS),
  /// or moves no vertex by more than this many cubes (mean value coordinates).
  double stopChange = 1e-4;
  /// A mesh of more than twice this many vertices starts from the map of its decimation to this
  /// many (levels_of_detail.h): one vertex's moves reach only its neighbours, so on a large mesh
  /// the sweeps a global change needs grow with its size. 0: always start from the projection.
  std::size_t coarseVertices = 3000;
  /// Where at most 64 flipped triangles are left, optimize once more from the same start with
  /// the fourth untangling phase (repairFolds) on. Not for the coarse map a large mesh starts
  /// from, whose folds the full mesh's own untangling sees again.
  bool repairFolds = true;
  /// Called after each sweep with its number and the map's distortion then.
  std::function<void(int sweep, const Distortion&)> progress = nullptr;
};

struct PolycubeParameterization {
  std::vector<Vec3d> texture;  ///< per mesh vertex: lattice coordinates on the polycube's surface
  Distortion initial;          ///< where optimization starts: the normal projection or the coarse map
  Distortion final;
  int sweeps = 0;
  std::size_t byClosestPoint = 0;  ///< vertices no face was within reach of along the normal
  std::size_t coarseVertices = 0;  ///< of the decimated mesh the map started from; 0: none
  int coarseSweeps = 0;
  double seconds = 0;
};

/// Mesh positions in the polycube's lattice coordinates.
inline std::vector<Vec3d> latticePositions(const TriangleMesh& mesh, const PolycubeFrame& frame) {
  if (!(frame.cubeSize > 0) || !std::isfinite(frame.cubeSize))
    throw Error(ErrorKind::InvalidArgument, "polycube parameterization: the cube size must be positive");
  std::vector<Vec3d> out(mesh.positions.size());
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = (Vec3d(mesh.positions[v]) - frame.origin) / frame.cubeSize;
  return out;
}

/// Step 1: each vertex onto the surface along its normal (the nearer hit either way, within
/// `reach` cubes), else to the surface's closest point. Counts the latter in `byClosestPoint`.
inline std::vector<Vec3d> projectAlongNormals(const TriangleMesh& mesh, std::span<const Vec3d> lattice,
                                              const PolycubeSurface& surface, std::size_t* byClosestPoint = nullptr,
                                              double reach = 2.0) {
  mesh.validate("polycube projection");
  if (lattice.size() != mesh.positions.size())
    throw Error(ErrorKind::InvalidArgument, "polycube projection: one lattice position per vertex is needed");
  const TriangleMesh cubes = surface.polycube().surfaceMesh();  // lattice units: exact integers
  const std::vector<Vec3d> corners(cubes.positions.begin(), cubes.positions.end());
  const TriangleBvh<double> bvh(corners, cubes.triangles);
  const std::vector<Vec3f> normals = computeVertexNormals(mesh);
  std::vector<Vec3d> out(lattice.size());
  std::vector<std::uint8_t> fellBack(lattice.size(), 0);
  parallelFor(0, lattice.size(), [&](std::size_t v) {
    const Vec3d x = lattice[v], n(normals[v]);
    std::optional<Vec3d> hitPoint;
    if (glm::dot(n, n) > 0.5) {
      double best = reach;
      for (double sign : {1.0, -1.0}) {
        const Hitd hit = bvh.closestHit(Rayd(x, sign * n, 0.0, best));
        if (hit.valid() && hit.t < best) {
          best = hit.t;
          hitPoint = x + sign * hit.t * n;
        }
      }
    }
    if (!hitPoint) {
      // A face's two triangles span its square, which is their bounding box: clamp to it.
      const std::uint32_t id = bvh.closestPoint(x).second;
      const Vec3u& t = cubes.triangles[id];
      Vec3d lo = corners[t[0]], hi = corners[t[0]];
      for (int k = 1; k < 3; ++k) {
        lo = glm::min(lo, corners[t[k]]);
        hi = glm::max(hi, corners[t[k]]);
      }
      hitPoint = glm::clamp(x, lo, hi);
      fellBack[v] = 1;
    }
    // Snap onto the surface exactly (a hit is on it up to rounding).
    out[v] = surface.project(*hitPoint).value_or(*hitPoint);
  }, 256);
  if (byClosestPoint) *byClosestPoint = std::size_t(std::count(fellBack.begin(), fellBack.end(), 1));
  return out;
}

/// Step 2: the local optimization, on one mesh, starting from given texture positions.
class PolycubeParameterizer {
 public:
  /// `lattice`: the mesh's positions in lattice coordinates; `texture`: where it starts.
  PolycubeParameterizer(std::span<const Vec3u> triangles, std::span<const Vec3d> lattice,
                        const PolycubeSurface& surface, std::vector<Vec3d> texture)
      : mSurface(surface), mTriangles(triangles.begin(), triangles.end()), mTexture(std::move(texture)) {
    if (mTexture.size() != lattice.size())
      throw Error(ErrorKind::InvalidArgument, "polycube parameterization: one texture position per vertex is needed");
    for (const Vec3u& t : mTriangles)
      for (int k = 0; k < 3; ++k)
        if (t[k] >= lattice.size())
          throw Error(ErrorKind::InvalidArgument, "polycube parameterization: a triangle refers to a missing vertex");
    buildRings(lattice);
    colourVertices();
    mNormals.resize(mTexture.size());
    for (std::size_t v = 0; v < mTexture.size(); ++v) mNormals[v] = mSurface.normal(mTexture[v]);
    chooseOrientation();
  }

  std::span<const Vec3d> texture() const { return mTexture; }

  Distortion distortion() const {
    return measureDistortion(mFrames, mTriangles, mTexture, [&](std::size_t i) { return outward(i); });
  }

  /// Untangles, then sweeps until the stopping rule holds; where flips are left (a fold the
  /// energy's barrier locked in), untangles and sweeps again, at most three rounds. Where a few
  /// flips (at most kRepairableFlips) are still left, all of it runs once more from the same
  /// start with untangling's fourth phase (repairFolds) on, and that second map is kept only if
  /// it has fewer flips than the first (the repair's random steps leave a little distortion
  /// behind). The fourth phase runs only then because it changes the path of maps that untangle
  /// without it (Laurana, extended MIPS: angle distortion 1.072 with it on from the start, 1.052
  /// without). Returns the sweeps run, both attempts counted.
  int optimize(const ParameterizationOptions& options) {
    mOptions = options;
    const std::vector<Vec3d> startTexture = mTexture, startNormals = mNormals;
    int sweep = optimizeInRounds(options, 0);
    const std::size_t flipped = survey().flipped;
    if (!options.repairFolds || options.energy == PolycubeEnergy::MeanValue || flipped == 0 ||
        flipped > kRepairableFlips)
      return sweep;
    // A second attempt from the same start, with untangling's fourth phase (repairFolds).
    std::vector<Vec3d> firstTexture = std::exchange(mTexture, startTexture);
    std::vector<Vec3d> firstNormals = std::exchange(mNormals, startNormals);
    mRepairFolds = true;
    sweep = optimizeInRounds(options, sweep);
    mRepairFolds = false;
    if (survey().flipped >= flipped) {
      mTexture = std::move(firstTexture);
      mNormals = std::move(firstNormals);
      survey();
    }
    return sweep;
  }

 private:
  /// Up to three rounds of untangling and sweeps (see optimize); `sweep` counts on.
  int optimizeInRounds(const ParameterizationOptions& options, int sweep) {
    for (int round = 0; round < 3; ++round) {
      sweep = untangle(options, sweep);
      sweep = settle(options, sweep);
      if (survey().flipped == 0 || options.energy == PolycubeEnergy::MeanValue) break;
    }
    return sweep;
  }

  /// Sweeps of the chosen energy until a sweep changes little (options.stopChange) or
  /// options.maxSweeps ran; `sweep` counts on from where it was.
  int settle(const ParameterizationOptions& options, int sweep) {
    double before = survey().energy;
    for (int limit = sweep + options.maxSweeps; sweep < limit;) {
      ++sweep;
      const double largestMove = options.energy == PolycubeEnergy::MeanValue ? meanValueSweep() : energySweep();
      const double after = survey().energy;
      if (options.progress) options.progress(sweep, distortion());
      const bool settled = options.energy == PolycubeEnergy::MeanValue ? largestMove < options.stopChange
                                                                       : before - after < options.stopChange * before;
      if (settled || largestMove == 0) break;
      before = after;
    }
    return sweep;
  }

  struct RingEnergy {
    std::size_t flipped = 0;
    double energy = 0;
    bool operator<(const RingEnergy& o) const {
      return flipped != o.flipped ? flipped < o.flipped : energy < o.energy;
    }
  };

  void buildRings(std::span<const Vec3d> lattice) {
    const std::size_t n = lattice.size();
    mFrames.resize(mTriangles.size());
    mRingStart.assign(n + 1, 0);
    for (std::size_t i = 0; i < mTriangles.size(); ++i) {
      const Vec3u& t = mTriangles[i];
      mFrames[i] = TriangleFrame(lattice[t[0]], lattice[t[1]], lattice[t[2]]);
      for (int k = 0; k < 3; ++k) ++mRingStart[t[k] + 1];
    }
    for (std::size_t v = 0; v < n; ++v) mRingStart[v + 1] += mRingStart[v];
    mRing.resize(mRingStart[n]);
    std::vector<std::size_t> fill(mRingStart.begin(), mRingStart.end() - 1);
    for (std::size_t i = 0; i < mTriangles.size(); ++i)
      for (int k = 0; k < 3; ++k) mRing[fill[mTriangles[i][k]]++] = std::uint32_t(i);
    buildMeanValueWeights(lattice);
  }

  /// Floater's weights from the mesh's own angles: w_j = (tan(a/2) + tan(b/2)) / |x_j - x_v|
  /// over the two triangles beside edge vj; a boundary vertex (an edge with one triangle) stays.
  void buildMeanValueWeights(std::span<const Vec3d> lattice) {
    const std::size_t n = lattice.size();
    mNeighbourStart.assign(n + 1, 0);
    mBoundary.assign(n, 0);
    std::vector<std::pair<std::uint32_t, double>> ring;
    std::vector<std::vector<std::pair<std::uint32_t, double>>> all(n);
    for (std::size_t v = 0; v < n; ++v) {
      ring.clear();
      std::vector<std::pair<std::uint32_t, int>> edgeUse;
      for (std::size_t r = mRingStart[v]; r < mRingStart[v + 1]; ++r) {
        const Vec3u& t = mTriangles[mRing[r]];
        const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        const std::uint32_t j = t[(k + 1) % 3], l = t[(k + 2) % 3];
        const Vec3d a = lattice[j] - lattice[v], b = lattice[l] - lattice[v];
        const double la = glm::length(a), lb = glm::length(b);
        const double angle = la > 0 && lb > 0 ? std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0)) : 0.0;
        const double half = std::tan(0.5 * angle);
        ring.push_back({j, la > 0 ? half / la : 0.0});
        ring.push_back({l, lb > 0 ? half / lb : 0.0});
        edgeUse.push_back({j, 1});
        edgeUse.push_back({l, 1});
      }
      std::sort(ring.begin(), ring.end());
      std::sort(edgeUse.begin(), edgeUse.end());
      for (std::size_t e = 0; e < edgeUse.size();) {  // an edge used by one triangle: boundary
        std::size_t f = e;
        while (f < edgeUse.size() && edgeUse[f].first == edgeUse[e].first) ++f;
        if (f - e == 1) mBoundary[v] = 1;
        e = f;
      }
      for (const auto& [j, w] : ring) {
        if (!all[v].empty() && all[v].back().first == j) all[v].back().second += w;
        else all[v].push_back({j, w});
      }
      mNeighbourStart[v + 1] = mNeighbourStart[v] + all[v].size();
    }
    mNeighbours.reserve(mNeighbourStart[n]);
    for (auto& list : all) mNeighbours.insert(mNeighbours.end(), list.begin(), list.end());
  }

  /// A triangle's outward direction: the sum of the surface normals at its corners, turned
  /// round when the mesh is oriented inwards.
  Vec3d outward(std::size_t i) const {
    const Vec3u& t = mTriangles[i];
    return mOrientation * (mNormals[t[0]] + mNormals[t[1]] + mNormals[t[2]]);
  }

  void chooseOrientation() {
    double signedArea = 0;
    mOrientation = 1;
    for (std::size_t i = 0; i < mTriangles.size(); ++i) {
      if (mFrames[i].degenerate()) continue;
      const Vec3u& t = mTriangles[i];
      signedArea += triangleStretch(mFrames[i], mTexture[t[0]], mTexture[t[1]], mTexture[t[2]], outward(i)).signedArea;
    }
    if (signedArea < 0) mOrientation = -1;
  }

  /// One triangle's energy, area-weighted; infinity when it is flipped or flat, unless the
  /// untangling regularization is on: then s1 s2 is replaced by (D + sqrt(eps^2 + D^2)) / 2,
  /// positive for every triangle and close to D where D >> eps (Garanzha et al. 2021,
  /// "Foldover-free maps in 50 lines of code"), so descent can pull flipped triangles back.
  /// The third untangling phase uses that paper's energy, MIPS plus (D^2 + 1) / s1 s2 for the
  /// area, which grows only as 1 / s1 s2 where extended MIPS grows as its fourth power.
  double triangleEnergy(const TriangleFrame& frame, const TriangleStretch& s) const {
    const double d = s.signedArea / (frame.area * mScale2);
    const double s1s2 = mEpsilon > 0 ? regularized(d) : d;
    if (!(s1s2 > kFlatShare)) return std::numeric_limits<double>::infinity();
    const double angle = s.frobenius2 / mScale2 / s1s2;  // s1/s2 + s2/s1
    if (mUntangleEnergy) return frame.area * (angle + (d * d + 1) / s1s2);
    if (mOptions.energy != PolycubeEnergy::ExtendedMips) return frame.area * angle;
    return frame.area * angle * std::pow(s1s2 + 1 / s1s2, mOptions.theta);
  }

  /// The energy of v's triangles with v at `p` (normal `n`).
  RingEnergy ringEnergy(std::size_t v, const Vec3d& p, const Vec3d& n) const {
    RingEnergy e;
    for (std::size_t r = mRingStart[v]; r < mRingStart[v + 1]; ++r) {
      const std::uint32_t i = mRing[r];
      if (mFrames[i].degenerate()) continue;
      const Vec3u& t = mTriangles[i];
      Vec3d w[3], normal(0.0);
      for (int k = 0; k < 3; ++k) {
        w[k] = t[k] == v ? p : mTexture[t[k]];
        normal += t[k] == v ? n : mNormals[t[k]];
      }
      const TriangleStretch s = triangleStretch(mFrames[i], w[0], w[1], w[2], mOrientation * normal);
      const double energy = triangleEnergy(mFrames[i], s);
      if (std::isfinite(energy)) e.energy += energy;
      else ++e.flipped;
    }
    return e;
  }

  struct Survey {
    std::size_t flipped = 0;  ///< flipped or flat triangles
    double energy = 0;        ///< of the others
    double smallestArea = 0;  ///< the smallest signed texture area over the triangle's share
  };

  /// One pass over the triangles at the current positions: the flipped ones, the area scale
  /// (texture area per unit of mesh area over the others, which the energies compare areas at
  /// until the next survey) and the total energy. `flippedOut`, when given, gets the flipped or
  /// flat triangles' indices.
  Survey survey(std::vector<std::uint32_t>* flippedOut = nullptr) {
    std::vector<TriangleStretch> stretch(mTriangles.size());
    Survey result;
    double mesh = 0, texture = 0;
    for (std::size_t i = 0; i < mTriangles.size(); ++i) {
      if (mFrames[i].degenerate()) continue;
      const Vec3u& t = mTriangles[i];
      stretch[i] = triangleStretch(mFrames[i], mTexture[t[0]], mTexture[t[1]], mTexture[t[2]], outward(i));
      if (stretch[i].signedArea > 0) {
        mesh += mFrames[i].area;
        texture += stretch[i].signedArea;
      }
    }
    mScale2 = mesh > 0 && texture > 0 ? texture / mesh : 1.0;
    result.smallestArea = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < mTriangles.size(); ++i) {
      if (mFrames[i].degenerate()) continue;
      result.smallestArea = std::min(result.smallestArea, stretch[i].signedArea / (mFrames[i].area * mScale2));
      if (flippedOrFlat(stretch[i].signedArea, mFrames[i].area, mScale2)) {
        ++result.flipped;
        if (flippedOut) flippedOut->push_back(std::uint32_t(i));
      }
      const double e = triangleEnergy(mFrames[i], stretch[i]);
      if (std::isfinite(e)) result.energy += e;
    }
    return result;
  }

  /// Untangles the folds normal projection leaves at the polycube's concave creases and where
  /// a feature is thinner than a cube. Three phases of sweeps, each run until 20 sweeps have not
  /// lowered the number of flipped triangles and each starting from the state with the fewest:
  /// 1. mean-value sweeps;
  /// 2. the chosen energy, regularized with eps shrinking by a tenth per sweep;
  /// 3. Garanzha et al.'s energy and eps rule: after three sweeps at one eps, with sigma the
  ///    fraction they lowered the energy by (at least 1/10) and D- the smallest normalized
  ///    area, mu = (1 - sigma) chi(D-, eps) and eps = 2 sqrt(mu (mu - D-)) while D- < mu.
  ///    It keeps eps near the worst fold's size, where the fixed schedule of phase 2 shrinks
  ///    it past folds that are not yet undone (the armadillo at N = 16: 10 flips left by phase
  ///    2 on its 3,000-vertex decimation, 1 by phase 3).
  /// Then, from the state with the fewest flips, in optimize's second attempt only, 4. the
  ///    flipped triangles' patches moved together (repairFolds), for the last few.
  /// Phases 2 to 4 run only while flips are left. Returns the sweep count, continued from
  /// `sweep`; phase 3 counts each of its sweeps, phase 4 each pass.
  int untangle(const ParameterizationOptions& options, int sweep) {
    const int limit = sweep + options.maxSweeps;
    std::size_t best = survey().flipped;
    std::vector<Vec3d> bestTexture = mTexture, bestNormals = mNormals;
    mInVertexOrder = true;
    for (int phase = 1; phase <= 3 && best > 0 && sweep < limit; ++phase) {
      mTexture = bestTexture;
      mNormals = bestNormals;
      mEpsilon = phase == 1 ? 0.0 : 1.0;
      mUntangleEnergy = phase == 3;
      Survey now = survey();  // also the area scale of the restored positions
      for (int sinceBest = 0; best > 0 && sweep < limit && sinceBest < 20;) {
        if (phase == 1) {
          meanValueSweep();
          ++sweep;
          now = survey();
        } else if (phase == 2) {
          energySweep();
          ++sweep;
          mEpsilon = std::max(1e-3, 0.9 * mEpsilon);
          now = survey();
        } else {
          now = adaptiveEpsilonStep(now.energy, sweep);
        }
        if (options.progress) options.progress(sweep, distortion());
        if (now.flipped < best) {
          best = now.flipped;
          bestTexture = mTexture;
          bestNormals = mNormals;
          sinceBest = 0;
        } else {
          ++sinceBest;
        }
      }
    }
    mEpsilon = 0;
    mUntangleEnergy = false;
    mInVertexOrder = false;
    mTexture = std::move(bestTexture);
    mNormals = std::move(bestNormals);
    if (best > 0 && mRepairFolds) sweep = repairFolds(options, sweep);
    return sweep;
  }

  /// Untangling's fourth phase, for the few folds the sweeps leave (at most kRepairableFlips), in
  /// optimize's second attempt only: the vertices within one ring of each flipped triangle's
  /// corners (then two, then three, while it stays flipped) move together, by a (1+1) evolution
  /// strategy, until no triangle of theirs is flipped. A sweep moves one vertex at a time down
  /// its own energy, and some folds only open when several move at once: on fertility's
  /// polycube (N = 24) a triangle across the concave crease of a case-6b vertex stays flipped
  /// through every sweep, and no single corner has a place where its triangles all face out.
  /// Per patch: a trial moves each vertex with probability 1/2 by a normal step of radius r
  /// (P puts it back on the surface) and is kept when it lowers (flipped triangles, sum over
  /// the patch's triangles of area x max(0, 1/10 - D)), D the normalized texture area; r grows
  /// by 3/2 after a kept trial and shrinks by 0.95 after a rejected one (steady at about one
  /// trial in nine kept), from half the patch's longest edge and never past a cube, for at most
  /// kRepairTrials. A vertex whose move would turn its normal past a right angle stays: that is
  /// the far side of a part thinner than the step, where P also takes points. The
  /// steps come from a splitmix64 sequence seeded by (triangle, pass, rings), so the result
  /// depends on neither the thread count nor a library's random distributions. Passes repeat
  /// while a patch improves, at most kRepairPasses. The energy is not looked at; the sweeps
  /// after it restore it.
  int repairFolds(const ParameterizationOptions& options, int sweep) {
    for (int pass = 0; pass < kRepairPasses; ++pass) {
      const std::vector<std::uint32_t> flipped = flippedTriangles();
      if (flipped.empty() || flipped.size() > kRepairableFlips) break;
      bool improved = false;
      for (const std::uint32_t triangle : flipped)
        improved = repairPatch(triangle, std::uint64_t(pass)) || improved;
      ++sweep;
      if (options.progress) options.progress(sweep, distortion());
      if (!improved) break;
    }
    survey();  // the area scale of the positions the next sweeps start from
    return sweep;
  }

  static constexpr std::size_t kRepairableFlips = 64;
  static constexpr int kRepairPasses = 4;
  static constexpr int kRepairTrials = 4096;
  static constexpr int kRepairRings = 3;  ///< the widest patch: vertices within 3 rings of the corners
  /// The largest step radius of a repair trial, in cubes.
  static constexpr double kRepairLongestStep = 1.0;
  /// A move whose normal has a component beyond this against the vertex's current one lands
  /// on the far side of a thin part (see evolvePatch).
  static constexpr double kRepairFarSide = 0.1;
  /// The normalized texture area below which a triangle still counts against its patch.
  static constexpr double kRepairMargin = 0.1;

  /// The flipped or flat triangles at the current positions (and the area scale, by survey).
  std::vector<std::uint32_t> flippedTriangles() {
    std::vector<std::uint32_t> flipped;
    survey(&flipped);
    return flipped;
  }

  struct PatchScore {
    std::size_t flipped = 0;
    double shortfall = 0;  ///< sum of area x max(0, kRepairMargin - D)
    bool operator<(const PatchScore& o) const {
      return flipped != o.flipped ? flipped < o.flipped : shortfall < o.shortfall;
    }
  };

  PatchScore patchScore(std::span<const std::uint32_t> triangles) const {
    PatchScore score;
    for (const std::uint32_t i : triangles) {
      if (mFrames[i].degenerate()) continue;
      const Vec3u& t = mTriangles[i];
      const TriangleStretch s = triangleStretch(mFrames[i], mTexture[t[0]], mTexture[t[1]], mTexture[t[2]], outward(i));
      if (flippedOrFlat(s.signedArea, mFrames[i].area, mScale2)) ++score.flipped;
      const double d = s.signedArea / (mFrames[i].area * mScale2);
      score.shortfall += mFrames[i].area * std::max(0.0, kRepairMargin - d);
    }
    return score;
  }

  /// One flipped triangle's repair (see repairFolds): the vertices within one ring of its
  /// corners, then two, then three, until none of their triangles is flipped. Whether the
  /// flipped count or the shortfall fell.
  bool repairPatch(std::uint32_t flippedTriangle, std::uint64_t pass) {
    const Vec3u& corners = mTriangles[flippedTriangle];
    std::vector<std::uint32_t> movers = {corners[0], corners[1], corners[2]};
    bool improved = false;
    for (int rings = 1; rings <= kRepairRings; ++rings) {
      addNeighbours(movers);
      const std::uint64_t seed = (std::uint64_t(flippedTriangle) << 8) ^ (pass * 0xd1b54a32d192ed03ull) ^ rings;
      const std::optional<PatchScore> after = evolvePatch(movers, seed);
      improved = improved || after.has_value();
      if (after && after->flipped == 0) break;
    }
    return improved;
  }

  /// Adds every neighbour of the vertices in `vertices` (sorted, each once).
  void addNeighbours(std::vector<std::uint32_t>& vertices) const {
    const std::size_t count = vertices.size();
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t n = mNeighbourStart[vertices[i]]; n < mNeighbourStart[vertices[i] + 1]; ++n)
        vertices.push_back(mNeighbours[n].first);
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  }

  /// The evolution strategy of repairFolds on the vertices `patch` (boundary vertices stay).
  /// Returns the patch's score when it fell, nothing when no trial was kept.
  std::optional<PatchScore> evolvePatch(std::span<const std::uint32_t> patch, std::uint64_t seed) {
    std::vector<std::uint32_t> movers, triangles;
    double largestEdge = 0;
    for (const std::uint32_t v : patch) {
      if (mBoundary[v]) continue;
      movers.push_back(v);
      for (std::size_t r = mRingStart[v]; r < mRingStart[v + 1]; ++r) triangles.push_back(mRing[r]);
      for (std::size_t n = mNeighbourStart[v]; n < mNeighbourStart[v + 1]; ++n)
        largestEdge = std::max(largestEdge, glm::length(mTexture[mNeighbours[n].first] - mTexture[v]));
    }
    std::sort(triangles.begin(), triangles.end());
    triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
    const PatchScore start = patchScore(triangles);
    if (movers.empty() || start.flipped == 0 || !(largestEdge > 0)) return std::nullopt;
    PatchScore best = start;
    std::vector<Vec3d> kept(movers.size()), keptNormals(movers.size());
    std::uint64_t state = seed;
    double radius = std::min(0.5 * largestEdge, kRepairLongestStep);
    for (int trial = 0; trial < kRepairTrials && best.flipped > 0 && radius > 1e-7 * largestEdge; ++trial) {
      for (std::size_t m = 0; m < movers.size(); ++m) {
        kept[m] = mTexture[movers[m]];
        keptNormals[m] = mNormals[movers[m]];
        if (unitInterval(state) < 0.5) continue;
        // One deviate per statement: the order a constructor's arguments are evaluated in is
        // unspecified, and each call advances the sequence.
        Vec3d step;
        step.x = normalDeviate(state);
        step.y = normalDeviate(state);
        step.z = normalDeviate(state);
        const std::optional<Vec3d> p = mSurface.project(kept[m] + radius * step);
        if (!p) continue;
        // A normal turned past a right angle is the far side of a part thinner than a step,
        // not a neighbouring face: such a move would fold the patch across it unseen.
        const Vec3d normal = mSurface.normal(*p);
        if (glm::dot(normal, keptNormals[m]) < -kRepairFarSide) continue;
        moveTo(movers[m], *p, normal);
      }
      if (const PatchScore score = patchScore(triangles); score < best) {
        best = score;
        radius = std::min(1.5 * radius, kRepairLongestStep);
      } else {
        for (std::size_t m = 0; m < movers.size(); ++m) moveTo(movers[m], kept[m], keptNormals[m]);
        radius *= 0.95;
      }
    }
    if (!(best < start)) return std::nullopt;
    return best;
  }

  /// A standard normal deviate from two values of the sequence (Box-Muller).
  static double normalDeviate(std::uint64_t& state) {
    const double u = unitInterval(state), v = unitInterval(state);
    return std::sqrt(-2 * std::log(u)) * std::cos(6.283185307179586 * v);
  }

  /// The next value of a splitmix64 sequence, in (0, 1] (never 0, so its logarithm is finite).
  static double unitInterval(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double(z >> 11) + 0.5) * 0x1.0p-53;
  }

  /// Untangling's phase 3, one step: three sweeps at the current eps, then the next eps by
  /// Garanzha et al.'s rule (see untangle) from the energy before them, `energyBefore`, and
  /// after. Returns the survey at the new eps (its energy is the next step's energyBefore).
  Survey adaptiveEpsilonStep(double energyBefore, int& sweep) {
    Survey after;
    for (int k = 0; k < 3; ++k, ++sweep) {
      energySweep();
      after = survey();  // the area scale the next sweep compares at
    }
    const double sigma = energyBefore > 0 ? std::max(1 - after.energy / energyBefore, 0.1) : 0.1;
    const double dMin = after.smallestArea;
    const double mu = (1 - sigma) * regularized(dMin);
    mEpsilon = dMin < mu ? std::max(2 * std::sqrt(mu * (mu - dMin)), 1e-6) : 1e-6;
    return survey();
  }

  /// chi(d, eps) = (d + sqrt(eps^2 + d^2)) / 2 at the current eps: positive for every d where
  /// eps > 0, close to d where d >> eps.
  double regularized(double d) const { return 0.5 * (d + std::sqrt(mEpsilon * mEpsilon + d * d)); }

  /// The mean-value average of v's neighbours' texture positions, taken onto the surface.
  std::optional<Vec3d> meanValueTarget(std::size_t v) const {
    Vec3d sum(0.0);
    double weight = 0;
    for (std::size_t k = mNeighbourStart[v]; k < mNeighbourStart[v + 1]; ++k) {
      sum += mNeighbours[k].second * mTexture[mNeighbours[k].first];
      weight += mNeighbours[k].second;
    }
    if (!(weight > 0)) return std::nullopt;
    return mSurface.project(sum / weight);
  }

  void moveTo(std::size_t v, const Vec3d& p, const Vec3d& n) {
    mTexture[v] = p;
    mNormals[v] = n;
  }

  /// Every interior vertex to its mean-value target; returns the largest move.
  double meanValueSweep() {
    return forEachVertexByColour([&](std::size_t v) {
      if (mBoundary[v]) return 0.0;
      const std::optional<Vec3d> target = meanValueTarget(v);
      if (!target) return 0.0;
      const double move = glm::length(*target - mTexture[v]);
      moveTo(v, *target, mSurface.normal(*target));
      return move;
    });
  }

  /// One descent step per vertex (see the file comment), at the area scale of the last survey,
  /// which every caller takes on the positions the sweep starts from; returns the largest move.
  double energySweep() {
    return forEachVertexByColour([&](std::size_t v) {
      RingEnergy current = ringEnergy(v, mTexture[v], mNormals[v]);
      const Vec3d start = mTexture[v];
      if (current.flipped > 0)
        if (const std::optional<Vec3d> target = meanValueTarget(v)) {
          const Vec3d n = mSurface.normal(*target);
          const RingEnergy e = ringEnergy(v, *target, n);
          if (e < current) {
            moveTo(v, *target, n);
            current = e;
          }
        }
      descend(v, current);
      return glm::length(mTexture[v] - start);
    });
  }

  /// Colours the vertices so that no two neighbours share one (greedy, in vertex order): a
  /// vertex's update reads only its neighbours and writes only itself, so the vertices of one
  /// colour update in parallel, and the result does not depend on the thread count.
  void colourVertices() {
    const std::size_t n = mTexture.size();
    std::vector<std::uint32_t> colour(n, 0);
    std::vector<std::uint8_t> taken;
    std::uint32_t colours = 0;
    for (std::size_t v = 0; v < n; ++v) {
      taken.assign(colours + 1, 0);
      for (std::size_t k = mNeighbourStart[v]; k < mNeighbourStart[v + 1]; ++k) {
        const std::uint32_t w = mNeighbours[k].first;
        if (w < v && colour[w] < taken.size()) taken[colour[w]] = 1;
      }
      std::uint32_t c = 0;
      while (taken[c]) ++c;
      colour[v] = c;
      colours = std::max(colours, c + 1);
    }
    mColourStart.assign(colours + 1, 0);
    for (std::size_t v = 0; v < n; ++v)
      if (mRingStart[v] != mRingStart[v + 1]) ++mColourStart[colour[v] + 1];
    for (std::uint32_t c = 0; c < colours; ++c) mColourStart[c + 1] += mColourStart[c];
    mByColour.resize(mColourStart[colours]);
    std::vector<std::size_t> fill(mColourStart.begin(), mColourStart.end() - 1);
    for (std::size_t v = 0; v < n; ++v)
      if (mRingStart[v] != mRingStart[v + 1]) mByColour[fill[colour[v]]++] = std::uint32_t(v);
    mMoves.assign(n, 0.0);
  }

  /// Calls update(v) for every vertex with triangles, colour by colour, each colour in
  /// parallel; returns the largest value update returned (the largest move).
  template <class Update>
  double forEachVertexByColour(Update&& update) {
    if (mInVertexOrder) {
      double largest = 0;
      for (std::size_t v = 0; v < mTexture.size(); ++v)
        if (mRingStart[v] != mRingStart[v + 1]) largest = std::max(largest, update(v));
      return largest;
    }
    for (std::size_t c = 0; c + 1 < mColourStart.size(); ++c)
      parallelFor(mColourStart[c], mColourStart[c + 1], [&](std::size_t i) {
        mMoves[mByColour[i]] = update(std::size_t(mByColour[i]));
      }, 64);
    double largest = 0;
    for (std::uint32_t v : mByColour) largest = std::max(largest, mMoves[v]);
    return largest;
  }

  /// The gradient of v's ring energy with respect to its texture position (normals held), over
  /// the triangles whose energy is finite. Per triangle, with X its texture area (signed), F the
  /// squared Frobenius norm of its Jacobian J = sum_k u_k g_k^T (g_k: the gradients of its
  /// barycentric coordinates on the mesh triangle), S the area scale and d = X / (A S) (or its
  /// regularization): E = A (F / (S d)) (d + 1/d)^theta, or in untangling's third phase
  /// A (F / (S d) + (D^2 + 1) / d) with D the unregularized d; dF/du_k = 2 J g_k and
  /// dX/du_k = +-(1/2) c^ x (u_{k+2} - u_{k+1}).
  Vec3d ringGradient(std::size_t v) const {
    Vec3d gradient(0.0);
    const double theta = mOptions.energy == PolycubeEnergy::ExtendedMips ? mOptions.theta : 0.0;
    for (std::size_t r = mRingStart[v]; r < mRingStart[v + 1]; ++r) {
      const std::uint32_t i = mRing[r];
      const TriangleFrame& frame = mFrames[i];
      if (frame.degenerate()) continue;
      const Vec3u& t = mTriangles[i];
      const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
      const Vec3d u0 = mTexture[t[0]], u1 = mTexture[t[1]], u2 = mTexture[t[2]];
      const TriangleJacobian j(frame, u0, u1, u2);
      const Vec2d g1(frame.inverse[0][0], frame.inverse[0][1]), g2(frame.inverse[1][0], frame.inverse[1][1]);
      const Vec2d gk = k == 0 ? -(g1 + g2) : k == 1 ? g1 : g2;
      const double length = glm::length(j.cross);
      if (!(length > 0)) continue;
      const double sign = glm::dot(j.cross, outward(i)) > 0 ? 1.0 : -1.0;
      const double area = sign * 0.5 * length;
      const double frobenius2 = j.frobenius2();
      const double raw = area / (frame.area * mScale2);
      double d = raw, dd = 1;  // d: s1 s2 or its regularization; dd: its derivative by raw
      if (mEpsilon > 0) {
        const double root = std::sqrt(mEpsilon * mEpsilon + raw * raw);
        dd = 0.5 * (1 + raw / root);
        d = 0.5 * (raw + root);
      }
      if (!(d > 0)) continue;
      double dEdF = 0, dEdRaw = 0;
      if (mUntangleEnergy) {  // A (F / (S d) + (raw^2 + 1) / d)
        dEdF = frame.area / (mScale2 * d);
        dEdRaw = frame.area * (2 * raw / d - (frobenius2 / mScale2 + raw * raw + 1) / (d * d) * dd);
      } else {
        const double q = theta > 0 ? std::pow(d + 1 / d, theta) : 1.0;
        const double dQ = theta > 0 ? theta * std::pow(d + 1 / d, theta - 1) * (1 - 1 / (d * d)) : 0.0;
        const double angle = frobenius2 / (mScale2 * d);
        dEdF = frame.area * q / (mScale2 * d);
        dEdRaw = frame.area * (-angle / d * q + angle * dQ) * dd;
      }
      const Vec3d dF = 2.0 * (j.column0 * gk.x + j.column1 * gk.y);
      const Vec3d& next = k == 0 ? u1 : k == 1 ? u2 : u0;
      const Vec3d& after = k == 0 ? u2 : k == 1 ? u0 : u1;
      const Vec3d dX = sign * 0.5 * glm::cross(j.cross / length, after - next);
      gradient += dEdF * dF + dEdRaw / (frame.area * mScale2) * dX;
    }
    return gradient;
  }

  /// A backtracking step down the tangential gradient of v's ring energy.
  void descend(std::size_t v, const RingEnergy& current) {
    const Vec3d p = mTexture[v], n = mNormals[v];
    double shortest = std::numeric_limits<double>::infinity();
    // A neighbour at the same point (a fold collapsed onto one point) gives no length: the
    // step takes the shortest of the others, or the vertex would never leave it.
    for (std::size_t k = mNeighbourStart[v]; k < mNeighbourStart[v + 1]; ++k)
      if (const double d = glm::length(mTexture[mNeighbours[k].first] - p); d > 0) shortest = std::min(shortest, d);
    if (!std::isfinite(shortest)) return;
    Vec3d gradient = ringGradient(v);
    gradient -= glm::dot(gradient, n) * n;
    const double length = glm::length(gradient);
    if (!(length > 0) || !std::isfinite(length)) return;
    double distance = 0.5 * shortest;
    for (int halving = 0; halving < 12; ++halving, distance *= 0.5) {
      const std::optional<Vec3d> candidate = mSurface.project(p - (distance / length) * gradient);
      if (!candidate) continue;
      const Vec3d candidateNormal = mSurface.normal(*candidate);
      if (ringEnergy(v, *candidate, candidateNormal) < current) {
        moveTo(v, *candidate, candidateNormal);
        return;
      }
    }
  }

  const PolycubeSurface& mSurface;
  std::vector<Vec3u> mTriangles;
  std::vector<TriangleFrame> mFrames;
  std::vector<std::size_t> mRingStart;
  std::vector<std::uint32_t> mRing;  ///< triangles around each vertex
  std::vector<std::size_t> mNeighbourStart;
  std::vector<std::pair<std::uint32_t, double>> mNeighbours;  ///< with their mean value weights
  std::vector<std::uint8_t> mBoundary;
  std::vector<std::size_t> mColourStart;
  std::vector<std::uint32_t> mByColour;  ///< vertices with triangles, colour by colour
  std::vector<double> mMoves;            ///< each vertex's move in the last sweep
  /// Untangling sweeps run in vertex order, one vertex after the other: a mesh's vertex order is
  /// mostly coherent in space, so one sweep carries a change across the mesh, where colour by
  /// colour it moves one ring per sweep; folds resolve in far fewer sweeps.
  bool mInVertexOrder = false;
  std::vector<Vec3d> mTexture, mNormals;
  double mOrientation = 1;
  double mScale2 = 1;
  double mEpsilon = 0;  ///< the untangling regularization, 0 when off
  bool mUntangleEnergy = false;  ///< untangling's third phase: Garanzha et al.'s energy
  bool mRepairFolds = false;     ///< untangling's fourth phase on (optimize's second attempt)
  ParameterizationOptions mOptions;
};

/// Both steps: texture positions for every vertex of `mesh` on `surface`, placed in world space
/// by `frame`; a large mesh starts from the map of its decimation (options.coarseVertices).
inline PolycubeParameterization parameterize(const TriangleMesh& mesh, const PolycubeSurface& surface,
                                             const PolycubeFrame& frame, const ParameterizationOptions& options = {}) {
  const auto start = std::chrono::steady_clock::now();
  if (mesh.triangles.empty())
    throw Error(ErrorKind::InvalidArgument, "polycube parameterization: the mesh has no triangles");
  mesh.validate("polycube parameterization");  // indices and coordinates, before anything reads them
  const std::vector<Vec3d> lattice = latticePositions(mesh, frame);
  PolycubeParameterization result;
  std::vector<Vec3d> texture;
  if (options.coarseVertices > 0 && mesh.positions.size() > 2 * options.coarseVertices) {
    const TriangleMesh coarse = decimate(mesh, options.coarseVertices);
    ParameterizationOptions coarseOptions = options;
    coarseOptions.coarseVertices = 0;
    coarseOptions.repairFolds = false;
    const PolycubeParameterization coarseMap = parameterize(coarse, surface, frame, coarseOptions);
    result.coarseVertices = coarse.positions.size();
    result.coarseSweeps = coarseMap.sweeps;
    result.byClosestPoint = coarseMap.byClosestPoint;
    texture = transferTexturePositions(latticePositions(coarse, frame), coarse.triangles, coarseMap.texture, lattice,
                                       surface);
  } else {
    texture = projectAlongNormals(mesh, lattice, surface, &result.byClosestPoint);
  }
  PolycubeParameterizer parameterizer(mesh.triangles, lattice, surface, std::move(texture));
  result.initial = parameterizer.distortion();
  result.sweeps = parameterizer.optimize(options);
  result.final = parameterizer.distortion();
  result.texture.assign(parameterizer.texture().begin(), parameterizer.texture().end());
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace cellrelief::polycube
