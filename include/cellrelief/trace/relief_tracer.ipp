// SPDX-License-Identifier: MIT
/// @file relief_tracer.ipp
/// ReliefTracer's member bodies; relief_tracer.h has the class, its declarations and the why.
#pragma once

namespace cellrelief::trace {

template <Real T, SearchPolicy Search>
ReliefTracer<T, Search>::ReliefTracer(const relief::ReliefModel& model, const TraceOptions& options)
    : mModel(model), mOptions(options), mGrid(openvdb::Int32Grid::create(-1)) {
  auto acc = mGrid->getAccessor();
  for (std::size_t i = 0; i < model.cells.size(); ++i) {
    const Vec3i p = model.cells[i].ijk();
    acc.setValueOn(openvdb::Coord(p.x, p.y, p.z), std::int32_t(i));
  }
  const Aabbd surface = relief::surfaceBoundsWS(model);
  mBounds = Aabb<T>(Vec3<T>(surface.min), Vec3<T>(surface.max));
  mCellReach = relief::cellReaches(model);
  mOrigin = Vec3<T>(model.originWS);
  mCellSize = T(model.cellSizeWS);
  mDistanceScale = T(model.distanceCodec.scale());
  mZeroCode = T(model.distanceCodec.zeroCode);
  if (options.skipEmptySpace) mPyramid = EmptySpacePyramid(model);
  mOpenModel = model.openSurface();
  mNearFace = T(constants::kNearFaceSamples) / T(model.texels - 1);
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::fieldAt(const Vec3<T>& pointWS) const -> std::optional<T> {
  const Vec3<T> u = (pointWS - mOrigin) / mCellSize;
  if (!(glm::all(glm::greaterThanEqual(u, Vec3<T>(0))) && glm::all(glm::lessThanEqual(u, Vec3<T>(mModel.gridSize)))))
    return std::nullopt;
  const Vec3i c = glm::min(Vec3i(glm::floor(u)), Vec3i(mModel.gridSize - 1));
  const std::int32_t index = mGrid->getConstAccessor().getValue(openvdb::Coord(c.x, c.y, c.z));
  if (index < 0) return std::nullopt;
  const relief::CellRecord& record = mModel.cells[index];
  return mModel.visitDistanceCodes([&](const auto& codes) {
    return record.projection<T>().visit([&](const auto& p) {
      projection::FacePoint<T> fp;
      return std::optional<T>(field(codes, p, record, u - Vec3<T>(c), fp));
    });
  });
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::finishHit(std::int32_t index, const Ray<T>& ray, T t,
                                        const projection::FacePoint<T>& fp, std::uint32_t steps,
                                        bool shadeHit) const -> Hit {
  Hit hit = makeHit(index, ray, t, fp, steps);
  if (!shadeHit) return hit;
  const relief::CellRecord& record = mModel.cells[index];
  mModel.visitDistanceCodes([&](const auto& codes) {
    record.projection<T>().visit([&](const auto& p) { shadeFound(codes, p, record, ray, hit); });
  });
  return hit;
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::prepareRay(Ray<T>& ray) const -> std::optional<RayInterval<T>> {
  ray.setDirection(ray.direction);
  // Such rays meet nothing, and must not reach the walk's index arithmetic.
  const bool finite = std::isfinite(ray.origin.x) && std::isfinite(ray.origin.y) &&
                      std::isfinite(ray.origin.z) && std::isfinite(ray.direction.x) &&
                      std::isfinite(ray.direction.y) && std::isfinite(ray.direction.z);
  if (!finite || ray.direction == Vec3<T>(0) || !(ray.tmin <= ray.tmax)) return std::nullopt;
  const RayInterval<T> span = cellrelief::intersect(ray, mBounds);
  if (!span.hit) return std::nullopt;
  return span;
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::crossesAtFace(T fIn, bool inside, T exitField) const -> bool {
  // A crossing unless both cells read a real distance far from the surface there: then they
  // disagree because one of them misreads the side (a projection line that meets the surface
  // twice, past the occlusion the grid size allows), and the entered cell is trusted. An empty
  // line (no surface sampled, as in a sliver thinner than a sample) tells nothing against it.
  auto farFromSurface = [&](T f) { return std::abs(f) > mNearFace && std::abs(f) < kEmptyField; };
  return (fIn > 0) != inside && !(farFromSurface(fIn) && farFromSurface(exitField));
}

template <Real T, SearchPolicy Search>
template <class Codes>
auto ReliefTracer<T, Search>::traceWith(const Codes& codes, const Ray<T>& input,
                                        bool shadeHit) const -> Hit {
  Ray<T> ray = input;
  const std::optional<RayInterval<T>> prepared = prepareRay(ray);
  if (!prepared) return {};
  const RayInterval<T>& span = *prepared;
  // Unregistered: a registered accessor takes a lock in the tree on creation, once per ray.
  auto acc = mGrid->getConstUnsafeAccessor();
  GridDda<T> walk(ray, mOrigin, mCellSize, mModel.gridSize, span.t0, span.t1);
  // The side of the surface the ray is on, carried from cell to cell: outside when it enters
  // the grid from outside (the grid holds the whole mesh), unknown when it starts within it.
  // White and black cells hold no surface, so they keep the side.
  Side side{span.t0 > ray.tmin ? Side::Outside : Side::Unknown};
  std::uint32_t steps = 0;  // over every grey cell searched (a search that misses reports its steps too)
  do {
    const Vec3i& cell = walk.cell();
    const std::int32_t index = acc.getValue(openvdb::Coord(cell.x, cell.y, cell.z));
    if (index >= 0) {
      const relief::CellRecord& record = mModel.cells[index];
      const auto proj = record.projection<T>();
      const CellFrame frame = cellFrame(ray, record);
      Hit hit = proj.visit([&](const auto& p) {
        Hit found = searchCell(codes, p, record, index, ray, frame, walk.tEntry(), walk.tExit(), side);
        if (found.valid() && shadeHit) shadeFound(codes, p, record, ray, found);
        return found;
      });
      steps += hit.steps;
      if (hit.valid()) {
        hit.steps = steps;
        return hit;
      }
    } else {
      side.exitField = std::numeric_limits<T>::infinity();
    }
  } while (walk.next());
  return missAfter(steps);
}

template <Real T, SearchPolicy Search>
template <class Codes>
auto ReliefTracer<T, Search>::stored(const Codes& codes, int layer, const Vec2<T>& uv,
                                     bool emptyLinesCrossed) const -> std::optional<T> {
  const int texels = mModel.texels;
  // Written so that NaN lands on 0: an index from NaN would be undefined.
  const T x = (uv.x > T(0) ? std::min(uv.x, T(1)) : T(0)) * T(texels - 1);
  const T y = (uv.y > T(0) ? std::min(uv.y, T(1)) : T(0)) * T(texels - 1);
  const int a0 = std::min(texels - 2, int(x)), b0 = std::min(texels - 2, int(y));
  const T fx = x - T(a0), fy = y - T(b0);
  const relief::DistanceCodec& codec = mModel.distanceCodec;
  // Codes less the zero code (exact in T): distances in code steps, negative before the face.
  T c00 = T(codes(layer, a0, b0)) - mZeroCode, c10 = T(codes(layer, a0 + 1, b0)) - mZeroCode;
  T c01 = T(codes(layer, a0, b0 + 1)) - mZeroCode, c11 = T(codes(layer, a0 + 1, b0 + 1)) - mZeroCode;
  const T empty = T(codec.emptyCode()) - mZeroCode;
  const int emptyCount = int(c00 >= empty) + int(c10 >= empty) + int(c01 >= empty) + int(c11 >= empty);
  if (emptyCount > 0) {
    if (!emptyLinesCrossed || emptyCount == 4) return std::nullopt;
    mixedTexel(c00, c10, c01, c11, empty, emptyCount);
  }
  const T top = c00 + fx * (c10 - c00);
  const T bottom = c01 + fx * (c11 - c01);
  return (top + fy * (bottom - top)) * mDistanceScale;
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::field(const Codes& codes, const P& proj, const relief::CellRecord& r,
                                    const Vec3<T>& p, projection::FacePoint<T>& fp) const -> T {
  fp = proj.project(glm::clamp(p, Vec3<T>(0), Vec3<T>(1)));
  const bool interior = r.configuration == 0;
  const T emptyValue = interior && r.centreInside() ? kEmptyField : -kEmptyField;
  const int layer = r.layerOf(fp.face);
  if (layer < 0) return emptyValue;
  const std::optional<T> s = stored(codes, layer, fp.uv, interior);
  if (!s) return emptyValue;
  return interior && !r.centreInside() ? *s - fp.distance : fp.distance - *s;
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::searchCell(const Codes& codes, const P& proj,
                                         const relief::CellRecord& r, std::int32_t index,
                                         const Ray<T>& ray, const CellFrame& frame, T t0, T t1,
                                         Side& side) const -> Hit {
  auto local = [&](T t) { return frame.origin + t * frame.direction; };
  projection::FacePoint<T> fp;
  const T fIn = field(codes, proj, r, local(t0), fp);
  // An open model's cells read the side each on its own (ReliefModel::openSurface()).
  if (!mOpenModel && side.where != Side::Unknown &&
      crossesAtFace(fIn, side.where == Side::Inside, side.exitField))
    return makeHit(index, ray, t0, fp, 1);
  // The linear search starts where the field was just read and ends where the next cell's
  // side is decided: it hands both values over instead of reading them again.
  T fOut = std::numeric_limits<T>::quiet_NaN();
  Hit hit = searchInside(codes, proj, r, index, ray, frame, t0, t1, fIn, fp, fOut);
  if (!hit.valid()) {
    if (std::isnan(fOut)) fOut = field(codes, proj, r, local(t1), fp);
    side.where = mOpenModel ? Side::Unknown : fOut > 0 ? Side::Inside : Side::Outside;
    side.exitField = std::abs(fOut);
  }
  return hit;
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::searchInside(const Codes& codes, const P& proj,
                                           const relief::CellRecord& r, std::int32_t index,
                                           const Ray<T>& ray, const CellFrame& frame, T t0, T t1,
                                           T fStart, const projection::FacePoint<T>& fpStart,
                                           T& fEnd) const -> Hit {
  constexpr bool kSingleDirection = std::is_same_v<P, projection::ParallelProjection<T>> ||
                                    std::is_same_v<P, projection::PlanarProjection<T>>;
  // A segment that cannot meet a change of side needs no skipping walk either; one that can
  // is searched only within the cell's reach, where the side can change (searchCell reads the
  // field at t1 after a skipping walk's miss).
  RayInterval<T> reach{t0, t1, true};
  reach.hit = clipToReach(index, frame.origin, frame.direction, reach.t0, reach.t1);
  if (!reach.hit)
    return linearBinarySearch(codes, proj, r, index, ray, frame, t0, t1, fStart, fpStart, fEnd, reach);
  if constexpr (kSingleDirection) {
    if (mOptions.skipEmptySpace) return skipSearch(codes, proj, r, index, ray, frame, reach.t0, reach.t1);
  } else {
    // Interior cells read an empty line on the centre's side, not the face's: a node that
    // mixes empty and filled texel cells tells no side there, so they keep the sampled search.
    // The side at reach.t0 is fStart's: outside the reach the field keeps it.
    if (mOptions.skipEmptySpace && mOptions.skipCentralCells && r.configuration != 0)
      return centralSkipSearch(codes, proj, r, index, ray, frame, reach.t0, reach.t1, fStart);
  }
  return linearBinarySearch(codes, proj, r, index, ray, frame, t0, t1, fStart, fpStart, fEnd, reach);
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::linearBinarySearch(const Codes& codes, const P& proj,
                                                 const relief::CellRecord& r, std::int32_t index,
                                                 const Ray<T>& ray, const CellFrame& frame, T t0,
                                                 T t1, T fStart,
                                                 const projection::FacePoint<T>& fpStart,
                                                 T& fEnd, const RayInterval<T>& reach) const -> Hit {
  auto local = [&](T t) { return frame.origin + t * frame.direction; };
  projection::FacePoint<T> fp = fpStart;
  // The samples cover [from, to]; outside the cell's reach the field keeps the side read at t0.
  T from = t0, to = t1;
  int linear = constants::kLinearStepsOutsideReach;
  int facePrev = fp.face;
  if (reach.hit) {
    from = reach.t0;
    to = reach.t1;
    // The footprint on the maps, from four points of the span; a change of face counts as a
    // whole face crossed (conservative: the two pieces meet on the shared edge).
    auto at = [&](T t) { return proj.project(glm::clamp(local(t), Vec3<T>(0), Vec3<T>(1))); };
    T footprint = 0;
    projection::FacePoint<T> a = at(from);
    facePrev = a.face;
    for (int k = 1; k <= constants::kFootprintProbes; ++k) {
      const projection::FacePoint<T> b = at(from + (to - from) * T(k) / T(constants::kFootprintProbes));
      footprint += a.face == b.face ? glm::length(b.uv - a.uv) : T(1);
      a = b;
    }
    linear = Search::linearSteps(mOptions, double(footprint * T(mModel.texels - 1)));
  }
  T fPrev = fStart;
  T tPrev = from;
  std::uint32_t steps = 1;
  // In a cell with a hole's rim, a step between an empty line and one with surface is no
  // crossing: the empty line may look through the hole (CellRecord::kOpenSurface).
  const bool open = r.openSurface();
  for (int i = 1; i <= linear; ++i) {
    const T t = from + (to - from) * T(i) / T(linear);
    const T f = field(codes, proj, r, local(t), fp);
    ++steps;
    // Nor is a step across a planar cell's mid-plane: each half reads its own face, and its side
    // there says nothing of the other half's (as in skipSearch, which searches the halves apart).
    // Counted as a crossing, the flip between a half that sees a sheet near its face (inside up
    // to the mid-plane) and a half without surface made false hits on the mid-plane.
    const bool otherHalf = std::is_same_v<P, projection::PlanarProjection<T>> && fp.face != facePrev;
    facePrev = fp.face;
    if (!otherHalf && (fPrev > 0) != (f > 0) && !(open && (isEmptyField(fPrev) || isEmptyField(f))))
      return refineCrossing(codes, proj, r, index, ray, frame, tPrev, t, fPrev, f, steps);
    fPrev = f;
    tPrev = t;
  }
  // The next cell weighs the field where the ray leaves (crossesAtFace): read there, past the
  // reach, with the side the last sample has.
  if (to < t1) {
    fPrev = field(codes, proj, r, local(t1), fp);
    ++steps;
  }
  fEnd = fPrev;
  return missAfter(steps);
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::refineCrossing(const Codes& codes, const P& proj,
                                             const relief::CellRecord& r, std::int32_t index,
                                             const Ray<T>& ray, const CellFrame& frame, T lo, T hi,
                                             T fLo, T fHi, std::uint32_t steps) const -> Hit {
  auto local = [&](T t) { return frame.origin + t * frame.direction; };
  projection::FacePoint<T> fp;
  const bool positiveLo = fLo > 0;
  for (int k = 0; k < mOptions.binarySteps; ++k) {
    const T mid = T(0.5) * (lo + hi);
    const T fm = field(codes, proj, r, local(mid), fp);
    ++steps;
    if ((fm > 0) == positiveLo) lo = mid, fLo = fm;
    else hi = mid, fHi = fm;
  }
  const T t = secantCrossing(lo, hi, fLo, fHi);
  field(codes, proj, r, local(t), fp);
  return makeHit(index, ray, t, fp, steps);
}

template <Real T, SearchPolicy Search>
template <class Codes>
auto ReliefTracer<T, Search>::nodeCode(const Codes& codes, int layer, int level, int ix,
                                       int iy) const -> std::uint32_t {
  if (level > 0) return mPyramid.code(layer, level, ix, iy);
  const std::uint32_t c[4] = {codes(layer, ix, iy), codes(layer, ix + 1, iy), codes(layer, ix, iy + 1),
                              codes(layer, ix + 1, iy + 1)};
  const relief::DistanceCodec& codec = mModel.distanceCodec;
  return codec.isEmpty(c[0]) || codec.isEmpty(c[1]) || codec.isEmpty(c[2]) || codec.isEmpty(c[3])
             ? codec.emptyCode()
             : std::min({c[0], c[1], c[2], c[3]});
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::skipSearch(const Codes& codes, const P& proj,
                                         const relief::CellRecord& r, std::int32_t index,
                                         const Ray<T>& ray, const CellFrame& frame, T t0,
                                         T t1) const -> Hit {
  if constexpr (std::is_same_v<P, projection::ParallelProjection<T>>) {
    return skipSearchFace(codes, r, index, ray, frame, proj.face, t0, t1, T(1));
  } else {
    const int axis = proj.axis;
    const T o = frame.origin[axis], d = frame.direction[axis];
    // Split at the mid-plane; the lower half projects onto the - face, the upper onto the +.
    T tMid = d != 0 ? (T(0.5) - o) / d : std::numeric_limits<T>::infinity();
    const bool startsUpper = o + t0 * d >= T(0.5) && !(d < 0 && o + t0 * d == T(0.5));
    const int first = 2 * axis + (startsUpper ? 1 : 0);
    if (!(tMid > t0 && tMid < t1)) {
      // One half only: decided by the segment's middle, which rounding cannot put on the plane.
      const int face = 2 * axis + (o + T(0.5) * (t0 + t1) * d >= T(0.5) ? 1 : 0);
      return skipSearchFace(codes, r, index, ray, frame, face, t0, t1, T(0.5));
    }
    const Hit hit = skipSearchFace(codes, r, index, ray, frame, first, t0, tMid, T(0.5));
    if (hit.valid()) return hit;
    Hit second = skipSearchFace(codes, r, index, ray, frame, first ^ 1, tMid, t1, T(0.5));
    second.steps += hit.steps;
    return second;
  }
}

template <Real T, SearchPolicy Search>
template <class Codes>
auto ReliefTracer<T, Search>::skipSearchFace(const Codes& codes, const relief::CellRecord& r,
                                             std::int32_t index, const Ray<T>& ray,
                                             const CellFrame& frame, int face, T t0, T t1,
                                             T depthLimit) const -> Hit {
  const int layer = r.layerOf(face);
  if (layer < 0 || !(t1 > t0)) return {};
  const int axis = cells::faceAxis(face), ua = (axis + 1) % 3, va = (axis + 2) % 3;
  const T scale = T(mModel.texels - 1);
  // Along the segment, parameter s in [0, 1]: depth, and position in sample units.
  const Vec3<T> p0 = frame.origin + t0 * frame.direction;
  const Vec3<T> dp = (t1 - t0) * frame.direction;
  const bool upper = cells::faceSign(face) > 0;
  const T depth0 = upper ? T(1) - p0[axis] : p0[axis];
  const T dDepth = upper ? -dp[axis] : dp[axis];
  const T x0 = p0[ua] * scale, dx = dp[ua] * scale;
  const T y0 = p0[va] * scale, dy = dp[va] * scale;
  auto depthAt = [&](T s) { return glm::clamp(depth0 + s * dDepth, T(0), depthLimit); };
  const int top = mPyramid.levels() - 1;
  int level = top;
  T s = 0;
  std::uint32_t steps = 0;
  auto hitAt = [&](T sHit) {
    const T t = t0 + sHit * (t1 - t0);
    projection::FacePoint<T> fp;
    fp.face = face;
    const Vec3<T> p = glm::clamp(frame.origin + t * frame.direction, Vec3<T>(0), Vec3<T>(1));
    fp.uv = Vec2<T>(p[ua], p[va]);
    fp.distance = depthAt(sHit);
    return makeHit(index, ray, t, fp, steps);
  };
  // Which side of the surface the ray is on, as the sampled search reads it: an empty texel
  // cell (the rim of the surface's projection) reads as outside, so entering a texel cell
  // below its surface, or leaving one into the rim, is a crossing at the texel cell's edge.
  // In a cell with a hole's rim an empty texel cell tells no side (`known` false): the next
  // texel cell with surface decides it instead of making a crossing.
  const bool open = r.openSurface();
  bool inside = false, known = true;
  if (const std::optional<T> d = stored(codes, layer, Vec2<T>(p0[ua], p0[va]))) inside = depthAt(0) > *d;
  else known = !open;
  constexpr T kProgress = T(constants::kSkipProgress);  // a floor on each advance, against rounding stalls
  while (s < T(1)) {
    ++steps;
    const int size = 1 << level, nodes = mPyramid.size(level);
    // The node the ray is in, nudged along the ray so boundaries go to the node ahead.
    const T x = x0 + s * dx, y = y0 + s * dy;
    const int ix = std::clamp(int(std::floor((x + nudge(x, dx)) / T(size))), 0, nodes - 1);
    const int iy = std::clamp(int(std::floor((y + nudge(y, dy)) / T(size))), 0, nodes - 1);
    // An axis along which the ray is already past the layer's edge and moving away never
    // exits a node: it must not hold the walk at s (rounding puts a ray there near cell edges).
    const T edge = T(mPyramid.size(0));
    T sExit = T(1);
    if (dx != 0 && !(dx > 0 ? x >= edge : x <= 0))
      sExit = std::min(sExit, (T(dx > 0 ? (ix + 1) * size : ix * size) - x0) / dx);
    if (dy != 0 && !(dy > 0 ? y >= edge : y <= 0))
      sExit = std::min(sExit, (T(dy > 0 ? (iy + 1) * size : iy * size) - y0) / dy);
    sExit = std::max(sExit, s + kProgress);
    const std::uint32_t code = nodeCode(codes, layer, level, ix, iy);
    const T deepest = std::max(depthAt(s), depthAt(std::min(sExit, T(1))));
    if (mPyramid.isEmptyCode(code) || deepest < (T(code) - mZeroCode) * mDistanceScale) {
      // No surface under the node, or all of it beyond the ray here: outside, unless the node
      // is empty in a cell with a hole's rim, where that tells no side.
      if (open && mPyramid.isEmptyCode(code)) {
        known = false;
      } else {
        if (inside && known) return hitAt(s);
        known = true;
      }
      inside = false;
      s = sExit;
      level = std::min(level + 1, top);
      continue;
    }
    if (level > 0) {
      --level;
      continue;
    }
    // A texel cell: f(s) = depth(s) - bilinear(x(s), y(s)) is a quadratic in s.
    const T s1 = std::min(sExit, T(1));
    const T d00 = (T(codes(layer, ix, iy)) - mZeroCode) * mDistanceScale;
    const T d10 = (T(codes(layer, ix + 1, iy)) - mZeroCode) * mDistanceScale;
    const T d01 = (T(codes(layer, ix, iy + 1)) - mZeroCode) * mDistanceScale;
    const T d11 = (T(codes(layer, ix + 1, iy + 1)) - mZeroCode) * mDistanceScale;
    const T ax = x0 - T(ix), ay = y0 - T(iy);  // local coordinates at s = 0, slopes dx, dy
    const T e = d00 - d10 - d01 + d11;
    // bilinear = d00 + (d10 - d00) fx + (d01 - d00) fy + e fx fy with fx = ax + dx s, fy = ay + dy s
    const T c0 = d00 + (d10 - d00) * ax + (d01 - d00) * ay + e * ax * ay;
    const T c1 = (d10 - d00) * dx + (d01 - d00) * dy + e * (ax * dy + ay * dx);
    const T c2 = e * dx * dy;
    // Depth is clamped to the half-cell in planar cells; the texel walk stays inside it.
    const T qa = -c2, qb = dDepth - c1, qc = depth0 - c0;
    auto f = [&](T at) { return (qa * at + qb) * at + qc; };
    if (!known) inside = f(s) > 0, known = true;
    if ((f(s) > 0) != inside) return hitAt(s);
    if (const std::optional<T> root = firstRoot(qa, qb, qc, s, s1)) return hitAt(*root);
    inside = f(s1) > 0;
    s = sExit;
    level = std::min(level + 1, top);
  }
  return missAfter(steps);
}

template <Real T, SearchPolicy Search>
template <class P>
auto ReliefTracer<T, Search>::centralRay(const P& proj, const CellFrame& frame) -> CentralRay {
  CentralRay c;
  c.origin = frame.origin;
  c.direction = frame.direction;
  if constexpr (std::is_same_v<P, projection::AxialProjection<T>>) {
    c.centre = proj.point;
    c.axis = proj.axis;
  } else {
    c.centre = proj.centre;
  }
  c.w0 = frame.origin - c.centre;
  c.w1 = frame.direction;
  if (c.axis >= 0) c.w0[c.axis] = c.w1[c.axis] = T(0);
  return c;
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::exitFaceAt(const CentralRay& c, T t) -> int {
  int best = -1;
  T bestRatio = -std::numeric_limits<T>::infinity(), bestSlope = bestRatio;
  for (int f = 0; f < cells::kFaceCount; ++f) {
    if (!c.reachable(f)) continue;
    const T ratio = c.ratio0(f) + t * c.ratio1(f), slope = c.ratio1(f);
    if (ratio > bestRatio || (ratio == bestRatio && slope > bestSlope)) best = f, bestRatio = ratio, bestSlope = slope;
  }
  return best;
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::faceChange(const CentralRay& c, int face, T t, T tEnd)
    -> std::pair<T, int> {
  T when = tEnd;
  int next = -1;
  for (int g = 0; g < cells::kFaceCount; ++g) {
    if (g == face || !c.reachable(g)) continue;
    const T gap0 = c.ratio0(g) - c.ratio0(face), gap1 = c.ratio1(g) - c.ratio1(face);
    if (!(gap1 > 0)) continue;  // never overtakes as t grows
    const T at = -gap0 / gap1;
    if (at > t && at < when) when = at, next = g;
  }
  return {when, next};
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::centralSkipSearch(const Codes& codes, const P& proj,
                                                const relief::CellRecord& r, std::int32_t index,
                                                const Ray<T>& ray, const CellFrame& frame, T t0,
                                                T t1, T fStart) const -> Hit {
  const CentralRay central = centralRay(proj, frame);
  WalkSide side{fStart > 0, !(r.openSurface() && isEmptyField(fStart))};
  std::uint32_t steps = 1;  // the field at t0
  T t = t0;
  int face = exitFaceAt(central, t), previous = -1;
  while (face >= 0 && t < t1) {
    const auto [tEnd, next] = faceChange(central, face, t, t1);
    const Hit hit =
        centralSkipFace(codes, proj, r, index, ray, frame, central, face, previous, t, tEnd, side, steps);
    if (hit.valid()) return hit;
    t = tEnd;
    previous = face;
    face = next;
  }
  return missAfter(steps);
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::centralSkipFace(const Codes& codes, const P& proj,
                                              const relief::CellRecord& r, std::int32_t index,
                                              const Ray<T>& ray, const CellFrame& frame,
                                              const CentralRay& central, int face, int previous,
                                              T ta, T tb, WalkSide& side,
                                              std::uint32_t& steps) const -> Hit {
  auto local = [&](T t) { return frame.origin + t * frame.direction; };
  auto hitAt = [&](T t) {
    projection::FacePoint<T> fp;
    field(codes, proj, r, local(t), fp);
    return makeHit(index, ray, t, fp, steps);
  };
  const bool open = r.openSurface();
  // A stretch the walk proves to be on one side: entering it from the other is a crossing
  // at its start. An empty node in a cell with a hole's rim tells no side.
  auto enter = [&](bool positive, bool tellsSide, T t) {
    const bool crossed = tellsSide && side.known && side.positive != positive;
    side = {positive, tellsSide};
    return crossed ? hitAt(t) : Hit{};
  };
  const int layer = r.layerOf(face);
  if (layer < 0 || !(tb > ta)) {
    ++steps;
    return layer < 0 ? enter(false, !open, ta) : Hit{};  // no map: every line here is empty
  }
  const T scale = T(mModel.texels - 1);
  const LinearRatio u = central.coordinate(face, projection::faceUAxis(face));
  const LinearRatio v = central.coordinate(face, projection::faceVAxis(face));
  const T du = u.direction(), dv = v.direction();
  const T r0 = central.ratio0(face), r1 = central.ratio1(face);
  auto depthAt = [&](T t) { return glm::clamp(T(1) - (r0 + r1 * t), T(0), T(1)); };
  // Squared: the longest of a node's four lines takes one square root, not four (the root
  // is monotonic and correctly rounded, so the result is the same).
  auto squaredLineLength = [&](int x, int y) {
    const Vec3<T> q = projection::facePoint<T>(face, Vec2<T>(T(x), T(y)) / scale);
    const Vec3<T> e = q - proj.lineEnd(face, q);
    return e.x * e.x + e.y * e.y + e.z * e.z;
  };
  // The floor on each advance: a fraction of the stretch, and never below a few ulps of t.
  auto advance = [&](T from) {
    return from + std::max(T(constants::kSkipProgress) * (tb - ta),
                           T(constants::kNudgeUlps) * std::numeric_limits<T>::epsilon() * std::max(T(1), std::abs(from)));
  };
  const int top = mPyramid.levels() - 1;
  const T edge = T(mPyramid.size(0));
  int level = top;
  // The position in texel units. Where the walk crossed a node boundary it is that boundary,
  // exactly: recomputed from the rounded t it can land a few ulps short, a rounding that
  // differs between the CPU and a GPU (there the next node would depend on the driver).
  T t = ta, x = u.at(t) * scale, y = v.at(t) * scale;
  // Coming from the previous face, the walk enters on the edge the two faces share: there the
  // coordinate along the previous face's axis is that face's plane, exactly.
  if (previous >= 0) {
    const T plane = cells::faceSign(previous) > 0 ? scale : T(0);
    if (cells::faceAxis(previous) == projection::faceUAxis(face)) x = plane;
    if (cells::faceAxis(previous) == projection::faceVAxis(face)) y = plane;
  }
  T xBoundary = 0, yBoundary = 0;
  auto moveTo = [&](T next, bool acrossU, bool acrossV) {
    t = next;
    x = acrossU ? xBoundary : u.at(t) * scale;
    y = acrossV ? yBoundary : v.at(t) * scale;
  };
  while (t < tb) {
    ++steps;
    const int size = 1 << level, nodes = mPyramid.size(level);
    if (!std::isfinite(x) || !std::isfinite(y)) {  // at the centre itself (0 / 0): step past it
      moveTo(std::min(tb, advance(t)), false, false);
      continue;
    }
    const int ix = std::clamp(int(std::floor((x + nudge(x, du)) / T(size))), 0, nodes - 1);
    const int iy = std::clamp(int(std::floor((y + nudge(y, dv)) / T(size))), 0, nodes - 1);
    // An axis along which the ray is past the layer's edge and moving away never exits. The
    // ratio takes the boundary's value once more on its other branch (past its pole), where
    // the denominator has the other sign: that one is no exit.
    T tExit = tb;
    bool acrossU = false, acrossV = false;
    auto exitAt = [&](const LinearRatio& c, T boundary, bool& across) {
      const T at = c.solve(boundary / scale);
      if ((c.d0 + c.d1 * at > 0) != (c.d0 + c.d1 * t > 0) || at > tExit) return;
      if (at < tExit) acrossU = acrossV = false;
      tExit = at;
      across = true;
    };
    xBoundary = T(du > 0 ? (ix + 1) * size : ix * size);
    yBoundary = T(dv > 0 ? (iy + 1) * size : iy * size);
    if (du != 0 && !(du > 0 ? x >= edge : x <= 0)) exitAt(u, xBoundary, acrossU);
    if (dv != 0 && !(dv > 0 ? y >= edge : y <= 0)) exitAt(v, yBoundary, acrossV);
    if (const T least = advance(t); !(tExit >= least)) tExit = least, acrossU = acrossV = false;
    if (tExit >= tb) tExit = tb, acrossU = acrossV = false;
    const std::uint32_t code = nodeCode(codes, layer, level, ix, iy);
    bool skip = mPyramid.isEmptyCode(code);
    if (!skip) {
      const int xa = ix * size, xb = std::min((ix + 1) * size, mModel.texels - 1);
      const int ya = iy * size, yb = std::min((iy + 1) * size, mModel.texels - 1);
      const T longest = std::sqrt(std::max({squaredLineLength(xa, ya), squaredLineLength(xb, ya),
                                            squaredLineLength(xa, yb), squaredLineLength(xb, yb)}));
      skip = std::max(depthAt(t), depthAt(tExit)) * longest < (T(code) - mZeroCode) * mDistanceScale;
    }
    if (skip) {
      // No surface under the node, or all of it beyond the ray here: outside (f < 0).
      if (const Hit hit = enter(false, !(open && mPyramid.isEmptyCode(code)), t); hit.valid()) return hit;
      moveTo(tExit, acrossU, acrossV);
      level = std::min(level + 1, top);
      continue;
    }
    if (level > 0) {
      --level;
      continue;
    }
    // A texel cell the bound cannot skip: sample it.
    T tPrev = t;
    // The walk knows the side at t, not the field: a value not read, of that side's sign.
    T fPrev = side.positive ? kUnreadField : -kUnreadField;
    projection::FacePoint<T> fp;
    for (int k = 1; k <= constants::kCentralTexelSamples; ++k) {
      const T ts = t + (tExit - t) * T(k) / T(constants::kCentralTexelSamples);
      const T f = field(codes, proj, r, local(ts), fp);
      ++steps;
      if (open && isEmptyField(f)) {
        side.known = false;
      } else {
        if (side.known && (f > 0) != side.positive)
          return refineCrossing(codes, proj, r, index, ray, frame, tPrev, ts, fPrev, f, steps);
        side = {f > 0, true};
      }
      tPrev = ts;
      fPrev = f;
    }
    moveTo(tExit, acrossU, acrossV);
    level = std::min(level + 1, top);
  }
  return Hit{};
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::firstRoot(T a, T b, T c, T lo, T hi) -> std::optional<T> {
  auto value = [&](T s) { return (a * s + b) * s + c; };
  const T fLo = value(lo), fHi = value(hi);
  // The end values decide when rounding defeats the closed form: a sign change always has a
  // root, found by bisection then.
  const bool signChange = (fLo > 0) != (fHi > 0);
  auto bisect = [&] {
    T l = lo, h = hi;
    for (int i = 0; i < constants::kRootBisections; ++i) {
      const T m = T(0.5) * (l + h);
      ((value(m) > 0) == (fLo > 0) ? l : h) = m;
    }
    return h;
  };
  const T magnitude = std::abs(a) + std::abs(b) + std::abs(c);
  if (std::abs(a) <= T(constants::kQuadraticEpsilon) * std::max(magnitude, T(1e-30))) {
    if (b != 0) {
      const T s = -c / b;
      if (s >= lo && s <= hi) return s;
    } else if (c == 0) {
      return lo;
    }
    return signChange ? std::optional<T>(bisect()) : std::nullopt;
  }
  const T disc = b * b - 4 * a * c;
  if (disc < 0) return signChange ? std::optional<T>(bisect()) : std::nullopt;
  const T q = T(-0.5) * (b + std::copysign(std::sqrt(disc), b));
  T r0 = q / a, r1 = q != 0 ? c / q : r0;
  if (r0 > r1) std::swap(r0, r1);
  if (r0 >= lo && r0 <= hi) return r0;
  if (r1 >= lo && r1 <= hi) return r1;
  // Rounding can push a root just outside while the end values still differ in sign.
  return signChange ? std::optional<T>(bisect()) : std::nullopt;
}

template <Real T, SearchPolicy Search>
auto ReliefTracer<T, Search>::makeHit(std::int32_t index, const Ray<T>& ray, T t,
                                      const projection::FacePoint<T>& fp, std::uint32_t steps) const
    -> Hit {
  Hit hit;
  hit.t = t;
  hit.position = ray.at(t);
  hit.cell = index;
  hit.face = fp.face;
  hit.uv = Vec2f(glm::clamp(fp.uv, Vec2<T>(0), Vec2<T>(1)));
  hit.texel = hit.uv * float(mModel.texels - 1);
  hit.steps = steps;
  return hit;
}

template <Real T, SearchPolicy Search>
template <class Codes, class P>
auto ReliefTracer<T, Search>::shade(const Codes& codes, const P& proj, const relief::CellRecord& r,
                                    Hit& hit) const -> void {
  const int layer = r.layerOf(hit.face);
  if (layer < 0) return;
  const int texels = mModel.texels;
  int a = std::clamp(int(std::lround(hit.texel.x)), 0, texels - 1);
  int b = std::clamp(int(std::lround(hit.texel.y)), 0, texels - 1);
  // A hit at the rim of the surface's projection (a crossing found at a cell face or a texel
  // edge) can round to a sample without surface (empty, or before the face): shade from the
  // nearest filled one within two samples.
  if (!mModel.distanceCodec.hasSurface(codes(layer, a, b))) {
    int best = std::numeric_limits<int>::max(), bestA = a, bestB = b;
    const int radius = constants::kShadeSearchRadius;
    for (int y = std::max(0, b - radius); y <= std::min(texels - 1, b + radius); ++y)
      for (int x = std::max(0, a - radius); x <= std::min(texels - 1, a + radius); ++x) {
        const int d2 = (x - a) * (x - a) + (y - b) * (y - b);
        if (d2 < best && mModel.distanceCodec.hasSurface(codes(layer, x, y)))
          best = d2, bestA = x, bestB = y;
      }
    a = bestA;
    b = bestB;
  }
  if (mModel.normalFormat != relief::NormalFormat::None) {
    hit.normal = mModel.normal(layer, a, b);
  } else {
    const relief::DistanceCodec& codec = mModel.distanceCodec;
    auto point = [&](int x, int y) -> std::optional<Vec3d> {
      if (x < 0 || y < 0 || x >= texels || y >= texels) return std::nullopt;
      const std::uint32_t code = codes(layer, x, y);
      if (!codec.hasSurface(code)) return std::nullopt;
      const double d = codec.decode(code);
      return Vec3d(proj.unproject(hit.face, Vec2<T>(T(x) / T(texels - 1), T(y) / T(texels - 1)), T(d)));
    };
    // Central differences where both neighbours exist, one-sided ones at the edge of the
    // surface; none (the caller's reverse ray direction) when the sample stands alone. The
    // centre is unprojected only for a one-sided difference (most hits have both neighbours).
    std::optional<Vec3d> centre;
    bool centreRead = false;
    auto centrePoint = [&]() -> const std::optional<Vec3d>& {
      if (!centreRead) centre = point(a, b), centreRead = true;
      return centre;
    };
    auto derivative = [&](int dx, int dy) -> std::optional<Vec3d> {
      const auto plus = point(a + dx, b + dy), minus = point(a - dx, b - dy);
      if (plus && minus) return *plus - *minus;
      if (plus && centrePoint()) return *plus - *centrePoint();
      if (minus && centrePoint()) return *centrePoint() - *minus;
      return std::nullopt;
    };
    const auto du = derivative(1, 0), dv = derivative(0, 1);
    Vec3d n(0);
    if (du && dv) n = glm::cross(*du, *dv);
    if (cells::faceSign(hit.face) < 0) n = -n;
    // The samples see the surface from the face; in an interior cell whose centre is outside,
    // the outside is behind the surface, not in front of it.
    if (r.configuration == 0 && !r.centreInside()) n = -n;
    hit.normal = glm::length(n) > 0 ? Vec3f(glm::normalize(n)) : Vec3f(0);
  }
  if (mModel.colorFormat == relief::ColorFormat::Rgba8)
    for (int c = 0; c < 4; ++c) hit.color[c] = mModel.colors.at(a, b, layer, c);
}

}  // namespace cellrelief::trace
