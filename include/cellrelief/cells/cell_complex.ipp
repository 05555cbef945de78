// SPDX-License-Identifier: MIT
/// @file cell_complex.ipp
/// CellComplex::build: snap, bin triangles into cells with the exact overlap test, flood-fill the
/// non-grey cells, classify enclosed components by winding number, derive configurations, and
/// store the result in an OpenVDB grid.
#pragma once

namespace cellrelief::cells {

namespace detail {
enum : std::uint8_t { kUnvisited = 0, kLabelWhite = 1, kLabelBlack = 2, kLabelGrey = 3 };

inline std::string mib(std::size_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

/// Per axis, the distinct coordinates of the axis planes that hold a whole triangle (its three
/// vertices share the coordinate), sorted.
inline std::array<std::vector<double>, 3> axisPlanesOfTriangles(const TriangleMesh& mesh) {
  std::array<std::vector<double>, 3> planes;
  for (const Vec3u& t : mesh.triangles)
    for (int a = 0; a < 3; ++a) {
      const float c = mesh.positions[t[0]][a];
      if (mesh.positions[t[1]][a] == c && mesh.positions[t[2]][a] == c) planes[a].push_back(c);
    }
  for (std::vector<double>& p : planes) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
  }
  return planes;
}

/// How far a lattice coordinate u (in cells) lies from the planes where projections end or pass
/// (the grid planes, u integer, and the planes through the cells' middles, u + 1/2 integer), as a
/// fraction of a cell in [0, 1/4].
inline double offProjectionPlanes(double u) {
  const double half = 2.0 * u;
  return 0.5 * std::abs(half - std::round(half));
}

/// The shift phi in [0, 1/2) (in cells) that keeps every u_i + phi farthest from the projection
/// planes (period 1/2): the middle of the widest gap between the points -u_i, modulo 1/2.
inline double shiftOffProjectionPlanes(const std::vector<double>& u) {
  std::vector<double> q;  // -u_i in half cells, in [0, 1)
  for (const double x : u) {
    const double g = 2.0 * x;
    q.push_back(std::fmod(1.0 - (g - std::floor(g)), 1.0));
  }
  std::sort(q.begin(), q.end());
  double bestGap = -1, bestMid = 0.5;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double next = i + 1 < q.size() ? q[i + 1] : q[0] + 1.0;
    if (next - q[i] > bestGap) {
      bestGap = next - q[i];
      bestMid = q[i] + 0.5 * bestGap;
    }
  }
  return 0.5 * (bestMid - std::floor(bestMid));
}

/// Where the lattice lies: its minimum corner and cell size.
struct GridPlacement {
  Vec3d minWS{0};
  double cellSizeWS = 0;
};

/// The lattice of an N^3 complex over `box`, the bounds of the mesh. By default it is the bounding
/// cube, centred. A surface lying in a plane where projection lines end or run (grid planes, and
/// the planes of the centres, axes and planar projections, all at 0 or 1/2 of a cell) meets the
/// lines only at their ends or along their length, so neither cell beside it would store it: a
/// flat mesh, the middle plane of a symmetric model, axis-aligned faces a whole number of cells
/// apart. When a whole triangle lies in such a plane, the cube grows by half a cell (h = longest
/// extent / (N - 1/2)) and, per axis, the lattice is shifted so that every plane holding a triangle
/// keeps as far from those planes as the others allow (a quarter cell for one plane), with the mesh
/// as near the middle as that leaves. Planes on the cube's boundary need nothing: there the
/// surface lies on an external face, at distance 0.
inline GridPlacement placeGrid(const TriangleMesh& mesh, const Aabbd& box, int n, bool avoidProjectionPlanes) {
  const Aabbd cube = box.boundingCube(0.0);
  GridPlacement place{cube.min, cube.extent().x / n};
  if (!avoidProjectionPlanes) return place;
  const Vec3d extent = box.extent();
  const std::array<std::vector<double>, 3> planes = axisPlanesOfTriangles(mesh);
  // A little more than the snapping step: a plane that close to a grid plane snaps onto it.
  constexpr double kOnPlane = 16.0 / double(kCellUnits);
  auto onProjectionPlane = [&](int a, double c) {
    const double u = (c - place.minWS[a]) / place.cellSizeWS;
    const bool onBoundary = std::abs(u) < kOnPlane || std::abs(u - n) < kOnPlane;
    return !onBoundary && offProjectionPlanes(u) < kOnPlane;
  };
  bool shift = false;
  for (int a = 0; a < 3; ++a)
    for (const double c : planes[a]) shift = shift || onProjectionPlane(a, c);
  if (shift) {
    const double h = std::max({extent.x, extent.y, extent.z}) / (n - 0.5);
    place.cellSizeWS = h;
    for (int a = 0; a < 3; ++a) {
      const double slack = n * h - extent[a];  // at least half a cell
      double delta = 0.5 * slack;              // how far the lattice starts below the mesh
      if (!planes[a].empty()) {
        std::vector<double> u;
        for (const double c : planes[a]) u.push_back((c - box.min[a]) / h);
        const double phi = shiftOffProjectionPlanes(u);
        // delta = phi h + k h / 2 for the whole k nearest the middle that keeps the mesh inside.
        const double kMax = std::floor((slack / h - phi) * 2.0);
        const double k = std::clamp(std::round((0.5 * slack / h - phi) * 2.0), 0.0, kMax);
        delta = (phi + 0.5 * k) * h;
      }
      place.minWS[a] = box.min[a] - delta;
    }
  }
  return place;
}
}  // namespace detail

inline CellComplex CellComplex::build(const TriangleMesh& mesh, const ComplexOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int n = options.gridSize;
  if (n < 1 || n > kMaxGridSize)
    throw Error(ErrorKind::InvalidArgument, "grid size N = " + std::to_string(n) +
                                                " is out of range (1 to " +
                                                std::to_string(kMaxGridSize) + ")");
  if (mesh.triangles.empty())
    throw Error(ErrorKind::InvalidInput, "the mesh has no triangles: nothing to classify");
  if (mesh.triangles.size() >= (std::size_t(1) << 31))
    throw Error(ErrorKind::ResourceLimit, "2^31 triangles or more: over what one complex indexes");
  mesh.validate("mesh");
  const std::size_t estimate = estimateMemory(mesh.triangles.size(), n);
  if (estimate > options.memoryLimitBytes)
    throw Error(ErrorKind::ResourceLimit,
                "grid size N = " + std::to_string(n) + " needs about " + detail::mib(estimate) +
                    ", over the limit of " + detail::mib(options.memoryLimitBytes));

  // Bounds of the referenced vertices (unreferenced ones, as in the bunny, do not count).
  Aabbd box;
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) box.extend(Vec3d(mesh.positions[t[k]]));
  const Vec3d extent = box.extent();
  if (std::max({extent.x, extent.y, extent.z}) <= 0)
    throw Error(ErrorKind::InvalidInput, "the mesh has zero extent (all vertices coincide)");

  CellComplex c;
  c.mGridSize = n;
  const detail::GridPlacement place =
      detail::placeGrid(mesh, box, n, options.offProjectionPlanes);
  c.mCellSizeWS = place.cellSizeWS;
  const double side = n * c.mCellSizeWS;
  c.mBoundsWS = Aabbd(place.minWS, place.minWS + Vec3d(side));

  // Snap to the fixed-point lattice of index space.
  const std::int64_t maxCoord = std::int64_t(n) * kCellUnits;
  const double scale = double(n) * double(kCellUnits) / side;
  std::vector<FixedPoint3> fixed(mesh.positions.size());
  c.mSnappedIS.resize(mesh.positions.size());
  parallelFor(0, mesh.positions.size(), [&](std::size_t i) {
    const Vec3d q = (Vec3d(mesh.positions[i]) - c.mBoundsWS.min) * scale;
    for (int a = 0; a < 3; ++a)
      fixed[i][a] = std::clamp<std::int64_t>(std::llround(q[a]), 0, maxCoord);
    c.mSnappedIS[i] = Vec3d(fixed[i]) / double(kCellUnits);
  });

  // Bin triangles into the cells they meet: keys (cell << 32 | triangle), sorted.
  tbb::enumerable_thread_specific<std::vector<std::uint64_t>> localKeys;
  const std::uint64_t nn = std::uint64_t(n);
  parallelForRange(0, mesh.triangles.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint64_t>& out = localKeys.local();
    for (std::size_t f = begin; f < end; ++f) {
      const Vec3u& t = mesh.triangles[f];
      const FixedPoint3 &a = fixed[t[0]], &b = fixed[t[1]], &cc = fixed[t[2]];
      Vec3i lo(0), hi(0);  // every component is set below; GCC at -O2 cannot tell
      for (int k = 0; k < 3; ++k) {
        const std::int64_t mn = std::min({a[k], b[k], cc[k]}), mx = std::max({a[k], b[k], cc[k]});
        // Closed cells: cell i meets [mn, mx] iff i S <= mx and (i + 1) S >= mn.
        lo[k] = int(std::max<std::int64_t>(0, ((mn + kCellUnits - 1) >> kFractionBits) - 1));
        hi[k] = int(std::min<std::int64_t>(n - 1, mx >> kFractionBits));
      }
      const bool single = lo == hi;  // the triangle lies inside one closed cell
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) {
            if (!single) {
              const FixedPoint3 cmin(std::int64_t(x) * kCellUnits, std::int64_t(y) * kCellUnits,
                                     std::int64_t(z) * kCellUnits);
              if (!triangleOverlapsBox(a, b, cc, cmin, cmin + FixedPoint3(kCellUnits))) continue;
            }
            const std::uint64_t cell = (std::uint64_t(z) * nn + std::uint64_t(y)) * nn + x;
            out.push_back((cell << 32) | f);
          }
    }
  }, 256);
  std::vector<std::uint64_t> keys;
  {
    std::size_t total = 0;
    for (const auto& v : localKeys) total += v.size();
    keys.reserve(total);
    for (auto& v : localKeys) {
      keys.insert(keys.end(), v.begin(), v.end());
      std::vector<std::uint64_t>().swap(v);
    }
  }
  if (keys.size() >= (std::size_t(1) << 32))
    throw Error(ErrorKind::ResourceLimit, "over 2^32 cell-triangle pairs: use a smaller N");
  tbb::parallel_sort(keys.begin(), keys.end());

  // Grey cells with their triangle lists (CSR), and the dense scratch labels.
  std::vector<std::uint8_t> labels(nn * nn * nn, detail::kUnvisited);
  c.mCellTriangles.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::uint64_t cell = keys[i] >> 32;
    c.mCellTriangles[i] = std::uint32_t(keys[i] & 0xffffffffu);
    if (i == 0 || (keys[i - 1] >> 32) != cell) {
      GreyCell g;
      g.ijk = Vec3i(int(cell % nn), int((cell / nn) % nn), int(cell / (nn * nn)));
      g.firstTriangle = std::uint32_t(i);
      c.mGreyCells.push_back(g);
      labels[cell] = detail::kLabelGrey;
    }
    ++c.mGreyCells.back().triangleCount;
  }
  std::vector<std::uint64_t>().swap(keys);

  // Flood fill: non-grey cells reachable from the grid boundary are white.
  auto linear = [&](int x, int y, int z) { return (std::uint64_t(z) * nn + y) * nn + x; };
  std::vector<std::uint64_t> queue;
  auto bfs = [&](std::uint8_t label) {
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint64_t id = queue[head];
      const int x = int(id % nn), y = int((id / nn) % nn), z = int(id / (nn * nn));
      const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                            {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n || q[1] >= n || q[2] >= n) continue;
        const std::uint64_t qi = linear(q[0], q[1], q[2]);
        if (labels[qi] != detail::kUnvisited) continue;
        labels[qi] = label;
        queue.push_back(qi);
      }
    }
  };
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        if (x != 0 && y != 0 && z != 0 && x != n - 1 && y != n - 1 && z != n - 1) continue;
        const std::uint64_t id = linear(x, y, z);
        if (labels[id] != detail::kUnvisited) continue;
        labels[id] = detail::kLabelWhite;
        queue.push_back(id);
      }
  bfs(detail::kLabelWhite);

  // Enclosed components: one winding-number query each.
  for (std::uint64_t id = 0; id < labels.size(); ++id) {
    if (labels[id] != detail::kUnvisited) continue;
    const Vec3d centre(double(id % nn) + 0.5, double((id / nn) % nn) + 0.5,
                       double(id / (nn * nn)) + 0.5);
    const double w = windingNumber(c.mSnappedIS, mesh.triangles, centre);
    const std::uint8_t label = std::abs(w) > 0.5 ? detail::kLabelBlack : detail::kLabelWhite;
    queue.assign(1, id);
    labels[id] = label;
    bfs(label);
    ++c.mStats.enclosedComponents;
  }
  std::vector<std::uint64_t>().swap(queue);

  // Configurations: a face is external when the neighbour across it is white or outside the grid.
  parallelFor(0, c.mGreyCells.size(), [&](std::size_t i) {
    GreyCell& g = c.mGreyCells[i];
    std::uint8_t config = 0;
    for (int f = 0; f < kFaceCount; ++f) {
      const Vec3i q = g.ijk + faceNormal(f);
      const bool outside = q.x < 0 || q.y < 0 || q.z < 0 || q.x >= n || q.y >= n || q.z >= n;
      if (outside || labels[linear(q.x, q.y, q.z)] == detail::kLabelWhite)
        config |= std::uint8_t(1u << f);
    }
    g.configuration = config;
    g.baseCase = kConfigurationTable[config].baseCase;
    g.rotation = kConfigurationTable[config].rotation;
  });

  // The sparse grid: grey cells active, black cells inactive tiles after pruning, white background.
  openvdb::initialize();
  c.mGrid = Grid::create(kWhite);
  // OpenVDB's scale maps refuse a voxel whose volume is near 0 in absolute terms (a cell under
  // about 1.4e-5 units): such a grid keeps the identity transform (see grid()).
  if (hasWorldTransform(c.mCellSizeWS)) {
    c.mGrid->setTransform(openvdb::math::Transform::createLinearTransform(c.mCellSizeWS));
    c.mGrid->transform().postTranslate(openvdb::Vec3d(c.mBoundsWS.min.x + 0.5 * c.mCellSizeWS,
                                                      c.mBoundsWS.min.y + 0.5 * c.mCellSizeWS,
                                                      c.mBoundsWS.min.z + 0.5 * c.mCellSizeWS));
  }
  c.mGrid->setName("cellrelief_cells");
  {
    Grid::Accessor acc = c.mGrid->getAccessor();
    for (std::size_t i = 0; i < c.mGreyCells.size(); ++i) {
      const Vec3i& p = c.mGreyCells[i].ijk;
      acc.setValueOn(openvdb::Coord(p.x, p.y, p.z), std::int32_t(i));
    }
    for (std::uint64_t id = 0; id < labels.size(); ++id)
      if (labels[id] == detail::kLabelBlack)
        acc.setValueOff(openvdb::Coord(int(id % nn), int((id / nn) % nn), int(id / (nn * nn))),
                        kBlack);
  }
  openvdb::tools::prune(c.mGrid->tree());

  ComplexStats& s = c.mStats;
  for (const std::uint8_t l : labels) {
    s.white += l == detail::kLabelWhite;
    s.black += l == detail::kLabelBlack;
  }
  s.grey = c.mGreyCells.size();
  for (const GreyCell& g : c.mGreyCells) {
    ++s.perCase[static_cast<int>(g.baseCase)];
    (g.border() ? s.borderGrey : s.interiorGrey)++;
  }
  s.cellTrianglePairs = c.mCellTriangles.size();
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return c;
}

}  // namespace cellrelief::cells
