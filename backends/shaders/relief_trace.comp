// SPDX-License-Identifier: MIT
// The GPU ray caster of relief models: the algorithm of include/cellrelief/trace/relief_tracer.h
// and the shading of backends/cpu/cpu_backend.h, one invocation per pixel. Shared by the OpenGL
// and Vulkan backends; the backend prepends a preamble (backends/gpu/shader_preamble.h) with
//  - CR_VULKAN or not (binding syntax),
//  - the traversal constants, written from trace/trace_options.h (never typed here),
//  - the variant, as constant bools: CR_PARALLEL, CR_PLANAR, CR_PERSPECTIVE, CR_AXIAL (projection
//    types present), CR_OCT_NORMALS, CR_RGBA_NORMALS, CR_COLORS (maps present), CR_SKIP, CR_SKIP_CENTRAL,
//    CR_SHADOWS, CR_REFLECTIONS (features used), CR_GATHER (one textureGather per 2 x 2 samples),
//    CR_OUT_COLOR, CR_OUT_DEPTH, CR_OUT_NORMAL, CR_OUT_MASK, CR_OUT_CELL, CR_OUT_STEPS (channels),
//    CR_POLYCUBE (polycube-mapped meshes present; gpu/polycube_layout.h), CR_GEOTEX (geometry
//    textures present; gpu/geotex_layout.h), CR_PARALLAX (relief surfaces present;
//    gpu/parallax_layout.h);
//    OpenGL compiles them as plain constants, Vulkan as specialization constants of one SPIR-V
//    module; either way the compiler removes the branches a variant switches off;
//  - the workgroup size and the number of lights.
// Comments name the C++ function each part follows; the reasons are written there. The structure
// differs from the C++ where SIMD lanes need it: a GPU (and llvmpipe, 8 pixels a vector) runs
// every block any lane of a group takes, so rarely taken work is moved out of the hot loops.

#ifdef CR_VULKAN
#define CR_BIND(n) set = 0, binding = n
#else
#define CR_BIND(n) binding = n
#endif

#ifdef CR_FRAGMENT
// The stencil of the rasterized cells must cull fragments before the shader runs: a shader that
// writes storage buffers otherwise runs for every pixel and is tested afterwards.
layout(early_fragment_tests) in;
#else
layout(local_size_x = CR_GROUP_WIDTH, local_size_y = CR_GROUP_HEIGHT, local_size_z = 1) in;
#endif

#define CR_INF uintBitsToFloat(0x7f800000u)
#define CR_NO_FIELD 1e30  // "not read": beyond any field value (at most CR_EMPTY_FIELD); not NaN, which fast-math drivers may not test

struct Light {
  vec4 direction;  // towards the light, normalized; w unused
  vec4 color;      // rgb * intensity
};

layout(std140, CR_BIND(0)) uniform Params {
  vec4 eye;
  vec4 forward;
  vec4 right;
  vec4 up;            // already scaled: sx * right + sy * up spans the image plane
  vec4 ambient;
  vec4 background;
  Light lights[CR_MAX_LIGHTS];
  ivec4 size;         // width, height, model count, light count
  ivec4 steps;        // minLinearSteps, maxLinearSteps, binarySteps, reflection bounces
  vec4 tuning;        // stepsPerTexel, reflectivity, tanHalf * aspect, tanHalf
  ivec4 flags;        // shadows, skip, frame offsets: color, depth
  ivec4 offsets;      // frame offsets: normal, mask, cell, steps
} P;

struct ModelInfo {
  float origin[3];
  float cellSize;
  float distanceScale;
  float texelsMinus1;
  float distanceMax;
  float surfaceMin[3];  // relief::surfaceBoundsWS: the box rays are clipped to
  float surfaceMax[3];
  int gridSize;
  int texels;
  int cellOffset;
  int hashOffset;
  int hashMask;
  int layerBase;
  int tilesPerRow;
  int tilesPerLayer;
  int tileRowShift;
  int tileLayerShift;
  int emptyCode;
  int normalFormat;
  int colorFormat;
  int pyramidOffset;
  int pyramidLevels;
  int pyramidLayerStride;
  int layerCount;
  int openSurface;  // ReliefModel::openSurface()
  int zeroCode;     // DistanceCodec::zeroCode: codes below it are distances before the face
  int levelSize[CR_MAX_PYRAMID_LEVELS];
  int levelOffset[CR_MAX_PYRAMID_LEVELS];
};

struct CellRecord {
  uint packedIjk;
  uint info;  // configuration | projectionType << 8 | faceOrAxis << 16 | presentFaces << 24
  uint firstLayer;
  float point[3];
  uint reach[2];  // relief::CellReach (gpu::GpuCell)
};

layout(std430, CR_BIND(1)) readonly buffer Models { ModelInfo models[]; };
layout(std430, CR_BIND(2)) readonly buffer Cells { CellRecord cells[]; };
layout(std430, CR_BIND(3)) readonly buffer Hash { uvec2 slots[]; };
layout(std430, CR_BIND(4)) readonly buffer Pyramid { uint pyramidWords[]; };
layout(std430, CR_BIND(5)) writeonly buffer FrameOut { uint frameWords[]; };

// Every map is bound (a 1 x 1 placeholder when the scene lacks it): a variant switch that is
// off removes the reads, not the declaration, so one SPIR-V module serves every variant.
layout(CR_BIND(6)) uniform usampler2DArray distanceAtlas;
layout(CR_BIND(7)) uniform usampler2DArray octNormalAtlas;
layout(CR_BIND(8)) uniform usampler2DArray rgbaNormalAtlas;
layout(CR_BIND(9)) uniform usampler2DArray colorAtlas;

// ---- the current model and cell (GLSL has no references: the search reads these) -------------

int gModel;
vec3 gOrigin;
float gCellSize;
vec3 gSurfaceMin;  // the surface's box (relief/surface_bounds.h)
vec3 gSurfaceMax;
int gGrid;
int gTexels;
float gDistanceScale;
uint gEmptyCode;
float gZeroCode;
// Copies of the model's fields: in llvmpipe every read of a storage buffer by a non-constant
// index is a per-lane gather, so the inner loops read these instead.
int gHashOffset;
uint gHashMask;
int gLayerBase;
int gTileRowMask;
int gTileLayerMask;
int gTileRowShift;
int gTileLayerShift;
int gNormalFormat;
int gColorFormat;
float gDistanceMax;
int gPyramidOffset;
int gPyramidLevels;
int gPyramidLayerStride;
vec2 gInverseAtlasSize;  // set once in main()

int gCell;         // index into cells[]
uint gConfiguration;
int gProjection;   // CR_PROJ_*
int gFaceOrAxis;
uint gPresent;
int gFirstLayer;
vec3 gPoint;
uint gDomain;      // domain faces
bool gInterior;
bool gCentreInside;
bool gOpenSurface;  // CellRecord::kOpenSurface: the cell holds a hole's rim
uvec2 gReach;       // relief::CellReach: where the cell's field can change side
bool gOpenModel;    // ReliefModel::openSurface(): no side carried across cell faces

void selectModel(int m) {
  gModel = m;
  gOrigin = vec3(models[m].origin[0], models[m].origin[1], models[m].origin[2]);
  gCellSize = models[m].cellSize;
  gSurfaceMin = vec3(models[m].surfaceMin[0], models[m].surfaceMin[1], models[m].surfaceMin[2]);
  gSurfaceMax = vec3(models[m].surfaceMax[0], models[m].surfaceMax[1], models[m].surfaceMax[2]);
  gGrid = models[m].gridSize;
  gTexels = models[m].texels;
  gDistanceScale = models[m].distanceScale;
  gEmptyCode = uint(models[m].emptyCode);
  gZeroCode = float(models[m].zeroCode);
  gOpenModel = models[m].openSurface != 0;
  gHashOffset = models[m].hashOffset;
  gHashMask = uint(models[m].hashMask);
  gLayerBase = models[m].layerBase;
  gTileRowMask = models[m].tilesPerRow - 1;
  gTileLayerMask = models[m].tilesPerLayer - 1;
  gTileRowShift = models[m].tileRowShift;
  gTileLayerShift = models[m].tileLayerShift;
  gNormalFormat = models[m].normalFormat;
  gColorFormat = models[m].colorFormat;
  gDistanceMax = models[m].distanceMax;
  gPyramidOffset = models[m].pyramidOffset;
  gPyramidLevels = models[m].pyramidLevels;
  gPyramidLayerStride = models[m].pyramidLayerStride;
}

void selectCell(int index) {
  gCell = index;
  const uint info = cells[index].info;
  gConfiguration = info & 0xffu;
  gProjection = int((info >> 8) & 0xffu);
  gFaceOrAxis = int((info >> 16) & 0xffu);
  gPresent = (info >> 24) & 0xffu;
  gFirstLayer = int(cells[index].firstLayer);
  gPoint = vec3(cells[index].point[0], cells[index].point[1], cells[index].point[2]);
  gInterior = gConfiguration == 0u;
  gDomain = gInterior ? 63u : (gConfiguration & 63u);
  gCentreInside = (cells[index].packedIjk & CR_CENTRE_INSIDE_BIT) != 0u;
  gOpenSurface = (cells[index].packedIjk & CR_OPEN_SURFACE_BIT) != 0u;
  gReach = uvec2(cells[index].reach[0], cells[index].reach[1]);
}

// ---- the cell lookup (gpu_layout.h: cellHash, findCell) ---------------------------------------

uint cellHash(uint k) {
  k ^= k >> 16;
  k *= 0x7feb352du;
  k ^= k >> 15;
  k *= 0x846ca68bu;
  k ^= k >> 16;
  return k;
}

int findCell(ivec3 c) {
  const uint key = (uint(c.x) | (uint(c.y) << 10) | (uint(c.z) << 20)) + 1u;
  uint h = cellHash(key) & gHashMask;
  for (;;) {
    const uvec2 slot = slots[gHashOffset + int(h)];
    if (slot.x == key) return int(slot.y);
    if (slot.x == 0u) return -1;
    h = (h + 1u) & gHashMask;
  }
}

// ---- faces and projections (projection/projections.h) -----------------------------------------

int faceAxis(int face) { return face >> 1; }
// Components by a variable axis, and the next axis, as selects: llvmpipe turns a variable
// index into a vector (or a modulo) into per-lane scalar code.
int nextAxis(int a) { return a == 2 ? 0 : a + 1; }
float axisOf(vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }
vec3 withAxis(vec3 v, int a, float x) { return vec3(a == 0 ? x : v.x, a == 1 ? x : v.y, a == 2 ? x : v.z); }
bool facePositive(int face) { return (face & 1) != 0; }
int makeFace(int axis, bool positive) { return 2 * axis + (positive ? 1 : 0); }

vec2 faceUV(int face, vec3 p) {
  const int u = nextAxis(faceAxis(face));
  return vec2(axisOf(p, u), axisOf(p, nextAxis(u)));
}

vec3 facePoint(int face, vec2 uv) {
  const int a = faceAxis(face), u = nextAxis(a);
  vec3 p = withAxis(vec3(0.0), a, facePositive(face) ? 1.0 : 0.0);
  p = withAxis(p, u, uv.x);
  return withAxis(p, nextAxis(u), uv.y);
}

vec3 faceNormal(int face) {
  return withAxis(vec3(0.0), faceAxis(face), facePositive(face) ? 1.0 : -1.0);
}

int firstFace(uint mask) { return findLSB(mask); }

struct FacePoint {
  int face;
  vec2 uv;
  float distance;
};

// detail::exitPoint
FacePoint exitPoint(vec3 origin, vec3 w, vec3 p, int skipAxis) {
  float best = CR_INF;
  int face = -1;
  for (int a = 0; a < 3; ++a) {
    if (a == skipAxis || w[a] == 0.0) continue;
    const float bound = w[a] > 0.0 ? 1.0 : 0.0;
    const float t = (bound - origin[a]) / w[a];
    if (t < best) {
      best = t;
      face = makeFace(a, w[a] > 0.0);
    }
  }
  vec3 hit = withAxis(origin + best * w, faceAxis(face), facePositive(face) ? 1.0 : 0.0);
  hit = clamp(hit, vec3(0.0), vec3(1.0));
  return FacePoint(face, faceUV(face, hit), length(hit - p));
}

vec3 axialFoot(vec3 p) {
  return withAxis(gPoint, gFaceOrAxis, axisOf(p, gFaceOrAxis));
}

// The projection of the current cell, written for SIMD lanes that may hold cells of different
// types: llvmpipe runs every branch any lane takes, so the two single-direction projections
// (parallel, planar) share one path of selects and the two central ones (perspective, axial)
// share one exitPoint; a variant compiles only the paths its scene has.
FacePoint projectSingleDirection(vec3 p) {
  const bool parallel = CR_PARALLEL && (!CR_PLANAR || gProjection == CR_PROJ_PARALLEL);
  const int face = parallel ? gFaceOrAxis : makeFace(gFaceOrAxis, axisOf(p, gFaceOrAxis) >= 0.5);
  // p lies in the unit cell: the distance to the face is 1 - x or x (parallel: |target - x|).
  const float x = axisOf(p, faceAxis(face));
  return FacePoint(face, faceUV(face, p), facePositive(face) ? 1.0 - x : x);
}

FacePoint projectCentral(vec3 p) {
  const bool perspective = CR_PERSPECTIVE && (!CR_AXIAL || gProjection == CR_PROJ_PERSPECTIVE);
  const vec3 origin = perspective ? gPoint : axialFoot(p);
  const vec3 w = p - origin;
  if (w == vec3(0.0)) {  // the centre itself, or a point on the axis
    const int f = firstFace(gDomain);
    const vec3 target = perspective ? facePoint(f, vec2(0.5)) : withAxis(p, faceAxis(f), facePositive(f) ? 1.0 : 0.0);
    return FacePoint(f, faceUV(f, target), length(target - p));
  }
  return exitPoint(origin, w, p, perspective ? -1 : gFaceOrAxis);
}

FacePoint project(vec3 p) {
  const bool single = CR_PARALLEL || CR_PLANAR, central = CR_PERSPECTIVE || CR_AXIAL;
  if (single && central) {
    const FacePoint s = projectSingleDirection(p);
    const FacePoint c = projectCentral(p);
    return gProjection == CR_PROJ_PARALLEL || gProjection == CR_PROJ_PLANAR ? s : c;
  }
  if (single) return projectSingleDirection(p);
  if (central) return projectCentral(p);
  return FacePoint(-1, vec2(0.0), 0.0);
}

vec3 unproject(int face, vec2 uv, float distance) {
  const vec3 onFace = facePoint(face, uv);
  if (gProjection == CR_PROJ_PERSPECTIVE) return onFace + distance * normalize(gPoint - onFace);
  if (gProjection == CR_PROJ_AXIAL) return onFace + distance * normalize(axialFoot(onFace) - onFace);
  return onFace - distance * faceNormal(face);
}

// ---- the maps (gpu_layout.h: the atlas) --------------------------------------------------------

int layerOf(int face) {
  if ((gPresent & (1u << face)) == 0u) return -1;
  return gFirstLayer + bitCount(gPresent & ((1u << face) - 1u));
}

// The texel of sample (0, 0) of a model layer, and its array layer.
ivec3 tileOrigin(int layer) {
  // Tiles per row and per array layer are powers of two: shifts and masks, no division.
  const int r = layer & gTileLayerMask;
  return ivec3((r & gTileRowMask) * gTexels, (r >> gTileRowShift) * gTexels, gLayerBase + (layer >> gTileLayerShift));
}

uint sampleCode(ivec3 tile, int a, int b) {
  return texelFetch(distanceAtlas, ivec3(tile.x + a, tile.y + b, tile.z), 0).r;
}

// ReliefTracer::mixedTexel: in an interior cell, an empty sample of a texel with filled ones reads
// as a distance at or before the face: alone, the plane through the other three (at most 0); with
// other empty ones, half the negated mean of the filled samples.
void mixedTexel(inout float c00, inout float c10, inout float c01, inout float c11, float empty, int emptyCount) {
  if (emptyCount == 1) {
    if (c00 >= empty) c00 = min(c10 + c01 - c11, 0.0);
    if (c10 >= empty) c10 = min(c00 + c11 - c01, 0.0);
    if (c01 >= empty) c01 = min(c00 + c11 - c10, 0.0);
    if (c11 >= empty) c11 = min(c10 + c01 - c00, 0.0);
    return;
  }
  const float beforeFace = -0.5 * ((c00 < empty ? c00 : 0.0) + (c10 < empty ? c10 : 0.0) + (c01 < empty ? c01 : 0.0) +
                                   (c11 < empty ? c11 : 0.0)) / float(4 - emptyCount);
  c00 = c00 < empty ? c00 : beforeFace;
  c10 = c10 < empty ? c10 : beforeFace;
  c01 = c01 < empty ? c01 : beforeFace;
  c11 = c11 < empty ? c11 : beforeFace;
}

// ReliefTracer::stored: bilinear in the codes, false when a corner is empty (in an interior cell,
// when all four are: mixedTexel reads the others).
bool stored(int layer, vec2 uv, bool emptyLinesCrossed, out float value) {
  const float scale = float(gTexels - 1);
  const float x = (uv.x > 0.0 ? min(uv.x, 1.0) : 0.0) * scale;
  const float y = (uv.y > 0.0 ? min(uv.y, 1.0) : 0.0) * scale;
  const int a0 = min(gTexels - 2, int(x)), b0 = min(gTexels - 2, int(y));
  const float fx = x - float(a0), fy = y - float(b0);
  const ivec3 tile = tileOrigin(layer);
  uint c00, c10, c01, c11;
  if (CR_GATHER) {
    // One gather of the 2 x 2 block: (x, y, z, w) = (a0, b0+1), (a0+1, b0+1), (a0+1, b0), (a0, b0).
    const uvec4 g = textureGather(distanceAtlas, vec3((vec2(tile.xy) + vec2(a0 + 1, b0 + 1)) * gInverseAtlasSize,
                                                    float(tile.z)), 0);
    c00 = g.w, c10 = g.z, c01 = g.x, c11 = g.y;
  } else {
    c00 = sampleCode(tile, a0, b0);
    c10 = sampleCode(tile, a0 + 1, b0);
    c01 = sampleCode(tile, a0, b0 + 1);
    c11 = sampleCode(tile, a0 + 1, b0 + 1);
  }
  // Codes less the zero code (exact in float): distances in code steps, negative before the face.
  float d00 = float(c00) - gZeroCode, d10 = float(c10) - gZeroCode, d01 = float(c01) - gZeroCode,
        d11 = float(c11) - gZeroCode;
  const int emptyCount = int(c00 == gEmptyCode) + int(c10 == gEmptyCode) + int(c01 == gEmptyCode) + int(c11 == gEmptyCode);
  if (emptyCount > 0) {
    if (!emptyLinesCrossed || emptyCount == 4) return false;
    mixedTexel(d00, d10, d01, d11, float(gEmptyCode) - gZeroCode, emptyCount);
  }
  const float top = d00 + fx * (d10 - d00);
  const float bottom = d01 + fx * (d11 - d01);
  value = (top + fy * (bottom - top)) * gDistanceScale;
  return true;
}

// ReliefTracer::field: positive inside the object, negative outside.
float field(vec3 p, out FacePoint fp) {
  fp = project(clamp(p, vec3(0.0), vec3(1.0)));
  const float emptyValue = gInterior && gCentreInside ? CR_EMPTY_FIELD : -CR_EMPTY_FIELD;
  const int layer = layerOf(fp.face);
  if (layer < 0) return emptyValue;
  float s;
  if (!stored(layer, fp.uv, gInterior, s)) return emptyValue;
  return gInterior && !gCentreInside ? s - fp.distance : fp.distance - s;
}

// ---- hits ----------------------------------------------------------------------------------------

struct Hit {
  float t;
  int cell;   // -1: none
  int face;
  vec2 uv;
  uint steps;
};

Hit noHit() { return Hit(CR_INF, -1, -1, vec2(0.0), 0u); }
Hit missAfter(uint steps) { return Hit(CR_INF, -1, -1, vec2(0.0), steps); }

Hit makeHit(float t, FacePoint fp, uint steps) {
  return Hit(t, gCell, fp.face, clamp(fp.uv, vec2(0.0), vec2(1.0)), steps);
}

// The ray in the current cell's unit coordinates.
vec3 gLocalOrigin;
vec3 gLocalDirection;
vec3 localPoint(float t) { return gLocalOrigin + t * gLocalDirection; }

// ---- linear + binary search (ReliefTracer::linearBinarySearch) --------------------------------

// ReliefTracer::secantCrossing: where the field crosses zero in the last bracket if it is linear
// there; the far end where either end reads no distance (an empty line, a value not read).
float secantCrossing(float lo, float hi, float fLo, float fHi) {
  if (!(abs(fLo) < CR_EMPTY_FIELD && abs(fHi) < CR_EMPTY_FIELD)) return hi;
  return lo + (hi - lo) * (fLo / (fLo - fHi));
}

// relief::CellReach::clip: [t0, t1] narrowed to where the segment can meet a change of side in
// the cell (the slab test of its 8-bit box, as the CPU writes it); false where it cannot.
bool clipToReach(inout float t0, inout float t1) {
  const vec3 lo = vec3(float(gReach.x & 255u), float((gReach.x >> 8) & 255u), float((gReach.x >> 16) & 255u)) / 255.0;
  const vec3 hi = vec3(float(gReach.x >> 24), float(gReach.y & 255u), float((gReach.y >> 8) & 255u)) / 255.0;
  for (int a = 0; a < 3; ++a) {
    if (lo[a] > hi[a]) return false;  // the empty box
    if (gLocalDirection[a] == 0.0) {
      if (gLocalOrigin[a] < lo[a] || gLocalOrigin[a] > hi[a]) return false;
      continue;
    }
    const float inverse = 1.0 / gLocalDirection[a];
    float tNear = (lo[a] - gLocalOrigin[a]) * inverse, tFar = (hi[a] - gLocalOrigin[a]) * inverse;
    if (tNear > tFar) {
      const float swapped = tNear;
      tNear = tFar;
      tFar = swapped;
    }
    t0 = max(t0, tNear);
    t1 = min(t1, tFar);
    if (t0 > t1) return false;
  }
  return true;
}

// fStart, fpStart: the field and projection at t0; fEnd: the field at t1 when nothing is hit.
// reached: the segment meets the cell's reach, [from, to] (clipToReach), which the linear samples
// cover; where it does not, the fewest steps over [t0, t1] (CR_LINEAR_STEPS_OUTSIDE_REACH).
Hit linearBinarySearch(float t0, float t1, float fStart, FacePoint fpStart, inout float fEnd, bool reached,
                       float from, float to) {
  FacePoint fp = fpStart;
  float fPrev = fStart;
  int linear = CR_LINEAR_STEPS_OUTSIDE_REACH;
  int facePrev = fp.face;
  if (reached) {
    // Outside the cell's reach the field keeps the side read at t0.
    float footprint = 0.0;
    FacePoint a = project(clamp(localPoint(from), vec3(0.0), vec3(1.0)));
    facePrev = a.face;
    for (int k = 1; k <= CR_FOOTPRINT_PROBES; ++k) {
      const FacePoint b = project(clamp(localPoint(from + (to - from) * float(k) / float(CR_FOOTPRINT_PROBES)),
                                        vec3(0.0), vec3(1.0)));
      footprint += a.face == b.face ? length(b.uv - a.uv) : 1.0;
      a = b;
    }
    // BalancedSearch::linearSteps
    const float wanted = float(P.steps.x) + P.tuning.x * (footprint * float(gTexels - 1));
    linear = clamp(int(ceil(wanted)), 2, max(2, P.steps.y));
  }
  float tPrev = from, tCrossing = from, fCrossing = fPrev;
  uint steps = 1u;
  bool crossed = false;
  for (int i = 1; i <= linear; ++i) {
    const float t = from + (to - from) * float(i) / float(linear);
    const float f = field(localPoint(t), fp);
    ++steps;
    // With a hole's rim in the cell, a step between an empty line and one with surface is no crossing;
    // nor is a step across a planar cell's mid-plane (each half reads its own face, as in skipSearch).
    const bool otherHalf = gProjection == CR_PROJ_PLANAR && fp.face != facePrev;
    facePrev = fp.face;
    if (!otherHalf && (fPrev > 0.0) != (f > 0.0) &&
        !(gOpenSurface && (abs(fPrev) >= CR_EMPTY_FIELD || abs(f) >= CR_EMPTY_FIELD))) {
      crossed = true;
      tCrossing = t;
      fCrossing = f;
      break;
    }
    fPrev = f;
    tPrev = t;
  }
  if (!crossed) {
    // The next cell weighs the field where the ray leaves (crossesAtFace): read there, past the reach.
    if (to < t1) {
      fPrev = field(localPoint(t1), fp);
      ++steps;
    }
    fEnd = fPrev;
    return missAfter(steps);
  }
  // The binary search after the loop, not inside it: llvmpipe would run it on every sample.
  float lo = tPrev, hi = tCrossing, fLo = fPrev, fHi = fCrossing;
  for (int k = 0; k < P.steps.z; ++k) {
    const float mid = 0.5 * (lo + hi);
    const float fm = field(localPoint(mid), fp);
    ++steps;
    if ((fm > 0.0) == (fLo > 0.0)) {
      lo = mid;
      fLo = fm;
    } else {
      hi = mid;
      fHi = fm;
    }
  }
  const float t = secantCrossing(lo, hi, fLo, fHi);
  field(localPoint(t), fp);
  return makeHit(t, fp, steps);
}

// ---- empty-space skipping (ReliefTracer::skipSearchFace, firstRoot) ----------------------------

// Nodes per side at a level: level 0 has T - 1, each level above halves it rounding up
// (EmptySpacePyramid), which is ceil((T - 1) / 2^level).
int pyramidSize(int level) { return ((gTexels - 2) >> level) + 1; }

uint pyramidCode(int layer, int level, int a, int b) {
  const int index = gPyramidOffset + layer * gPyramidLayerStride +
                    models[gModel].levelOffset[level] + b * pyramidSize(level) + a;
  const uint word = pyramidWords[index >> 1];
  return (index & 1) != 0 ? word >> 16 : word & 0xffffu;
}

float quadratic(float a, float b, float c, float s) { return (a * s + b) * s + c; }

bool firstRoot(float a, float b, float c, float lo, float hi, out float root) {
  const float fLo = quadratic(a, b, c, lo), fHi = quadratic(a, b, c, hi);
  const bool signChange = (fLo > 0.0) != (fHi > 0.0);
  bool bisect = false;
  const float magnitude = abs(a) + abs(b) + abs(c);
  if (abs(a) <= CR_QUADRATIC_EPSILON * max(magnitude, 1e-30)) {
    if (b != 0.0) {
      const float s = -c / b;
      if (s >= lo && s <= hi) {
        root = s;
        return true;
      }
    } else if (c == 0.0) {
      root = lo;
      return true;
    }
    bisect = true;
  } else {
    const float disc = b * b - 4.0 * a * c;
    if (disc < 0.0) {
      bisect = true;
    } else {
      const float sq = sqrt(disc);
      const float q = -0.5 * (b + (b < 0.0 ? -sq : sq));
      float r0 = q / a, r1 = q != 0.0 ? c / q : r0;
      if (r0 > r1) {
        const float swap = r0;
        r0 = r1;
        r1 = swap;
      }
      if (r0 >= lo && r0 <= hi) {
        root = r0;
        return true;
      }
      if (r1 >= lo && r1 <= hi) {
        root = r1;
        return true;
      }
      bisect = true;
    }
  }
  if (!bisect || !signChange) return false;
  float l = lo, h = hi;
  for (int i = 0; i < CR_ROOT_BISECTIONS; ++i) {
    const float m = 0.5 * (l + h);
    if ((quadratic(a, b, c, m) > 0.0) == (fLo > 0.0))
      l = m;
    else
      h = m;
  }
  root = h;
  return true;
}

float nudge(float v, float dv) {
  return dv == 0.0 ? 0.0 : (dv > 0.0 ? 1.0 : -1.0) * CR_NUDGE_ULPS * CR_FLOAT_EPSILON * max(1.0, abs(v));
}

Hit skipHitAt(float sHit, float t0, float t1, int face, float depth0, float dDepth, float depthLimit,
              uint steps) {
  const float t = t0 + sHit * (t1 - t0);
  const vec3 p = clamp(localPoint(t), vec3(0.0), vec3(1.0));
  FacePoint fp = FacePoint(face, faceUV(face, p),
                           clamp(depth0 + sHit * dDepth, 0.0, depthLimit));
  return makeHit(t, fp, steps);
}

Hit skipSearchFace(int face, float t0, float t1, float depthLimit) {
  const int layer = layerOf(face);
  if (layer < 0 || !(t1 > t0)) return noHit();
  const int axis = faceAxis(face), ua = nextAxis(axis), va = nextAxis(ua);
  const float scale = float(gTexels - 1);
  const vec3 p0 = localPoint(t0);
  const vec3 dp = (t1 - t0) * gLocalDirection;
  const bool upper = facePositive(face);
  const float depth0 = upper ? 1.0 - axisOf(p0, axis) : axisOf(p0, axis);
  const float dDepth = upper ? -axisOf(dp, axis) : axisOf(dp, axis);
  const float x0 = axisOf(p0, ua) * scale, dx = axisOf(dp, ua) * scale;
  const float y0 = axisOf(p0, va) * scale, dy = axisOf(dp, va) * scale;
  const int top = gPyramidLevels - 1;
  const ivec3 tile = tileOrigin(layer);
  int level = top;
  float s = 0.0;
  uint steps = 0u;
  bool inside = false, known = true;  // known false: an empty texel cell with a hole's rim in the cell
  float d;
  if (stored(layer, vec2(axisOf(p0, ua), axisOf(p0, va)), false, d)) inside = clamp(depth0, 0.0, depthLimit) > d;
  else known = !gOpenSurface;
  const float edge = float(gTexels - 1);
  while (s < 1.0) {
    // The walk skips and descends in a tight loop of its own until a texel cell needs the exact
    // test, which runs after it (llvmpipe would run that test's code on every node otherwise).
    bool test = false;
    int ix = 0, iy = 0;
    float sExit = 1.0;
    uint c00 = 0u, c10 = 0u, c01 = 0u, c11 = 0u;
    while (s < 1.0) {
      ++steps;
      const int size = 1 << level, nodes = pyramidSize(level);
      const float x = x0 + s * dx, y = y0 + s * dy;
      ix = clamp(int(floor((x + nudge(x, dx)) / float(size))), 0, nodes - 1);
      iy = clamp(int(floor((y + nudge(y, dy)) / float(size))), 0, nodes - 1);
      sExit = 1.0;
      if (dx != 0.0 && !(dx > 0.0 ? x >= edge : x <= 0.0))
        sExit = min(sExit, (float(dx > 0.0 ? (ix + 1) * size : ix * size) - x0) / dx);
      if (dy != 0.0 && !(dy > 0.0 ? y >= edge : y <= 0.0))
        sExit = min(sExit, (float(dy > 0.0 ? (iy + 1) * size : iy * size) - y0) / dy);
      sExit = max(sExit, s + CR_SKIP_PROGRESS);
      uint code;
      if (level > 0) {
        code = pyramidCode(layer, level, ix, iy);
      } else {
        c00 = sampleCode(tile, ix, iy);
        c10 = sampleCode(tile, ix + 1, iy);
        c01 = sampleCode(tile, ix, iy + 1);
        c11 = sampleCode(tile, ix + 1, iy + 1);
        code = c00 == gEmptyCode || c10 == gEmptyCode || c01 == gEmptyCode || c11 == gEmptyCode
                   ? gEmptyCode
                   : min(min(c00, c10), min(c01, c11));
      }
      const float deepest = max(clamp(depth0 + s * dDepth, 0.0, depthLimit),
                                clamp(depth0 + min(sExit, 1.0) * dDepth, 0.0, depthLimit));
      if (code >= gEmptyCode || deepest < (float(code) - gZeroCode) * gDistanceScale) {
        if (gOpenSurface && code >= gEmptyCode) {
          known = false;
        } else {
          if (inside && known) return skipHitAt(s, t0, t1, face, depth0, dDepth, depthLimit, steps);
          known = true;
        }
        inside = false;
        s = sExit;
        level = min(level + 1, top);
        continue;
      }
      if (level > 0) {
        --level;
        continue;
      }
      test = true;
      break;
    }
    if (!test) break;
    // A texel cell: depth(s) - bilinear(x(s), y(s)) is a quadratic in s.
    const float s1 = min(sExit, 1.0);
    const float d00 = (float(c00) - gZeroCode) * gDistanceScale, d10 = (float(c10) - gZeroCode) * gDistanceScale;
    const float d01 = (float(c01) - gZeroCode) * gDistanceScale, d11 = (float(c11) - gZeroCode) * gDistanceScale;
    const float ax = x0 - float(ix), ay = y0 - float(iy);
    const float e = d00 - d10 - d01 + d11;
    const float q0 = d00 + (d10 - d00) * ax + (d01 - d00) * ay + e * ax * ay;
    const float q1 = (d10 - d00) * dx + (d01 - d00) * dy + e * (ax * dy + ay * dx);
    const float q2 = e * dx * dy;
    const float qa = -q2, qb = dDepth - q1, qc = depth0 - q0;
    if (!known) {
      inside = quadratic(qa, qb, qc, s) > 0.0;
      known = true;
    }
    if ((quadratic(qa, qb, qc, s) > 0.0) != inside)
      return skipHitAt(s, t0, t1, face, depth0, dDepth, depthLimit, steps);
    float root;
    if (firstRoot(qa, qb, qc, s, s1, root))
      return skipHitAt(root, t0, t1, face, depth0, dDepth, depthLimit, steps);
    inside = quadratic(qa, qb, qc, s1) > 0.0;
    s = sExit;
    level = min(level + 1, top);
  }
  return missAfter(steps);
}

// ReliefTracer::skipSearch: a planar cell is two parallel half-cells.
Hit skipSearch(float t0, float t1) {
  if (CR_PARALLEL && gProjection == CR_PROJ_PARALLEL) return skipSearchFace(gFaceOrAxis, t0, t1, 1.0);
  const int axis = gFaceOrAxis;
  const float o = axisOf(gLocalOrigin, axis), d = axisOf(gLocalDirection, axis);
  const float tMid = d != 0.0 ? (0.5 - o) / d : CR_INF;
  const bool startsUpper = o + t0 * d >= 0.5 && !(d < 0.0 && o + t0 * d == 0.5);
  const int first = 2 * axis + (startsUpper ? 1 : 0);
  if (!(tMid > t0 && tMid < t1)) {
    const int face = 2 * axis + (o + 0.5 * (t0 + t1) * d >= 0.5 ? 1 : 0);
    return skipSearchFace(face, t0, t1, 0.5);
  }
  const Hit hit = skipSearchFace(first, t0, tMid, 0.5);
  if (hit.cell >= 0) return hit;
  Hit second = skipSearchFace(first ^ 1, tMid, t1, 0.5);
  second.steps += hit.steps;
  return second;
}

// ---- empty-space skipping in central cells (ReliefTracer::centralSkipSearch) -----------------

// ReliefTracer::refineCrossing (fLo: CR_NO_FIELD with the side's sign where the walk knows the
// side at lo, not the field).
Hit refineCrossing(float lo, float hi, float fLo, float fHi, uint steps) {
  FacePoint fp;
  const bool positiveLo = fLo > 0.0;
  for (int k = 0; k < P.steps.z; ++k) {
    const float mid = 0.5 * (lo + hi);
    const float fm = field(localPoint(mid), fp);
    ++steps;
    if ((fm > 0.0) == positiveLo) {
      lo = mid;
      fLo = fm;
    } else {
      hi = mid;
      fHi = fm;
    }
  }
  const float t = secantCrossing(lo, hi, fLo, fHi);
  field(localPoint(t), fp);
  return makeHit(t, fp, steps);
}

// LinearRatio (n0 + n1 t) / (d0 + d1 t) as vec4(n0, n1, d0, d1).
// `precise` here and below: the walk's node boundaries must round as the CPU's do, which fuses
// no multiply-add (a driver may fuse them unless told not to).
float ratioAt(vec4 c, float t) {
  precise float n = c.x + c.y * t, d = c.z + c.w * t;
  return n / d;
}
float ratioSolve(vec4 c, float value) {
  precise float n = value * c.z - c.x, d = c.y - value * c.w;
  return n / d;
}
float ratioDirection(vec4 c) {
  precise float s = c.y * c.z - c.x * c.w;
  return s;
}

// CentralRay: w(t) = w0 + t w1 from the centre (axial: the axis point) to the ray's point.
vec3 gCentralCentre;
vec3 gCentralW0;
vec3 gCentralW1;
int gCentralAxis;

float centralReach(int face) { return (facePositive(face) ? 1.0 : 0.0) - axisOf(gCentralCentre, faceAxis(face)); }
bool centralReachable(int face) { return faceAxis(face) != gCentralAxis && centralReach(face) != 0.0; }
float centralRatio0(int face) { return axisOf(gCentralW0, faceAxis(face)) / centralReach(face); }
float centralRatio1(int face) { return axisOf(gCentralW1, faceAxis(face)) / centralReach(face); }
vec4 centralCoordinate(int face, int along) {
  if (along == gCentralAxis) return vec4(axisOf(gLocalOrigin, along), axisOf(gLocalDirection, along), 1.0, 0.0);
  const int a = faceAxis(face);
  const float k = centralReach(face), c = axisOf(gCentralCentre, along);
  precise float n0 = c * axisOf(gCentralW0, a) + k * axisOf(gCentralW0, along);
  precise float n1 = c * axisOf(gCentralW1, a) + k * axisOf(gCentralW1, along);
  return vec4(n0, n1, axisOf(gCentralW0, a), axisOf(gCentralW1, a));
}

// ReliefTracer::exitFaceAt
int exitFaceAt(float t) {
  int best = -1;
  float bestRatio = -CR_INF, bestSlope = -CR_INF;
  for (int f = 0; f < 6; ++f) {
    if (!centralReachable(f)) continue;
    precise float ratio = centralRatio0(f) + t * centralRatio1(f);
    const float slope = centralRatio1(f);
    if (ratio > bestRatio || (ratio == bestRatio && slope > bestSlope)) {
      best = f;
      bestRatio = ratio;
      bestSlope = slope;
    }
  }
  return best;
}

// ReliefTracer::faceChange: returns when, sets next.
float faceChange(int face, float t, float tEnd, out int next) {
  float when = tEnd;
  next = -1;
  for (int g = 0; g < 6; ++g) {
    if (g == face || !centralReachable(g)) continue;
    const float gap0 = centralRatio0(g) - centralRatio0(face), gap1 = centralRatio1(g) - centralRatio1(face);
    if (!(gap1 > 0.0)) continue;
    const float at = -gap0 / gap1;
    if (at > t && at < when) {
      when = at;
      next = g;
    }
  }
  return when;
}

bool gWalkPositive;  // ReliefTracer::WalkSide
bool gWalkKnown;

Hit centralHitAt(float t, uint steps) {
  FacePoint fp;
  field(localPoint(t), fp);
  return makeHit(t, fp, steps);
}

// ReliefTracer::centralSkipFace's `enter`: the walk proves a stretch outside; whether entering
// it is a crossing (from a known inside), and the side it leaves.
bool enterOutside(bool tellsSide) {
  const bool crossed = tellsSide && gWalkKnown && gWalkPositive;
  gWalkPositive = false;
  gWalkKnown = tellsSide;
  return crossed;
}

// ReliefTracer::centralSkipFace
Hit centralSkipFace(int face, int previous, float ta, float tb, inout uint steps) {
  const int layer = layerOf(face);
  if (layer < 0 || !(tb > ta)) {
    ++steps;
    if (layer >= 0) return noHit();
    return enterOutside(!gOpenSurface) ? centralHitAt(ta, steps) : noHit();
  }
  const float scale = float(gTexels - 1);
  const vec4 u = centralCoordinate(face, nextAxis(faceAxis(face)));
  const vec4 v = centralCoordinate(face, nextAxis(nextAxis(faceAxis(face))));
  const float du = ratioDirection(u), dv = ratioDirection(v);
  const float r0 = centralRatio0(face), r1 = centralRatio1(face);
  const bool perspective = CR_PERSPECTIVE && (!CR_AXIAL || gProjection == CR_PROJ_PERSPECTIVE);
  const float progress = CR_SKIP_PROGRESS * (tb - ta);
  const int top = gPyramidLevels - 1;
  const ivec3 tile = tileOrigin(layer);
  const float edge = float(pyramidSize(0));
  int level = top;
  // The position in texel units: exactly the boundary where the walk crossed one (see the C++).
  float t = ta;
  precise float x = ratioAt(u, t) * scale, y = ratioAt(v, t) * scale;
  if (previous >= 0) {  // on the edge shared with the previous face
    const float plane = facePositive(previous) ? scale : 0.0;
    if (faceAxis(previous) == nextAxis(faceAxis(face))) x = plane;
    if (faceAxis(previous) == nextAxis(nextAxis(faceAxis(face)))) y = plane;
  }
  float xBoundary = 0.0, yBoundary = 0.0;
  bool acrossU = false, acrossV = false;
  while (t < tb) {
    ++steps;
    precise float floorStep = max(progress, CR_NUDGE_ULPS * CR_FLOAT_EPSILON * max(1.0, abs(t)));
    const int size = 1 << level, nodes = pyramidSize(level);
    if (isinf(x) || isinf(y) || isnan(x) || isnan(y)) {  // at the centre itself (0 / 0)
      t = min(tb, t + floorStep);
      x = ratioAt(u, t) * scale;
      y = ratioAt(v, t) * scale;
      continue;
    }
    const int ix = clamp(int(floor((x + nudge(x, du)) / float(size))), 0, nodes - 1);
    const int iy = clamp(int(floor((y + nudge(y, dv)) / float(size))), 0, nodes - 1);
    float tExit = tb;
    acrossU = false;
    acrossV = false;
    xBoundary = float(du > 0.0 ? (ix + 1) * size : ix * size);
    yBoundary = float(dv > 0.0 ? (iy + 1) * size : iy * size);
    if (du != 0.0 && !(du > 0.0 ? x >= edge : x <= 0.0)) {
      const float at = ratioSolve(u, xBoundary / scale);
      precise float branchAt = u.z + u.w * at, branchHere = u.z + u.w * t;
      if ((branchAt > 0.0) == (branchHere > 0.0) && at <= tExit) {
        tExit = at;
        acrossU = true;
      }
    }
    if (dv != 0.0 && !(dv > 0.0 ? y >= edge : y <= 0.0)) {
      const float at = ratioSolve(v, yBoundary / scale);
      precise float branchAt = v.z + v.w * at, branchHere = v.z + v.w * t;
      if ((branchAt > 0.0) == (branchHere > 0.0) && at <= tExit) {
        if (at < tExit) acrossU = false;
        tExit = at;
        acrossV = true;
      }
    }
    precise float least = t + floorStep;
    if (!(tExit >= least)) {
      tExit = least;
      acrossU = false;
      acrossV = false;
    }
    if (tExit >= tb) {
      tExit = tb;
      acrossU = false;
      acrossV = false;
    }
    uint code;
    if (level > 0) {
      code = pyramidCode(layer, level, ix, iy);
    } else {
      const uint c00 = sampleCode(tile, ix, iy), c10 = sampleCode(tile, ix + 1, iy);
      const uint c01 = sampleCode(tile, ix, iy + 1), c11 = sampleCode(tile, ix + 1, iy + 1);
      code = c00 == gEmptyCode || c10 == gEmptyCode || c01 == gEmptyCode || c11 == gEmptyCode
                 ? gEmptyCode
                 : min(min(c00, c10), min(c01, c11));
    }
    bool skip = code >= gEmptyCode;
    if (!skip) {
      const int xa = ix * size, xb = min((ix + 1) * size, gTexels - 1);
      const int ya = iy * size, yb = min((iy + 1) * size, gTexels - 1);
      precise float longestSquared = 0.0;  // one square root per node (see the C++)
      for (int k = 0; k < 4; ++k) {
        const vec3 q = facePoint(face, vec2(float((k & 1) != 0 ? xb : xa), float((k & 2) != 0 ? yb : ya)) / scale);
        const vec3 e = q - (perspective ? gPoint : axialFoot(q));
        precise float squared = e.x * e.x + e.y * e.y + e.z * e.z;
        longestSquared = max(longestSquared, squared);
      }
      precise float depthIn = clamp(1.0 - (r0 + r1 * t), 0.0, 1.0), depthOut = clamp(1.0 - (r0 + r1 * tExit), 0.0, 1.0);
      precise float longest = sqrt(longestSquared);
      precise float deepest = max(depthIn, depthOut) * longest, nearest = (float(code) - gZeroCode) * gDistanceScale;
      skip = deepest < nearest;
    }
    if (skip) {
      if (enterOutside(!(gOpenSurface && code >= gEmptyCode))) return centralHitAt(t, steps);
      t = tExit;
      x = acrossU ? xBoundary : ratioAt(u, t) * scale;
      y = acrossV ? yBoundary : ratioAt(v, t) * scale;
      level = min(level + 1, top);
      continue;
    }
    if (level > 0) {
      --level;
      continue;
    }
    float tPrev = t;
    float fPrev = gWalkPositive ? CR_NO_FIELD : -CR_NO_FIELD;  // the side at t, not the field
    FacePoint fp;
    for (int k = 1; k <= CR_CENTRAL_TEXEL_SAMPLES; ++k) {
      precise float ts = t + (tExit - t) * float(k) / float(CR_CENTRAL_TEXEL_SAMPLES);
      const float f = field(localPoint(ts), fp);
      ++steps;
      if (gOpenSurface && abs(f) >= CR_EMPTY_FIELD) {
        gWalkKnown = false;
      } else {
        if (gWalkKnown && (f > 0.0) != gWalkPositive) return refineCrossing(tPrev, ts, fPrev, f, steps);
        gWalkPositive = f > 0.0;
        gWalkKnown = true;
      }
      tPrev = ts;
      fPrev = f;
    }
    t = tExit;
    x = acrossU ? xBoundary : ratioAt(u, t) * scale;
    y = acrossV ? yBoundary : ratioAt(v, t) * scale;
    level = min(level + 1, top);
  }
  return noHit();
}

Hit centralSkipSearch(float t0, float t1, float fStart) {
  const bool perspective = CR_PERSPECTIVE && (!CR_AXIAL || gProjection == CR_PROJ_PERSPECTIVE);
  gCentralCentre = gPoint;
  gCentralAxis = perspective ? -1 : gFaceOrAxis;
  gCentralW0 = gLocalOrigin - gCentralCentre;
  gCentralW1 = gLocalDirection;
  if (!perspective) {
    gCentralW0 = withAxis(gCentralW0, gCentralAxis, 0.0);
    gCentralW1 = withAxis(gCentralW1, gCentralAxis, 0.0);
  }
  gWalkPositive = fStart > 0.0;
  gWalkKnown = !(gOpenSurface && abs(fStart) >= CR_EMPTY_FIELD);
  uint steps = 1u;
  float t = t0;
  int face = exitFaceAt(t), previous = -1;
  while (face >= 0 && t < t1) {
    int next;
    const float tEnd = faceChange(face, t, t1, next);
    const Hit hit = centralSkipFace(face, previous, t, tEnd, steps);
    if (hit.cell >= 0) return hit;
    t = tEnd;
    previous = face;
    face = next;
  }
  return missAfter(steps);
}

Hit searchInside(float t0, float t1, float fStart, FacePoint fpStart, inout float fEnd) {
  // A segment that cannot meet a change of side needs no skipping walk either.
  float from = t0, to = t1;
  if (!clipToReach(from, to)) return linearBinarySearch(t0, t1, fStart, fpStart, fEnd, false, t0, t1);
  if (CR_SKIP && (gProjection == CR_PROJ_PARALLEL || gProjection == CR_PROJ_PLANAR) && (P.flags.y & 1) != 0 &&
      gPyramidOffset >= 0)
    return skipSearch(from, to);
  // Not in interior cells (see ReliefTracer::searchInside).
  if (CR_SKIP_CENTRAL && (gProjection == CR_PROJ_PERSPECTIVE || gProjection == CR_PROJ_AXIAL) && !gInterior &&
      (P.flags.y & 2) != 0 && gPyramidOffset >= 0)
    return centralSkipSearch(from, to, fStart);
  return linearBinarySearch(t0, t1, fStart, fpStart, fEnd, true, from, to);
}

// ---- the side carried across cell faces (ReliefTracer::searchCell) -----------------------------

const int kSideUnknown = 0, kSideOutside = 1, kSideInside = 2;
int gSide;
float gExitField;

Hit searchCell(float t0, float t1) {
  FacePoint fp;
  const float fIn = field(localPoint(t0), fp);
  const float nearFace = CR_NEAR_FACE_SAMPLES / float(gTexels - 1);
  const bool farIn = abs(fIn) > nearFace && abs(fIn) < CR_EMPTY_FIELD;
  const bool farExit = abs(gExitField) > nearFace && abs(gExitField) < CR_EMPTY_FIELD;
  if (!gOpenModel && gSide != kSideUnknown && (fIn > 0.0) != (gSide == kSideInside) && !(farIn && farExit))
    return makeHit(t0, fp, 1u);
  // The linear search hands over the fields at both ends instead of reading them again.
  float fOut = CR_NO_FIELD;
  const Hit hit = searchInside(t0, t1, fIn, fp, fOut);
  if (hit.cell < 0) {
    if (fOut == CR_NO_FIELD) fOut = field(localPoint(t1), fp);
    gSide = gOpenModel ? kSideUnknown : fOut > 0.0 ? kSideInside : kSideOutside;
    gExitField = abs(fOut);
  }
  return hit;
}

// ---- the DDA over the grid (ReliefTracer::trace) -------------------------------------------------

// The slab test of core/aabb.h, widened by 2 gamma(3) at the far end, on the surface's box (the
// CPU tracer's boundsWS()).
bool gridSpan(vec3 o, vec3 d, float tmin, float tmax, out float t0, out float t1) {
  const vec3 lo = gSurfaceMin, hi = gSurfaceMax;
  t0 = tmin;
  t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    const float inv = 1.0 / d[a];
    float tNear = (lo[a] - o[a]) * inv, tFar = (hi[a] - o[a]) * inv;
    if (tNear > tFar) {
      const float swap = tNear;
      tNear = tFar;
      tFar = swap;
    }
    tFar *= 1.0 + 2.0 * CR_GAMMA3;
    t0 = tNear > t0 ? tNear : t0;
    t1 = tFar < t1 ? tFar : t1;
    if (t0 > t1) return false;
  }
  return true;
}

// One DDA step to the next cell; false when the ray leaves the grid or its interval.
bool advanceCell(inout ivec3 cell, inout vec3 tMax, inout float tCell, float tExit, float tEnd, ivec3 stepDir,
                 vec3 tDelta, int n) {
  if (tExit >= tEnd) return false;
  const int axis = tMax.x < tMax.y ? (tMax.x < tMax.z ? 0 : 2) : (tMax.y < tMax.z ? 1 : 2);
  const bvec3 along = bvec3(axis == 0, axis == 1, axis == 2);
  cell += ivec3(along) * stepDir;
  const int c = axis == 0 ? cell.x : (axis == 1 ? cell.y : cell.z);
  if (c < 0 || c >= n) return false;
  tCell = axisOf(tMax, axis);
  tMax = mix(tMax, tMax + tDelta, along);
  return true;
}

Hit traceModel(vec3 o, vec3 d, float tmin, float tmax) {
  if (any(isinf(o)) || any(isnan(o)) || any(isinf(d)) || any(isnan(d)) || d == vec3(0.0) || !(tmin <= tmax))
    return noHit();
  float tStart, tEnd;
  if (!gridSpan(o, d, tmin, tmax, tStart, tEnd)) return noHit();
  const int n = gGrid;
  const float h = gCellSize;
  const vec3 entry = (o + tStart * d - gOrigin) / h;
  ivec3 cell = clamp(ivec3(floor(entry)), ivec3(0), ivec3(n - 1));
  ivec3 stepDir = ivec3(0);
  vec3 tMax = vec3(CR_INF), tDelta = vec3(CR_INF);
  for (int a = 0; a < 3; ++a) {
    const float inverse = 1.0 / d[a];
    if (d[a] == 0.0 || isinf(inverse)) continue;
    if (d[a] > 0.0) {
      stepDir[a] = 1;
      tMax[a] = (float(cell[a] + 1) * h + gOrigin[a] - o[a]) * inverse;
      tDelta[a] = h * inverse;
    } else {
      stepDir[a] = -1;
      tMax[a] = (float(cell[a]) * h + gOrigin[a] - o[a]) * inverse;
      tDelta[a] = -h * inverse;
    }
  }
  gSide = tStart > tmin ? kSideOutside : kSideUnknown;
  gExitField = CR_INF;
  float tCell = tStart;
  uint steps = 0u;  // over every grey cell searched
  for (;;) {
    // White and black cells in a tight loop of their own: every lane walks to its next grey cell
    // (or out of the grid) before the search runs, so the search runs with its lanes busy
    // (llvmpipe executes a block for all lanes when any lane takes it).
    int index = -1;
    float tExit;
    bool inside = true;
    for (;;) {
      tExit = min(min(tMax.x, tMax.y), min(tMax.z, tEnd));
      index = findCell(cell);
      if (index >= 0) break;
      gExitField = CR_INF;
      inside = advanceCell(cell, tMax, tCell, tExit, tEnd, stepDir, tDelta, n);
      if (!inside) break;
    }
    if (!inside) break;
    selectCell(index);
    const vec3 cellOrigin = gOrigin + vec3(cell) * h;
    gLocalOrigin = (o - cellOrigin) / h;
    gLocalDirection = d / h;
    Hit hit = searchCell(tCell, tExit);
    steps += hit.steps;
    if (hit.cell >= 0) {
      hit.steps = steps;
      return hit;
    }
    if (!advanceCell(cell, tMax, tCell, tExit, tEnd, stepDir, tDelta, n)) break;
  }
  return missAfter(steps);
}

// ---- polycube-mapped meshes (trace/polycube_tracer.h; the words of gpu/polycube_layout.h) --------

layout(std430, CR_BIND(10)) readonly buffer PolycubeWords { uint pcWords[]; };
layout(CR_BIND(11)) uniform sampler2DArray polycubeT2;

vec2 gT2InverseSize;  // set once in main()

int pcMeshCount() { return CR_POLYCUBE ? int(pcWords[0]) : 0; }
uint pcInfo(int mesh, int field) { return pcWords[1 + mesh * CR_PC_MESH_INFO_WORDS + field]; }
float pcFloat(uint index) { return uintBitsToFloat(pcWords[index]); }
vec3 pcVec3(uint index) { return vec3(pcFloat(index), pcFloat(index + 1u), pcFloat(index + 2u)); }

struct MeshHit {
  float t;
  float u, v;     // barycentrics of corners 1 and 2
  int triangle;   // in the BVH's leaf order; -1: none
  vec3 ng;        // unnormalized geometric normal
};

// intersectTriangle (core/hit.h): Moller-Trumbore with its barycentric slack.
bool pcIntersectTriangle(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, inout MeshHit best, int triangle) {
  const vec3 e1 = p1 - p0, e2 = p2 - p0;
  const vec3 pv = cross(d, e2);
  const float det = dot(e1, pv);
  if (det == 0.0) return false;
  const float invDet = 1.0 / det;
  const vec3 tv = o - p0;
  const float u = dot(tv, pv) * invDet;
  if (u < -CR_PC_BARYCENTRIC_SLACK || u > 1.0 + CR_PC_BARYCENTRIC_SLACK) return false;
  const vec3 qv = cross(tv, e1);
  const float v = dot(d, qv) * invDet;
  if (v < -CR_PC_BARYCENTRIC_SLACK || u + v > 1.0 + CR_PC_BARYCENTRIC_SLACK) return false;
  const float t = dot(e2, qv) * invDet;
  if (t < 0.0 || t >= best.t) return false;
  best = MeshHit(t, u, v, triangle, cross(e1, e2));
  return true;
}

uvec3 pcTriangle(int mesh, int triangle) {
  const uint at = pcInfo(mesh, CR_PC_TRIANGLE_OFFSET) + uint(triangle) * uint(CR_PC_TRIANGLE_WORDS);
  return uvec3(pcWords[at], pcWords[at + 1u], pcWords[at + 2u]);
}
uint pcVertex(int mesh, uint v) { return pcInfo(mesh, CR_PC_VERTEX_OFFSET) + v * uint(CR_PC_VERTEX_WORDS); }

// core/aabb.h intersect: the slab test of the CPU, exactly (a zero direction component decided by
// the origin alone, the far distance widened against rounding), so flat boxes are not missed.
// Where the ray enters the box before tmax (0 from inside), or -1 where it does not.
float boxEntry(vec3 o, vec3 d, vec3 inv, vec3 lo, vec3 hi, float tmax) {
  float t0 = 0.0, t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return -1.0;
      continue;
    }
    float tNear = (lo[a] - o[a]) * inv[a], tFar = (hi[a] - o[a]) * inv[a];
    if (tNear > tFar) {
      const float swapped = tNear;
      tNear = tFar;
      tFar = swapped;
    }
    tFar *= 1.0 + 2.0 * CR_GAMMA3;
    t0 = max(t0, tNear);
    t1 = min(t1, tFar);
    if (t0 > t1) return -1.0;
  }
  return t0;
}
bool boxReached(vec3 o, vec3 d, vec3 inv, vec3 lo, vec3 hi, float tmax) { return boxEntry(o, d, inv, lo, hi, tmax) >= 0.0; }

// TriangleBvh::closestHit (or anyHit): the nearest hit with t in [0, tmax).
MeshHit pcTrace(int mesh, vec3 o, vec3 d, float tmax, bool anyHit) {
  MeshHit best = MeshHit(tmax, 0.0, 0.0, -1, vec3(0.0));
  const uint nodeBase = pcInfo(mesh, CR_PC_NODE_OFFSET);
  const vec3 inv = 1.0 / d;
  uint stack[64];
  int top = 0;
  stack[top++] = 0u;
  while (top > 0) {
    const uint node = stack[--top];
    const uint at = nodeBase + node * uint(CR_PC_NODE_WORDS);
    if (!boxReached(o, d, inv, pcVec3(at), pcVec3(at + 3u), best.t)) continue;
    const uint first = pcWords[at + 6u], count = pcWords[at + 7u];
    if (count == 0u) {
      if (top < 62) {
        stack[top++] = first;       // the right child
        stack[top++] = node + 1u;   // the left child, next
      }
      continue;
    }
    for (uint i = first; i < first + count; ++i) {
      const uvec3 t = pcTriangle(mesh, int(i));
      if (pcIntersectTriangle(o, d, pcVec3(pcVertex(mesh, t.x)), pcVec3(pcVertex(mesh, t.y)), pcVec3(pcVertex(mesh, t.z)),
                              best, int(i)) && anyHit)
        return best;
    }
  }
  return best;
}

// The nearest mesh hit before tmax (CpuBackend::intersect, after the relief models); the mesh or -1.
int pcTraceMeshes(vec3 o, vec3 d, float tmax, out MeshHit best) {
  best = MeshHit(tmax, 0.0, 0.0, -1, vec3(0.0));
  int found = -1;
  for (int m = 0; m < pcMeshCount(); ++m) {
    const MeshHit h = pcTrace(m, o, d, best.t, false);
    if (h.triangle >= 0 && h.t < best.t) {
      best = h;
      found = m;
    }
  }
  return found;
}

bool pcOccluded(vec3 o, vec3 d) {
  for (int m = 0; m < pcMeshCount(); ++m)
    if (pcTrace(m, o, d, CR_INF, true).triangle >= 0) return true;
  return false;
}

// The look-up table's entry of a lattice vertex: (case | signed permutation << 3 | squarelets << 12,
// first tile); case CR_PC_EMPTY_CASE outside the box or where no surface passes.
uvec2 pcEntry(int mesh, ivec3 vertex) {
  const ivec3 origin = ivec3(int(pcInfo(mesh, CR_PC_LUT_ORIGIN)), int(pcInfo(mesh, CR_PC_LUT_ORIGIN + 1)),
                             int(pcInfo(mesh, CR_PC_LUT_ORIGIN + 2)));
  const ivec3 size = ivec3(int(pcInfo(mesh, CR_PC_LUT_SIZE)), int(pcInfo(mesh, CR_PC_LUT_SIZE + 1)),
                           int(pcInfo(mesh, CR_PC_LUT_SIZE + 2)));
  const ivec3 l = vertex - origin;
  if (any(lessThan(l, ivec3(0))) || any(greaterThanEqual(l, size))) return uvec2(uint(CR_PC_EMPTY_CASE), 0u);
  const uint index = (uint(l.z) * uint(size.y) + uint(l.y)) * uint(size.x) + uint(l.x);
  const uint at = pcInfo(mesh, CR_PC_LUT_OFFSET) + index * uint(CR_PC_LUT_ENTRY_WORDS);
  return uvec2(pcWords[at], pcWords[at + 1u]);
}

// applyTransform / applyInverseTransform (vertex_configuration.h) as signed permutations.
vec3 pcApply(uint permutation, vec3 d) {
  vec3 r;
  for (int i = 0; i < 3; ++i) {
    const uint f = (permutation >> uint(3 * i)) & 7u;
    const float v = d[int(f & 3u)];
    r[i] = (f & 4u) != 0u ? -v : v;
  }
  return r;
}
vec3 pcApplyInverse(uint permutation, vec3 d) {
  vec3 r;
  for (int i = 0; i < 3; ++i) {
    const uint f = (permutation >> uint(3 * i)) & 7u;
    r[int(f & 3u)] = (f & 4u) != 0u ? -d[i] : d[i];
  }
  return r;
}

// projection.h, detail::projectFromBoxCorner: cases 3, 4a, 4b.
vec3 pcProjectFromBoxCorner(vec3 p, bvec3 activeAxes) {
  float t = CR_INF;
  for (int a = 0; a < 3; ++a)
    if (activeAxes[a] && p[a] > -0.5) t = min(t, 0.5 / (p[a] + 0.5));
  if (t == CR_INF) return p;
  vec3 q = p;
  for (int a = 0; a < 3; ++a)
    if (activeAxes[a]) q[a] = -0.5 + t * (p[a] + 0.5);
  return q;
}

// detail::projectCase5.
vec3 pcProjectCase5(vec3 p) {
  const vec2 w = vec2(p.x - 0.5, p.y - 0.5);
  const float r = max(-w.x, -w.y);
  if (r <= 0.0) return vec3(0.5, 0.5, 0.0);
  const float sigma = 2.0 * r - 1.0, z = p.z;
  if (sigma >= 1.0 && z <= -0.5) return p;
  float sigmaImage, zImage;
  if (sigma >= -2.0 * z) {
    const float t = 0.5 / (z + 0.5);
    sigmaImage = 1.0 + t * (sigma - 1.0);
    zImage = 0.0;
  } else {
    const float t = 1.0 / (1.0 - sigma);
    sigmaImage = 0.0;
    zImage = -0.5 + t * (z + 0.5);
  }
  const float rImage = 0.5 * (sigmaImage + 1.0);
  return vec3(0.5 + w.x * (rImage / r), 0.5 + w.y * (rImage / r), zImage);
}

// detail::projectArmFan.
vec3 pcProjectArmFan(int axis, vec3 p) {
  const int b = axis == 2 ? 0 : axis + 1, c = b == 2 ? 0 : b + 1;
  const float r = max(p[b] + 0.5, p[c] + 0.5);
  const float sigma = 2.0 * r - 1.0, h = p[axis];
  if (r <= 0.0 || sigma >= 1.0) return p;
  const float tWall = 1.0 / (1.0 - sigma);
  const float hWall = 0.5 + tWall * (h - 0.5);
  float sigmaImage = 0.0, hImage = hWall;
  if (hWall < 0.0) {
    sigmaImage = 1.0 + (0.5 / (0.5 - h)) * (sigma - 1.0);
    hImage = 0.0;
  }
  const float scale = 0.5 * (sigmaImage + 1.0) / r;
  vec3 q;
  q[axis] = hImage;
  q[b] = -0.5 + (p[b] + 0.5) * scale;
  q[c] = -0.5 + (p[c] + 0.5) * scale;
  return q;
}

int pcLargest(vec3 v) { return v.x >= v.y && v.x >= v.z ? 0 : (v.y >= v.z ? 1 : 2); }

// detail::projectCase6a.
vec3 pcProjectCase6a(vec3 p) {
  const int positive = (p.x > 0.0 ? 1 : 0) + (p.y > 0.0 ? 1 : 0) + (p.z > 0.0 ? 1 : 0);
  if (positive <= 1) return pcProjectArmFan(pcLargest(p), p);
  return -pcProjectArmFan(pcLargest(-p), -p);
}

// detail::case6bSpinePoint.
vec3 pcCase6bSpinePoint(float s) {
  s = clamp(s, 0.0, 3.0);
  if (s <= 1.0) return vec3(s - 0.5, -0.5, -0.5);
  if (s <= 2.0) return vec3(0.5, s - 1.5, -0.5);
  return vec3(0.5, 0.5, s - 2.5);
}

// detail::case6bSpineParameter.
float pcCase6bSpineParameter(vec3 p) {
  const float sL = p.x + p.y <= 0.0 ? (p.x + 0.5) / (0.5 - p.y) : 2.0 - (0.5 - p.y) / (p.x + 0.5);
  const float sR = p.y + p.z <= 0.0 ? 1.0 + (p.y + 0.5) / (0.5 - p.z) : 3.0 - (0.5 - p.z) / (p.y + 0.5);
  if (p.x <= 0.0) return sL;
  if (p.z >= 0.0) return sR;
  const float a = min(min(length(vec2(p.x, max(p.y, 0.0))), p.y + 0.5), p.z + 0.5);
  const float b = min(min(0.5 - p.x, 0.5 - p.y), length(vec2(p.z, min(p.y, 0.0))));
  if (a + b <= 0.0) return 1.5;
  const float w = a * a / (a * a + b * b);
  return (1.0 - w) * sL + w * sR;
}

// detail::case6bFirstSurfaceHit, over case 6b's six squarelets (squareletBounds).
vec3 pcCase6bFirstSurfaceHit(vec3 p, vec3 d) {
  const vec3 lo[6] = vec3[6](vec3(-0.5, 0.0, -0.5), vec3(-0.5, -0.5, 0.0), vec3(0.0, -0.5, 0.0),
                             vec3(0.0, 0.0, -0.5), vec3(0.0), vec3(0.0));
  const vec3 hi[6] = vec3[6](vec3(0.0), vec3(0.0), vec3(0.5, 0.0, 0.0), vec3(0.0, 0.5, 0.0),
                             vec3(0.0, 0.5, 0.5), vec3(0.5, 0.0, 0.5));
  const int axes[6] = int[6](1, 2, 2, 0, 0, 1);
  float best = CR_INF;
  for (int i = 0; i < 6; ++i) {
    if (clamp(p, lo[i], hi[i]) == p) return p;
    const int axis = axes[i];
    if (d[axis] == 0.0) continue;
    const float t = -p[axis] / d[axis];
    if (t < 0.0 || t >= best) continue;
    const vec3 x = p + t * d;
    bool inside = true;
    for (int k = 0; k < 3; ++k)
      if (k != axis && (x[k] < lo[i][k] - 1e-6 || x[k] > hi[i][k] + 1e-6)) inside = false;
    if (inside) best = t;
  }
  if (best != CR_INF) return clamp(p + best * d, vec3(-0.5), vec3(0.5));
  vec3 nearest = p;  // a miss, beyond reach: the surface's nearest point
  float nearestDistance = CR_INF;
  for (int i = 0; i < 6; ++i) {
    const vec3 clamped = clamp(p, lo[i], hi[i]);
    const float distance = length(p - clamped);
    if (distance < nearestDistance) {
      nearestDistance = distance;
      nearest = clamped;
    }
  }
  return nearest;
}

// detail::projectCase6b: the solid side, and the empty side through (x, y, z) -> (z, -y, x).
vec3 pcProjectCase6bSolid(vec3 p) {
  return pcCase6bFirstSurfaceHit(p, p - pcCase6bSpinePoint(pcCase6bSpineParameter(p)));
}
vec3 pcProjectCase6b(vec3 p) {
  const int octant = (p.x > 0.0 ? 1 : 0) | (p.y > 0.0 ? 2 : 0) | (p.z > 0.0 ? 4 : 0);
  if (((0x8bu >> uint(octant)) & 1u) != 0u) return pcProjectCase6bSolid(p);
  const vec3 image = pcProjectCase6bSolid(vec3(p.z, -p.y, p.x));
  return vec3(image.z, -image.y, image.x);
}

// PolycubeSurface::project: P through the dual cell of the nearest lattice vertex.
bool pcProject(int mesh, vec3 p, out vec3 q) {
  q = p;
  const ivec3 vertex = ivec3(floor(p + 0.5));
  const uvec2 e = pcEntry(mesh, vertex);
  const uint c = e.x & 7u;
  if (c >= 6u) return false;  // empty
  const uint permutation = (e.x >> 3u) & 0x1ffu;
  const vec3 d = pcApplyInverse(permutation, p - vec3(vertex));
  vec3 image;
  if (c == 0u) image = pcProjectFromBoxCorner(d, bvec3(true, true, true));
  else if (c == 1u) image = pcProjectFromBoxCorner(d, bvec3(false, false, true));
  else if (c == 2u) image = pcProjectFromBoxCorner(d, bvec3(false, true, true));
  else if (c == 3u) image = pcProjectCase5(d);
  else if (c == 4u) image = pcProjectCase6a(d);
  else image = pcProjectCase6b(d);
  q = vec3(vertex) + pcApply(permutation, image);
  return true;
}

// PolycubeLut::locate and LutEntry::tileOf: the tile and squarelet coordinates of a surface point.
bool pcLocate(int mesh, vec3 p, out uint tile, out vec2 st) {
  tile = 0u;
  st = vec2(0.0);
  const ivec3 vertex = ivec3(floor(p + 0.5));
  const uvec2 e = pcEntry(mesh, vertex);
  if ((e.x & 7u) == uint(CR_PC_EMPTY_CASE)) return false;
  const uint squarelets = (e.x >> 12u) & 0xfffu;
  const vec3 d = p - vec3(vertex);
  const vec3 m = abs(d);
  // The planes the point is nearest first (std::sort of the three axes by |d|).
  ivec3 order = ivec3(0, 1, 2);
  if (m[order.y] < m[order.x]) order.xy = order.yx;
  if (m[order.z] < m[order.y]) order.yz = order.zy;
  if (m[order.y] < m[order.x]) order.xy = order.yx;
  for (int k = 0; k < 3; ++k) {
    const int axis = order[k];
    if (m[axis] > CR_PC_LOCATE_TOLERANCE) break;
    const int a = axis == 2 ? 0 : axis + 1, b = a == 2 ? 0 : a + 1;
    const int lo = min(a, b), hi = max(a, b);
    const int loSides = m[lo] <= CR_PC_LOCATE_TOLERANCE ? 2 : 1, hiSides = m[hi] <= CR_PC_LOCATE_TOLERANCE ? 2 : 1;
    for (int i = 0; i < loSides; ++i)
      for (int j = 0; j < hiSides; ++j) {
        const bool loPositive = loSides == 2 ? i == 1 : d[lo] > 0.0, hiPositive = hiSides == 2 ? j == 1 : d[hi] > 0.0;
        const uint s = uint(4 * axis + (loPositive ? 1 : 0) + (hiPositive ? 2 : 0));
        if (((squarelets >> s) & 1u) != 0u) {
          tile = e.y + uint(bitCount(squarelets & ((1u << s) - 1u)));
          st = 2.0 * vec2(m[lo], m[hi]);
          return true;
        }
      }
  }
  return false;
}

// PolycubeTexture::atlasPosition, in texels of the stacked texture.
vec2 pcAtlasPosition(int mesh, uint tile, vec2 st, int level) {
  const uint tilesPerRow = pcInfo(mesh, CR_PC_TILES_PER_ROW);
  const int texels = max(1, int(pcInfo(mesh, CR_PC_TEXELS)) >> level);
  const float size = float(texels + 2);
  return vec2(float(tile % tilesPerRow) * size + 1.0 + st.x * float(texels),
              float(pcInfo(mesh, CR_PC_LEVEL_ROW + level)) + float(tile / tilesPerRow) * size + 1.0 + st.y * float(texels));
}

vec4 pcBilinear(int mesh, uint tile, vec2 st, int level) {
  return textureLod(polycubeT2, vec3(pcAtlasPosition(mesh, tile, st, level) * gT2InverseSize, 0.0), 0.0);
}

// PolycubeTexture::sample.
vec4 pcSample(int mesh, uint tile, vec2 st, float lod) {
  st = clamp(st, vec2(0.0), vec2(1.0));
  const uint filterMode = pcInfo(mesh, CR_PC_FILTER);
  if (filterMode == 0u) {
    const int texels = int(pcInfo(mesh, CR_PC_TEXELS));
    const ivec2 i = min(ivec2(st * float(texels)), ivec2(texels - 1));
    const vec2 corner = pcAtlasPosition(mesh, tile, vec2(0.0), 0);
    return texelFetch(polycubeT2, ivec3(ivec2(corner) + i, 0), 0);
  }
  if (filterMode == 1u) return pcBilinear(mesh, tile, st, 0);
  const int levels = int(pcInfo(mesh, CR_PC_LEVELS));
  const float clamped = clamp(lod, 0.0, float(levels - 1));
  const int lower = int(floor(clamped));
  const int upper = min(lower + 1, levels - 1);
  const vec4 a = pcBilinear(mesh, tile, st, lower);
  if (upper == lower) return a;
  return mix(a, pcBilinear(mesh, tile, st, upper), clamped - float(lower));
}

float pcSurfaceOffset(int mesh) { return uintBitsToFloat(pcInfo(mesh, CR_PC_SURFACE_OFFSET)); }

// PolycubeTracer::intersect after the BVH: the shading normal and base colour of a mesh hit.
void pcShade(int mesh, MeshHit h, vec3 direction, float spread, out vec3 normal, out vec3 base) {
  const uvec3 t = pcTriangle(mesh, h.triangle);
  const uint v0 = pcVertex(mesh, t.x), v1 = pcVertex(mesh, t.y), v2 = pcVertex(mesh, t.z);
  const float w0 = 1.0 - h.u - h.v, w1 = h.u, w2 = h.v;
  const vec3 n = w0 * pcVec3(v0 + 3u) + w1 * pcVec3(v1 + 3u) + w2 * pcVec3(v2 + 3u);
  normal = length(n) > 0.0 ? n / length(n) : normalize(h.ng);
  base = vec3(200.0 / 255.0);
  if (pcInfo(mesh, CR_PC_USE) == 2u) return;  // TextureUse::None
  const vec3 texturePosition = w0 * pcVec3(v0 + 6u) + w1 * pcVec3(v1 + 6u) + w2 * pcVec3(v2 + 6u);
  const float cosine = abs(dot(normalize(direction), normalize(h.ng)));
  const float footprint = spread * h.t * length(direction) / max(cosine, CR_PC_MIN_FOOTPRINT_COSINE);
  const float cubesPerWorld = pcFloat(pcInfo(mesh, CR_PC_TRIANGLE_OFFSET) + uint(h.triangle) * uint(CR_PC_TRIANGLE_WORDS) + 3u);
  const float lod = log2(max(footprint * cubesPerWorld * 2.0 * float(pcInfo(mesh, CR_PC_TEXELS)), 1e-30));
  vec3 onSurface;
  uint tile;
  vec2 st;
  if (!pcProject(mesh, texturePosition, onSurface) || !pcLocate(mesh, onSurface, tile, st)) return;
  const vec4 texel = pcSample(mesh, tile, st, lod);
  if (pcInfo(mesh, CR_PC_USE) == 0u) {
    base = texel.rgb;
  } else {
    const vec3 mapped = 2.0 * texel.rgb - 1.0;
    if (length(mapped) > 0.1) normal = normalize(mapped);
  }
}

// ---- geometry textures (trace/geotex_tracer.h; the words of gpu/geotex_layout.h) ---------------

layout(std430, CR_BIND(12)) readonly buffer GeoTexWords { uint gtWords[]; };

#define CR_GT_NO_SURFACE 1e30  // a height below any surface: the gap above it counts as "no surface"

int gtModelCount() { return CR_GEOTEX ? int(gtWords[0]) : 0; }
uint gtInfo(int model, int field) { return gtWords[1 + model * CR_GT_MODEL_INFO_WORDS + field]; }
float gtFloat(uint index) { return uintBitsToFloat(gtWords[index]); }
vec3 gtVec3(uint index) { return vec3(gtFloat(index), gtFloat(index + 1u), gtFloat(index + 2u)); }

struct ChartHit {
  float t;
  vec2 uv;    // chart coordinates in texels
  int chart;  // -1: none
};

struct Chart {
  vec3 origin, rowX, rowY, rowZ, boxSize;
  float heightScale;
  int width, height;
  uint firstTexel;
  uint heightBase;  // the model's height words
  uint emptyCode;
  uint pyramid;     // the word of the first level-1 pyramid node
};

Chart gtChart(int model, int c) {
  const uint at = gtInfo(model, CR_GT_CHART_OFFSET) + uint(c) * uint(CR_GT_CHART_WORDS);
  Chart ch;
  ch.origin = gtVec3(at + uint(CR_GT_ORIGIN));
  ch.rowX = gtVec3(at + uint(CR_GT_ROW_X));
  ch.rowY = gtVec3(at + uint(CR_GT_ROW_Y));
  ch.rowZ = gtVec3(at + uint(CR_GT_ROW_Z));
  ch.boxSize = gtVec3(at + uint(CR_GT_BOX_SIZE));
  ch.heightScale = gtFloat(at + uint(CR_GT_HEIGHT_SCALE));
  ch.width = int(gtWords[at + uint(CR_GT_WIDTH)]);
  ch.height = int(gtWords[at + uint(CR_GT_HEIGHT)]);
  ch.firstTexel = gtWords[at + uint(CR_GT_FIRST_TEXEL)];
  ch.heightBase = gtInfo(model, CR_GT_HEIGHT_OFFSET);
  ch.emptyCode = gtInfo(model, CR_GT_EMPTY_CODE);
  ch.pyramid = gtWords[at + uint(CR_GT_PYRAMID)];
  return ch;
}

uint gtCode(Chart ch, uint texel) {
  const uint w = gtWords[ch.heightBase + texel / 2u];
  return (texel & 1u) != 0u ? w >> 16 : w & 0xffffu;
}

// GeoTexTracer::taps: bilinear taps over texel centres, clamped; empty taps weigh 0, and no tap
// at all counts where the texel under the point is empty.
float gtTaps(Chart ch, vec2 p, out uint texels[4], out float weights[4]) {
  for (int k = 0; k < 4; ++k) {
    texels[k] = 0u;
    weights[k] = 0.0;
  }
  const float far = float(1 << 30);
  if (!(p.x > -far && p.x < far && p.y > -far && p.y < far)) return 0.0;
  const int ni = clamp(int(floor(p.x)), 0, ch.width - 1), nj = clamp(int(floor(p.y)), 0, ch.height - 1);
  if (gtCode(ch, ch.firstTexel + uint(nj * ch.width + ni)) == ch.emptyCode) return 0.0;
  const vec2 f = p - 0.5;
  const int i0 = int(floor(f.x)), j0 = int(floor(f.y));
  const float ax = f.x - float(i0), ay = f.y - float(j0);
  float total = 0.0;
  for (int k = 0; k < 4; ++k) {
    const int i = clamp(i0 + (k & 1), 0, ch.width - 1), j = clamp(j0 + (k >> 1), 0, ch.height - 1);
    texels[k] = ch.firstTexel + uint(j * ch.width + i);
    const float w = ((k & 1) != 0 ? ax : 1.0 - ax) * ((k >> 1) != 0 ? ay : 1.0 - ay);
    weights[k] = gtCode(ch, texels[k]) == ch.emptyCode ? 0.0 : w;
    total += weights[k];
  }
  return total;
}

// GeoTexTracer::height: the surface height at chart point p, -CR_GT_NO_SURFACE where none. The
// taps of gtTaps written out, in its order: arrays indexed in a loop cost llvmpipe a trip through
// memory per sample (this hot path measured 1.3x as fast without them).
float gtHeight(Chart ch, vec2 p) {
  const float far = float(1 << 30);
  if (!(p.x > -far && p.x < far && p.y > -far && p.y < far)) return -CR_GT_NO_SURFACE;
  const int ni = clamp(int(floor(p.x)), 0, ch.width - 1), nj = clamp(int(floor(p.y)), 0, ch.height - 1);
  if (gtCode(ch, ch.firstTexel + uint(nj * ch.width + ni)) == ch.emptyCode) return -CR_GT_NO_SURFACE;
  const vec2 f = p - 0.5;
  const int i0 = int(floor(f.x)), j0 = int(floor(f.y));
  const float ax = f.x - float(i0), ay = f.y - float(j0);
  const uint ia = uint(clamp(i0, 0, ch.width - 1)), ib = uint(clamp(i0 + 1, 0, ch.width - 1));
  const uint rowA = ch.firstTexel + uint(clamp(j0, 0, ch.height - 1) * ch.width);
  const uint rowB = ch.firstTexel + uint(clamp(j0 + 1, 0, ch.height - 1) * ch.width);
  const uint c0 = gtCode(ch, rowA + ia), c1 = gtCode(ch, rowA + ib), c2 = gtCode(ch, rowB + ia), c3 = gtCode(ch, rowB + ib);
  const float w0 = c0 == ch.emptyCode ? 0.0 : (1.0 - ax) * (1.0 - ay);
  const float w1 = c1 == ch.emptyCode ? 0.0 : ax * (1.0 - ay);
  const float w2 = c2 == ch.emptyCode ? 0.0 : (1.0 - ax) * ay;
  const float w3 = c3 == ch.emptyCode ? 0.0 : ax * ay;
  const float total = w0 + w1 + w2 + w3;
  if (!(total > 0.0)) return -CR_GT_NO_SURFACE;
  const float h = w0 * float(c0) + w1 * float(c1) + w2 * float(c2) + w3 * float(c3);
  return h / total * ch.heightScale;
}

float gtGap(Chart ch, vec3 o, vec3 d, float t, inout uint samples) {
  const vec3 p = o + t * d;
  ++samples;
  return p.z - gtHeight(ch, p.xy);
}

bool gtHasSurface(float gap) { return gap < 0.5 * CR_GT_NO_SURFACE; }

// GeoTexTracer::refine: binary search from above (ta) to below (tb), then a secant step.
float gtRefine(Chart ch, vec3 o, vec3 d, float ta, float tb, float gapA, float gapB, inout uint samples) {
  for (int k = 0; k < CR_GT_BINARY_STEPS; ++k) {
    const float tm = 0.5 * (ta + tb);
    const float gap = gtGap(ch, o, d, tm, samples);
    if (gap > 0.0) {
      ta = tm;
      gapA = gap;
    } else {
      tb = tm;
      gapB = gap;
    }
  }
  return gtHasSurface(gapA) && gapA - gapB > 0.0 ? ta + (tb - ta) * gapA / (gapA - gapB) : tb;
}

int gtNodesAlong(int texels, int level) { return ((texels - 1) >> level) + 1; }

// Where the ray leaves pyramid node `node` (of `count` on this axis) at `level`, the node moved on
// while the ray at t is on its far side (GeoTexTracer::sameSideUntil's exitAlong).
float gtNodeExit(float origin, float dir, float inverse, float t, int level, inout int node, int count) {
  if (dir == 0.0) return CR_INF;
  float exit = 0.0;
  for (int k = 0; k <= count; ++k) {
    exit = (float((dir > 0.0 ? node + 1 : node) << level) - origin) * inverse;
    const int next = node + (dir > 0.0 ? 1 : -1);
    if (exit > t || next < 0 || next >= count) break;
    node = next;
  }
  return exit;
}

// GeoTexTracer::sameSideUntil: how far from t (up to tEnd) the ray stays above every surface
// point under it (`above`) or below every one, by the chart's pyramid; t where it cannot tell.
// `retry`: where the level-1 node it stopped in ends. Each node tested counts as a step.
float gtSameSideUntil(Chart ch, vec3 o, vec3 d, float t, float tEnd, bool above, out float retry, inout uint samples) {
  const float margin = 1e-6 * ch.boxSize.z;
  const vec2 inverse = vec2(1.0) / d.xy;
  int level = 1;
  uint first = ch.pyramid;  // the level's first node
  for (int pass = 0; pass < 8 * (ch.width + ch.height) && t < tEnd; ++pass) {
    ++samples;
    const int w = gtNodesAlong(ch.width, level), h = gtNodesAlong(ch.height, level);
    const vec3 p = o + t * d;
    const float far = float(1 << 30);  // far outside the map, or not a number: no walk
    if (!(abs(p.x) < far && abs(p.y) < far)) {
      retry = t;
      return t;
    }
    int i = clamp(int(floor(p.x)) >> level, 0, w - 1);
    int j = clamp(int(floor(p.y)) >> level, 0, h - 1);
    const float exitX = gtNodeExit(o.x, d.x, inverse.x, t, level, i, w);
    const float exitY = gtNodeExit(o.y, d.y, inverse.y, t, level, j, h);
    const float exit = min(min(exitX, exitY), tEnd);
    const float zExit = o.z + exit * d.z;
    const uint node = gtWords[first + uint(j * w + i)];
    const uint stored = above ? node & 0xffffu : node >> 16;
    const float bound = float(int(stored) - 1) * ch.heightScale;
    const bool passes = above ? stored == 0u || min(p.z, zExit) > bound + margin
                              : stored != 0u && max(p.z, zExit) < bound - margin;
    if (exit > t && passes) {
      t = exit;
      if (w > 1 || h > 1) {
        first += uint(w * h);
        ++level;
      }
    } else if (level == 1) {
      retry = max(t, exit);
      return t;
    } else {
      --level;
      first -= uint(gtNodesAlong(ch.width, level) * gtNodesAlong(ch.height, level));
    }
  }
  retry = t;
  return min(t, tEnd);
}

// GeoTexTracer::intersectChart: the chart's box in chart units (the slab test of core/aabb.h),
// linear steps by the texels crossed, a passage from above the surface to below it.
bool gtIntersectChart(int model, int c, vec3 ro, vec3 rd, float limit, inout ChartHit hit, inout uint samples) {
  const Chart ch = gtChart(model, c);
  const vec3 d0 = ro - ch.origin;
  const vec3 o = vec3(dot(d0, ch.rowX), dot(d0, ch.rowY), dot(d0, ch.rowZ));
  const vec3 d = vec3(dot(rd, ch.rowX), dot(rd, ch.rowY), dot(rd, ch.rowZ));
  const vec3 inv = 1.0 / d;
  float t0 = 0.0, t1 = limit;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < 0.0 || o[a] > ch.boxSize[a]) return false;
      continue;
    }
    float tNear = (0.0 - o[a]) * inv[a], tFar = (ch.boxSize[a] - o[a]) * inv[a];
    if (tNear > tFar) {
      const float swapped = tNear;
      tNear = tFar;
      tFar = swapped;
    }
    tFar *= 1.0 + 2.0 * CR_GAMMA3;
    t0 = max(t0, tNear);
    t1 = min(t1, tFar);
    if (t0 > t1) return false;
  }
  // GeoTexTracer::linearSteps
  const float wanted = length(d.xy) * (t1 - t0) * CR_GT_STEPS_PER_TEXEL;
  const int most = 4 * (ch.width + ch.height) + CR_GT_MIN_LINEAR_STEPS;
  const int steps = wanted < float(most) ? max(CR_GT_MIN_LINEAR_STEPS, int(ceil(wanted))) : most;
  const float dt = (t1 - t0) / float(steps);
  float tBefore = t0;
  float gapBefore = gtGap(ch, o, d, t0, samples);
  const bool skip = (P.flags.y & 1) != 0;  // --no-skip turns it off for every representation
  float walkFrom = t0;                      // the pyramid walk's next try, not before
  for (int k = 1; k <= steps; ++k) {
    if (skip && k < steps && tBefore >= walkFrom) {
      // Steps k..m stay on the side of the surface of step k - 1: the search goes on from step m.
      const bool above = gapBefore > 0.0;
      const float safe = gtSameSideUntil(ch, o, d, tBefore, t1, above, walkFrom, samples);
      if (safe >= t1) return false;
      const float along = (safe - t0) / dt;  // steps passed; not a number in a degenerate box
      int m = along >= 0.0 ? int(min(along, float(steps - 1))) : k - 1;
      while (m >= k && t0 + float(m) * dt > safe) --m;
      if (m > k) {
        const float tm = t0 + float(m) * dt;
        const float gapM = gtGap(ch, o, d, tm, samples);
        if ((gapM > 0.0) == above) {
          tBefore = tm;
          gapBefore = gapM;
          k = m;
          continue;
        }
      }
    }
    const float t = k == steps ? t1 : t0 + float(k) * dt;
    const float gap = gtGap(ch, o, d, t, samples);
    if (gap <= 0.0 && gapBefore > 0.0) {
      float found = -1.0;
      if (gtHasSurface(gapBefore)) {
        found = gtRefine(ch, o, d, tBefore, t, gapBefore, gap, samples);
      } else {
        // From no surface to below one: a hit only if the ray was above the surface where the
        // map's edge was crossed, not if it ran into the side of the height field.
        float ta = tBefore, tb = t;
        for (int b = 0; b < CR_GT_BINARY_STEPS + 4; ++b) {
          const float tm = 0.5 * (ta + tb);
          const float gm = gtGap(ch, o, d, tm, samples);
          if (gm > 0.0 && gtHasSurface(gm)) {
            found = gtRefine(ch, o, d, tm, tb, gm, gap, samples);
            break;
          }
          if (gm > 0.0) ta = tm;
          else tb = tm;
        }
      }
      if (found >= 0.0) {
        hit.t = found;
        hit.uv = (o + found * d).xy;
        hit.chart = c;
        return true;
      }
    }
    tBefore = t;
    gapBefore = gap;
  }
  return false;
}

// Where the ray enters BVH node `node` before tmax, or -1.
float gtNodeEntry(uint nodeBase, uint node, vec3 o, vec3 d, vec3 inv, float tmax) {
  const uint at = nodeBase + node * uint(CR_GT_NODE_WORDS);
  return boxEntry(o, d, inv, gtVec3(at), gtVec3(at + 3u), tmax);
}

// GeoTexTracer::intersect over one model: its BVH of chart boxes nearer first
// (BoxBvh::traverseNearFirst), the nearest hit before tmax.
ChartHit gtTrace(int model, vec3 o, vec3 d, float tmax, bool anyHit, inout uint samples) {
  ChartHit best = ChartHit(tmax, vec2(0.0), -1);
  const uint nodeBase = gtInfo(model, CR_GT_NODE_OFFSET), primitives = gtInfo(model, CR_GT_PRIMITIVE_OFFSET);
  const vec3 inv = 1.0 / d;
  uint stack[64];
  float entries[64];
  int top = 0;
  const float rootEntry = gtNodeEntry(nodeBase, 0u, o, d, inv, best.t);
  if (rootEntry < 0.0) return best;
  stack[top] = 0u;
  entries[top++] = rootEntry;
  while (top > 0) {
    --top;
    const uint node = stack[top];
    if (entries[top] > best.t) continue;
    const uint at = nodeBase + node * uint(CR_GT_NODE_WORDS);
    const uint first = gtWords[at + 6u], count = gtWords[at + 7u];
    if (count == 0u) {
      const uint left = node + 1u, right = first;
      const float leftEntry = gtNodeEntry(nodeBase, left, o, d, inv, best.t);
      const float rightEntry = gtNodeEntry(nodeBase, right, o, d, inv, best.t);
      if (top < 62) {
        if (leftEntry >= 0.0 && rightEntry >= 0.0) {
          const bool leftFirst = leftEntry <= rightEntry;
          stack[top] = leftFirst ? right : left;
          entries[top++] = leftFirst ? rightEntry : leftEntry;
          stack[top] = leftFirst ? left : right;
          entries[top++] = leftFirst ? leftEntry : rightEntry;
        } else if (leftEntry >= 0.0) {
          stack[top] = left;
          entries[top++] = leftEntry;
        } else if (rightEntry >= 0.0) {
          stack[top] = right;
          entries[top++] = rightEntry;
        }
      }
      continue;
    }
    for (uint i = first; i < first + count; ++i)
      if (gtIntersectChart(model, int(gtWords[primitives + i]), o, d, best.t, best, samples) && anyHit) return best;
  }
  return best;
}

// The nearest chart hit before tmax (CpuBackend::intersect, after relief models and meshes).
int gtTraceModels(vec3 o, vec3 d, float tmax, out ChartHit best, inout uint samples) {
  best = ChartHit(tmax, vec2(0.0), -1);
  int found = -1;
  for (int m = 0; m < gtModelCount(); ++m) {
    const ChartHit h = gtTrace(m, o, d, best.t, false, samples);
    if (h.chart >= 0 && h.t < best.t) {
      best = h;
      found = m;
    }
  }
  return found;
}

bool gtOccluded(vec3 o, vec3 d) {
  uint samples = 0u;
  for (int m = 0; m < gtModelCount(); ++m)
    if (gtTrace(m, o, d, CR_INF, true, samples).chart >= 0) return true;
  return false;
}

float gtSurfaceOffset(int model) { return uintBitsToFloat(gtInfo(model, CR_GT_SURFACE_OFFSET)); }

// GeoTexTracer's normal and colorAt: the maps filtered like the heights.
void gtShade(int model, ChartHit h, out vec3 normal, out vec3 base) {
  const Chart ch = gtChart(model, h.chart);
  uint texels[4];
  float weights[4];
  const float total = gtTaps(ch, h.uv, texels, weights);
  const uint normalBase = gtInfo(model, CR_GT_NORMAL_OFFSET), colorBase = gtInfo(model, CR_GT_COLOR_OFFSET);
  vec3 n = vec3(0.0), c = vec3(0.0);
  for (int k = 0; k < 4; ++k) {
    if (weights[k] == 0.0) continue;
    const uint e = gtWords[normalBase + texels[k]];
    // octahedralDecode of core/octahedral.h
    vec2 oct = vec2(float(e & 0xffffu), float(e >> 16)) / 65535.0;
    oct = oct * 2.0 - 1.0;
    vec3 m = vec3(oct.x, oct.y, 1.0 - abs(oct.x) - abs(oct.y));
    const float t = max(-m.z, 0.0);
    m.x += m.x >= 0.0 ? -t : t;
    m.y += m.y >= 0.0 ? -t : t;
    n += weights[k] * normalize(m);
    if (colorBase != 0u) c += (weights[k] / total) * vec3(unpackUnorm4x8(gtWords[colorBase + texels[k]]).rgb);
  }
  normal = length(n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
  base = colorBase != 0u && total > 0.0 ? c : vec3(CR_GT_NEUTRAL_GREY);
}

// ---- relief surfaces (trace/parallax_tracer.h; the words of gpu/parallax_layout.h) ------------

layout(std430, CR_BIND(13)) readonly buffer ParallaxWords { uint pxWords[]; };

int pxSurfaceCount() { return CR_PARALLAX ? int(pxWords[0]) : 0; }
uint pxInfo(int s, int field) { return pxWords[1 + s * CR_PX_SURFACE_WORDS + field]; }
float pxInfoFloat(int s, int field) { return uintBitsToFloat(pxInfo(s, field)); }
vec3 pxInfoVec3(int s, int field) { return vec3(pxInfoFloat(s, field), pxInfoFloat(s, field + 1), pxInfoFloat(s, field + 2)); }

struct SurfaceHit {
  float t;
  vec2 uv;
  float height;  // w at the hit, tile widths
  int face;      // ParallaxFace: -1 the relief, 0..4 a wall of the slab
  vec3 rowU, rowV, rowW;  // ParallaxFrame: the frame the hit was traced in
};

SurfaceHit pxNoHit() { return SurfaceHit(CR_INF, vec2(0.0), 0.0, -1, vec3(0.0), vec3(0.0), vec3(0.0)); }

// indirection::bilinearAxis (relief_map.h), without the slope
void pxAxis(float t, int size, bool repeat, out int i0, out int i1, out float f) {
  float x = t * float(size) - 0.5;
  if (repeat) {
    if (isinf(x) || isnan(x)) x = 0.0;
    x -= float(size) * floor(x / float(size));
    if (!(x >= 0.0 && x < float(size))) x = 0.0;  // far from the map, with fma: as bilinearAxis
    const float fl = floor(x);
    i0 = min(int(fl), size - 1);
    i1 = i0 + 1 == size ? 0 : i0 + 1;
    f = x - fl;
    return;
  }
  if (!(x > 0.0)) {
    i0 = i1 = 0;
    f = 0.0;
    return;
  }
  if (x >= float(size - 1)) {
    i0 = i1 = size - 1;
    f = 0.0;
    return;
  }
  const float fl = floor(x);
  i0 = int(fl);
  i1 = i0 + 1;
  f = x - fl;
}

float pxLerp(float a, float b, float t) { return a + (b - a) * t; }

// ReliefMap::heightAt over the surface's float heights.
float pxHeight(int s, vec2 uv) {
  const int w = int(pxInfo(s, CR_PX_HEIGHT_WIDTH)), h = int(pxInfo(s, CR_PX_HEIGHT_HEIGHT));
  const bool repeat = pxInfo(s, CR_PX_REPEAT) != 0u;
  const uint base = pxInfo(s, CR_PX_HEIGHT_OFFSET);
  int x0, x1, y0, y1;
  float fx, fy;
  pxAxis(uv.x, w, repeat, x0, x1, fx);
  pxAxis(uv.y, h, repeat, y0, y1, fy);
  const uint r0 = base + uint(y0 * w), r1 = base + uint(y1 * w);
  const float a = pxLerp(uintBitsToFloat(pxWords[r0 + uint(x0)]), uintBitsToFloat(pxWords[r0 + uint(x1)]), fx);
  const float b = pxLerp(uintBitsToFloat(pxWords[r1 + uint(x0)]), uintBitsToFloat(pxWords[r1 + uint(x1)]), fx);
  return pxLerp(a, b, fy);
}

// ReliefMap::gradientAt
vec2 pxGradient(int s, vec2 uv) {
  const int w = int(pxInfo(s, CR_PX_HEIGHT_WIDTH)), h = int(pxInfo(s, CR_PX_HEIGHT_HEIGHT));
  const bool repeat = pxInfo(s, CR_PX_REPEAT) != 0u;
  const uint base = pxInfo(s, CR_PX_HEIGHT_OFFSET);
  int x0, x1, y0, y1;
  float fx, fy;
  pxAxis(uv.x, w, repeat, x0, x1, fx);
  pxAxis(uv.y, h, repeat, y0, y1, fy);
  // d(fraction)/d(coordinate): the size, 0 where the clamped interpolant is constant
  const float sx = !repeat && x0 == x1 ? 0.0 : float(w), sy = !repeat && y0 == y1 ? 0.0 : float(h);
  const uint r0 = base + uint(y0 * w), r1 = base + uint(y1 * w);
  const float h00 = uintBitsToFloat(pxWords[r0 + uint(x0)]), h10 = uintBitsToFloat(pxWords[r0 + uint(x1)]);
  const float h01 = uintBitsToFloat(pxWords[r1 + uint(x0)]), h11 = uintBitsToFloat(pxWords[r1 + uint(x1)]);
  return vec2((pxLerp(h10, h11, fy) - pxLerp(h00, h01, fy)) * sx, (pxLerp(h01, h11, fx) - pxLerp(h00, h10, fx)) * sy);
}

// detail::bilinear over an RGBA8 map (colours, normals); unpackUnorm4x8 is the CPU's q / 255.
vec3 pxRgba(int s, int offsetField, vec2 uv, bool repeat) {
  const uint base = pxInfo(s, offsetField);
  const int w = int(pxInfo(s, offsetField + 1)), h = int(pxInfo(s, offsetField + 2));
  int x0, x1, y0, y1;
  float fx, fy;
  pxAxis(uv.x, w, repeat, x0, x1, fx);
  pxAxis(uv.y, h, repeat, y0, y1, fy);
  const vec3 c00 = unpackUnorm4x8(pxWords[base + uint(y0 * w + x0)]).rgb;
  const vec3 c10 = unpackUnorm4x8(pxWords[base + uint(y0 * w + x1)]).rgb;
  const vec3 c01 = unpackUnorm4x8(pxWords[base + uint(y1 * w + x0)]).rgb;
  const vec3 c11 = unpackUnorm4x8(pxWords[base + uint(y1 * w + x1)]).rgb;
  vec3 out3;
  for (int c = 0; c < 3; ++c) out3[c] = pxLerp(pxLerp(c00[c], c10[c], fx), pxLerp(c01[c], c11[c], fx), fy);
  return out3;
}

// detail::bilinear over the indirection map (two floats per texel, wrapped as the relief).
vec2 pxIndirection(int s, vec2 uv, bool repeat) {
  const uint base = pxInfo(s, CR_PX_INDIRECTION_OFFSET);
  const int w = int(pxInfo(s, CR_PX_INDIRECTION_OFFSET + 1)), h = int(pxInfo(s, CR_PX_INDIRECTION_OFFSET + 2));
  int x0, x1, y0, y1;
  float fx, fy;
  pxAxis(uv.x, w, repeat, x0, x1, fx);
  pxAxis(uv.y, h, repeat, y0, y1, fy);
  vec2 out2;
  for (int c = 0; c < 2; ++c) {
    const float a = pxLerp(uintBitsToFloat(pxWords[base + uint(2 * (y0 * w + x0) + c)]),
                           uintBitsToFloat(pxWords[base + uint(2 * (y0 * w + x1) + c)]), fx);
    const float b = pxLerp(uintBitsToFloat(pxWords[base + uint(2 * (y1 * w + x0) + c)]),
                           uintBitsToFloat(pxWords[base + uint(2 * (y1 * w + x1) + c)]), fx);
    out2[c] = pxLerp(a, b, fy);
  }
  return out2;
}

// ParallaxTracer::clipToSlab
bool pxClipToSlab(vec3 o, vec3 d, float top, inout float t0, inout float t1, out int entry, out bool floorExit) {
  const vec3 lo = vec3(0.0), hi = vec3(1.0, 1.0, top);
  entry = -1;
  floorExit = false;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (!(o[a] >= lo[a] && o[a] <= hi[a])) return false;
      continue;
    }
    const float inv = 1.0 / d[a];
    float ta = (lo[a] - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
    const bool towardsLow = ta > tb;
    if (towardsLow) {
      const float swap = ta;
      ta = tb;
      tb = swap;
    }
    if (ta > t0) {
      t0 = ta;
      entry = a == 2 ? (towardsLow ? -1 : 4) : 2 * a + (towardsLow ? 1 : 0);
    }
    if (tb < t1) {
      t1 = tb;
      floorExit = a == 2 && towardsLow;
    } else if (tb == t1 && a == 2 && towardsLow) {
      floorExit = true;
    }
  }
  return t0 <= t1;
}

float pxGap(int s, vec3 o, vec3 d, float t, inout uint samples) {
  ++samples;
  const vec3 p = o + t * d;
  return p.z - pxHeight(s, p.xy);
}

// ParallaxTracer::marchSlab: the local ray o + t d over [t0, t1].
SurfaceHit pxMarchSlab(int s, vec3 o, vec3 d, float t0, float t1, int entry, bool floorExit, bool anyHit,
                       inout uint samples) {
  SurfaceHit hit = pxNoHit();
  float gapA = pxGap(s, o, d, t0, samples);
  if (gapA <= 0.0) {
    hit.t = t0;
    hit.face = entry;
    hit.uv = vec2(o.x + t0 * d.x, o.y + t0 * d.y);
    hit.height = o.z + t0 * d.z;
    return hit;
  }
  const float span = t1 - t0;
  const float texels = max(abs(span * d.x) * float(pxInfo(s, CR_PX_HEIGHT_WIDTH)),
                           abs(span * d.y) * float(pxInfo(s, CR_PX_HEIGHT_HEIGHT)));
  const int steps = int(clamp(ceil(texels * CR_PX_STEPS_PER_TEXEL), float(CR_PX_MIN_LINEAR_STEPS), float(CR_PX_MAX_LINEAR_STEPS)));
  float a = t0;
  for (int k = 1; k <= steps; ++k) {
    const float b = t0 + span * float(k) / float(steps);
    float gapB = pxGap(s, o, d, b, samples);
    if (k == steps && floorExit) gapB = min(gapB, 0.0);
    if (gapB > 0.0) {
      a = b;
      gapA = gapB;
      continue;
    }
    if (anyHit) {
      hit.t = b;
      return hit;
    }
    float lo = a, hi = b, gapHi = gapB;
    for (int i = 0; i < CR_PX_REFINE_STEPS; ++i) {
      const float m = 0.5 * (lo + hi);
      const float gm = pxGap(s, o, d, m, samples);
      if (gm > 0.0) {
        lo = m;
        gapA = gm;
      } else {
        hi = m;
        gapHi = gm;
      }
    }
    hit.t = lo + (hi - lo) * (gapA / (gapA - gapHi));
    hit.uv = vec2(o.x + hit.t * d.x, o.y + hit.t * d.y);
    hit.height = o.z + hit.t * d.z;
    return hit;
  }
  return hit;
}

// ParallaxTracer::march over [tmin, tmax] of a square: intersect, or with anyHit occluded.
SurfaceHit pxTraceSquare(int s, vec3 ro, vec3 rd, float tmin, float tmax, bool anyHit, inout uint samples) {
  const vec3 r = ro - pxInfoVec3(s, CR_PX_ORIGIN);
  const vec3 rowU = pxInfoVec3(s, CR_PX_ROW_U), rowV = pxInfoVec3(s, CR_PX_ROW_V), rowW = pxInfoVec3(s, CR_PX_ROW_W);
  const vec3 o = vec3(dot(r, rowU), dot(r, rowV), dot(r, rowW));
  const vec3 d = vec3(dot(rd, rowU), dot(rd, rowV), dot(rd, rowW));
  float t0 = tmin, t1 = tmax;
  int entry;
  bool floorExit;
  if (!pxClipToSlab(o, d, pxInfoFloat(s, CR_PX_TOP), t0, t1, entry, floorExit)) return pxNoHit();
  SurfaceHit hit = pxMarchSlab(s, o, d, t0, t1, entry, floorExit, anyHit, samples);
  hit.rowU = rowU;
  hit.rowV = rowV;
  hit.rowW = rowW;
  return hit;
}

bool pxOnMesh(int s) { return pxInfo(s, CR_PX_MESH_NODE_OFFSET) != 0u; }
float pxWord(uint at) { return uintBitsToFloat(pxWords[at]); }
vec3 pxVec3(uint at) { return vec3(pxWord(at), pxWord(at + 1u), pxWord(at + 2u)); }
uint pxTriangleAt(int s, int slot) { return pxInfo(s, CR_PX_MESH_TRIANGLE_OFFSET) + uint(slot) * uint(CR_PX_TRIANGLE_WORDS); }

// TriangleBvh::closestHit (or anyHit) over the base mesh's front faces (Faces::Front), t in [0, tmax).
MeshHit pxTraceMeshFaces(int s, vec3 o, vec3 d, float tmax, bool anyHit) {
  MeshHit best = MeshHit(tmax, 0.0, 0.0, -1, vec3(0.0));
  const uint nodeBase = pxInfo(s, CR_PX_MESH_NODE_OFFSET);
  const vec3 inv = 1.0 / d;
  uint stack[64];
  int top = 0;
  stack[top++] = 0u;
  while (top > 0) {
    const uint node = stack[--top];
    const uint at = nodeBase + node * uint(CR_PX_NODE_WORDS);
    if (!boxReached(o, d, inv, pxVec3(at), pxVec3(at + 3u), best.t)) continue;
    const uint first = pxWords[at + 6u], count = pxWords[at + 7u];
    if (count == 0u) {
      if (top < 62) {
        stack[top++] = first;
        stack[top++] = node + 1u;
      }
      continue;
    }
    for (uint i = first; i < first + count; ++i) {
      const uint t = pxTriangleAt(s, int(i));
      const vec3 v0 = pxVec3(t), e1 = pxVec3(t + 3u), e2 = pxVec3(t + 6u);
      if (dot(d, cross(e1, e2)) >= 0.0) continue;  // a back face
      if (pcIntersectTriangle(o, d, v0, v0 + e1, v0 + e2, best, int(i)) && anyHit) return best;
    }
  }
  return best;
}

// ParallaxTracer::frameAt: the frame at barycentrics (b1, b2) of the triangle in leaf slot `slot`.
bool pxFrameAt(int s, int slot, float b1, float b2, out vec2 uv, out vec3 rowU, out vec3 rowV, out vec3 rowW) {
  const uint c0 = pxTriangleAt(s, slot) + 9u, c1 = c0 + uint(CR_PX_CORNER_WORDS), c2 = c1 + uint(CR_PX_CORNER_WORDS);
  const float b0 = 1.0 - b1 - b2;
  uv = b0 * vec2(pxWord(c0), pxWord(c0 + 1u)) + b1 * vec2(pxWord(c1), pxWord(c1 + 1u)) + b2 * vec2(pxWord(c2), pxWord(c2 + 1u));
  rowU = rowV = rowW = vec3(0.0);
  const vec3 summed = b0 * pxVec3(c0 + 2u) + b1 * pxVec3(c1 + 2u) + b2 * pxVec3(c2 + 2u);
  const float len = length(summed);
  if (!(len > 0.0)) return false;
  const vec3 n = summed / len;
  vec3 tu = b0 * pxVec3(c0 + 5u) + b1 * pxVec3(c1 + 5u) + b2 * pxVec3(c2 + 5u);
  vec3 tv = b0 * pxVec3(c0 + 8u) + b1 * pxVec3(c1 + 8u) + b2 * pxVec3(c2 + 8u);
  tu -= n * dot(n, tu);
  tv -= n * dot(n, tv);
  const float uu = dot(tu, tu), uv2 = dot(tu, tv), vv = dot(tv, tv);
  const float det = uu * vv - uv2 * uv2;
  if (!(det > CR_PX_MIN_FRAME_SPAN * uu * vv) || isinf(det)) return false;
  const float side = sqrt(sqrt(det));
  rowU = (vv * tu - uv2 * tv) / det;
  rowV = (uu * tv - uv2 * tu) / det;
  rowW = n / side;
  return true;
}

// ParallaxTracer::marchMesh: the nearest front face, then the march below it in its frame.
SurfaceHit pxTraceMesh(int s, vec3 ro, vec3 rd, float tmax, inout uint samples) {
  const MeshHit base = pxTraceMeshFaces(s, ro, rd, tmax, false);
  if (base.triangle < 0) return pxNoHit();
  vec2 uv;
  vec3 rowU, rowV, rowW;
  const bool framed = pxFrameAt(s, base.triangle, base.u, base.v, uv, rowU, rowV, rowW);
  const float top = pxInfoFloat(s, CR_PX_TOP);
  const vec3 d = vec3(dot(rd, rowU), dot(rd, rowV), dot(rd, rowW));
  if (!framed || !(d.z < 0.0)) {
    return SurfaceHit(base.t, uv, top, -1, rowU, rowV, framed ? rowW : normalize(base.ng));
  }
  SurfaceHit hit = pxMarchSlab(s, vec3(uv, top), d, 0.0, -top / d.z, -1, true, false, samples);
  hit.t += base.t;
  hit.rowU = rowU;
  hit.rowV = rowV;
  hit.rowW = rowW;
  if (!(hit.t <= tmax)) return pxNoHit();
  return hit;
}

SurfaceHit pxTrace(int s, vec3 ro, vec3 rd, float tmax, bool anyHit, inout uint samples) {
  if (!pxOnMesh(s)) return pxTraceSquare(s, ro, rd, 0.0, tmax, anyHit, samples);
  if (!anyHit) return pxTraceMesh(s, ro, rd, tmax, samples);
  SurfaceHit hit = pxNoHit();
  const MeshHit base = pxTraceMeshFaces(s, ro, rd, tmax, true);
  if (base.triangle >= 0) hit.t = base.t;
  return hit;
}

// ParallaxTracer::selfShadowed
bool pxSelfShadowed(int s, SurfaceHit h, vec3 normal, vec3 towards, float offset) {
  if (!pxOnMesh(s) || h.face != -1) return false;
  const vec3 lift = offset * normal;
  const vec3 start = vec3(h.uv, h.height) + vec3(dot(lift, h.rowU), dot(lift, h.rowV), dot(lift, h.rowW));
  const vec3 d = vec3(dot(towards, h.rowU), dot(towards, h.rowV), dot(towards, h.rowW));
  if (!(d.z > 0.0)) return true;
  const float top = pxInfoFloat(s, CR_PX_TOP);
  if (start.z >= top) return false;
  uint samples = 0u;
  return !isinf(pxMarchSlab(s, start, d, 0.0, (top - start.z) / d.z, -1, false, true, samples).t);
}

// The nearest surface hit before tmax (CpuBackend::intersect, after the charts).
int pxTraceSurfaces(vec3 o, vec3 d, float tmax, out SurfaceHit best, inout uint samples) {
  best = pxNoHit();
  best.t = tmax;
  int found = -1;
  for (int s = 0; s < pxSurfaceCount(); ++s) {
    const SurfaceHit h = pxTrace(s, o, d, best.t, false, samples);
    if (!isinf(h.t) && h.t < best.t) {
      best = h;
      found = s;
    }
  }
  return found;
}

bool pxOccluded(vec3 o, vec3 d) {
  uint samples = 0u;
  for (int s = 0; s < pxSurfaceCount(); ++s)
    if (!isinf(pxTrace(s, o, d, CR_INF, true, samples).t)) return true;
  return false;
}

float pxSurfaceOffset(int s) { return pxInfoFloat(s, CR_PX_SURFACE_OFFSET); }

// ParallaxTracer::normalAt and colorAt.
void pxShade(int s, SurfaceHit h, out vec3 normal, out vec3 base) {
  const bool repeat = pxInfo(s, CR_PX_REPEAT) != 0u;
  vec3 n;
  if (h.face == 0) n = vec3(-1.0, 0.0, 0.0);
  else if (h.face == 1) n = vec3(1.0, 0.0, 0.0);
  else if (h.face == 2) n = vec3(0.0, -1.0, 0.0);
  else if (h.face == 3) n = vec3(0.0, 1.0, 0.0);
  else if (h.face == 4) n = vec3(0.0, 0.0, -1.0);
  else if (pxInfo(s, CR_PX_NORMAL_OFFSET) != 0u) {
    const vec3 m = pxRgba(s, CR_PX_NORMAL_OFFSET, h.uv, repeat) * 2.0 - 1.0;
    const float len = length(m);
    n = len > 1e-6 ? m / len : vec3(0.0, 0.0, 1.0);
  } else {
    const vec2 g = pxGradient(s, h.uv);
    n = normalize(vec3(-g.x, -g.y, 1.0));
  }
  // ParallaxFrame::worldNormal
  const vec3 w = n.x * h.rowU + n.y * h.rowV + n.z * h.rowW;
  const float wl = length(w);
  normal = wl > 0.0 ? w / wl : normalize(h.rowW);
  vec2 st = h.uv;
  if (pxInfo(s, CR_PX_INDIRECTION_OFFSET) != 0u) st += pxIndirection(s, h.uv, repeat);
  if (pxInfo(s, CR_PX_COLOR_OFFSET) != 0u) {
    base = pxRgba(s, CR_PX_COLOR_OFFSET, st, repeat);
  } else {
    const float squares = float(pxInfo(s, CR_PX_CHECKER_SQUARES));
    const int parity = int(floor(st.x * squares)) + int(floor(st.y * squares));
    base = (parity & 1) != 0 ? CR_PX_CHECKER_LIGHT : CR_PX_CHECKER_DARK;
  }
}

// ---- the scene ---------------------------------------------------------------------------------

// The nearest hit over the scene's models (CpuBackend::intersect); leaves that model selected.
// best.steps: over every model's search, hit or miss.
Hit traceScene(vec3 o, vec3 d, out int hitModel) {
  Hit best = noHit();
  hitModel = -1;
  uint steps = 0u;
  for (int m = 0; m < P.size.z; ++m) {
    selectModel(m);
    const Hit h = traceModel(o, d, 0.0, best.cell >= 0 ? best.t : CR_INF);
    steps += h.steps;
    if (h.cell >= 0 && (best.cell < 0 || h.t < best.t)) {
      best = h;
      hitModel = m;
    }
  }
  if (hitModel >= 0) selectModel(hitModel);
  best.steps = steps;
  return best;
}

// The relief surface hit being shaded, for its self-shadowing (CpuBackend::shade); -1: none.
int gSelfSurface;
SurfaceHit gSelfHit;

bool occludedScene(vec3 o, vec3 d) {
  if (CR_POLYCUBE && pcOccluded(o, d)) return true;
  if (CR_GEOTEX && gtOccluded(o, d)) return true;
  if (CR_PARALLAX && pxOccluded(o, d)) return true;
  for (int m = 0; m < P.size.z; ++m) {
    selectModel(m);
    if (traceModel(o, d, 0.0, CR_INF).cell >= 0) return true;
  }
  return false;
}


// ---- shading (ReliefTracer::shade, CpuBackend::shade) ------------------------------------------

// DistanceCodec::hasSurface: neither empty nor before the face.
bool hasSurface(uint code) { return code != gEmptyCode && float(code) >= gZeroCode; }

float sampleDistance(int layer, int a, int b, out bool filled) {
  const uint code = sampleCode(tileOrigin(layer), a, b);
  filled = hasSurface(code);
  return (float(code) - gZeroCode) / (float(gEmptyCode - 1u) - gZeroCode) * gDistanceMax;
}

// The unprojected sample (x, y) of the current cell's face, false where out of range or empty.
bool samplePoint(int face, int layer, int x, int y, out vec3 point) {
  if (x < 0 || y < 0 || x >= gTexels || y >= gTexels) return false;
  bool filled;
  const float d = sampleDistance(layer, x, y, filled);
  if (!filled) return false;
  point = unproject(face, vec2(float(x), float(y)) / float(gTexels - 1), d);
  return true;
}

bool sampleDerivative(int face, int layer, int a, int b, int dx, int dy, bool haveCentre, vec3 centre,
                      out vec3 derivative) {
  vec3 plus, minus;
  const bool hasPlus = samplePoint(face, layer, a + dx, b + dy, plus);
  const bool hasMinus = samplePoint(face, layer, a - dx, b - dy, minus);
  if (hasPlus && hasMinus) {
    derivative = plus - minus;
    return true;
  }
  if (hasPlus && haveCentre) {
    derivative = plus - centre;
    return true;
  }
  if (hasMinus && haveCentre) {
    derivative = centre - minus;
    return true;
  }
  return false;
}

// Shading normal and color of a hit (the hit's cell and model are selected).
void shadeHit(Hit hit, vec3 direction, out vec3 normal, out vec3 color) {
  normal = vec3(0.0);
  color = vec3(200.0 / 255.0);
  const int layer = layerOf(hit.face);
  if (layer >= 0) {
    const ivec3 tile = tileOrigin(layer);
    const vec2 texel = hit.uv * float(gTexels - 1);
    int a = clamp(int(floor(texel.x + 0.5)), 0, gTexels - 1);
    int b = clamp(int(floor(texel.y + 0.5)), 0, gTexels - 1);
    if (!hasSurface(sampleCode(tile, a, b))) {
      int best = 0x7fffffff, bestA = a, bestB = b;
      const int radius = CR_SHADE_SEARCH_RADIUS;
      for (int y = max(0, b - radius); y <= min(gTexels - 1, b + radius); ++y)
        for (int x = max(0, a - radius); x <= min(gTexels - 1, a + radius); ++x) {
          const int d2 = (x - a) * (x - a) + (y - b) * (y - b);
          if (d2 < best && hasSurface(sampleCode(tile, x, y))) {
            best = d2;
            bestA = x;
            bestB = y;
          }
        }
      a = bestA;
      b = bestB;
    }
    const ivec3 at = ivec3(tile.x + a, tile.y + b, tile.z);
    const int normalFormat = gNormalFormat;
    if (normalFormat == CR_NORMALS_NONE) {
      vec3 centre;
      const bool haveCentre = samplePoint(hit.face, layer, a, b, centre);
      vec3 du, dv;
      vec3 n = vec3(0.0);
      if (sampleDerivative(hit.face, layer, a, b, 1, 0, haveCentre, centre, du) &&
          sampleDerivative(hit.face, layer, a, b, 0, 1, haveCentre, centre, dv))
        n = cross(du, dv);
      if (!facePositive(hit.face)) n = -n;
      if (gInterior && !gCentreInside) n = -n;
      normal = length(n) > 0.0 ? normalize(n) : vec3(0.0);
    }
    if (CR_OCT_NORMALS && normalFormat == CR_NORMALS_OCT) {
      // octahedralDecode of relief_model.h
      vec2 e = vec2(texelFetch(octNormalAtlas, at, 0).rg) / 65535.0;
      e = e * 2.0 - 1.0;
      vec3 n = vec3(e.x, e.y, 1.0 - abs(e.x) - abs(e.y));
      const float t = max(-n.z, 0.0);
      n.x += n.x >= 0.0 ? -t : t;
      n.y += n.y >= 0.0 ? -t : t;
      normal = normalize(n);
    }
    if (CR_RGBA_NORMALS && normalFormat == CR_NORMALS_RGBA)
      normal = normalize(vec3(texelFetch(rgbaNormalAtlas, at, 0).rgb) / 255.0 * 2.0 - 1.0);
    if (CR_COLORS && gColorFormat == CR_COLORS_RGBA) color = vec3(texelFetch(colorAtlas, at, 0).rgb) / 255.0;
  }
  if (normal == vec3(0.0)) normal = -normalize(direction);
}

vec3 facing(vec3 n, vec3 direction) { return dot(n, direction) > 0.0 ? -n : n; }

float surfaceOffset() { return CR_SURFACE_OFFSET_SAMPLES * gCellSize / float(max(1, gTexels - 1)); }

// Ambient plus Lambert over the lights, each gated by a shadow ray leaving `offset` off the surface.
vec3 shadeLocal(vec3 position, vec3 normal, vec3 base, float offset) {
  vec3 light = P.ambient.rgb;
  for (int i = 0; i < P.size.w; ++i) {
    const vec3 towards = P.lights[i].direction.xyz;
    const float lambert = dot(normal, towards);
    if (lambert <= 0.0) continue;
    if (CR_SHADOWS && P.flags.x != 0) {
      if (CR_PARALLAX && gSelfSurface >= 0 && pxSelfShadowed(gSelfSurface, gSelfHit, normal, towards, offset)) continue;
      const int keep = gModel;
      const bool blocked = occludedScene(position + offset * normal, towards);
      if (keep >= 0) selectModel(keep);  // -1 on a polycube mesh's hit
      if (blocked) continue;
    }
    light += P.lights[i].color.rgb * lambert;
  }
  return base * light;
}

// ---- one pixel -----------------------------------------------------------------------------------

// One pixel per invocation of the compute pass, or (CR_FRAGMENT, the paper's way) per fragment
// of a full-screen pass that the stencil of the rasterized grey cells limits to covered pixels.
void main() {
#if defined(CR_FRAGMENT) && defined(CR_VULKAN)
  // The viewport is flipped (negative height), so the cover draws as in OpenGL; framebuffer rows
  // still count from the top.
  const ivec2 pixel = ivec2(gl_FragCoord.xy);
#elif defined(CR_FRAGMENT)
  const ivec2 pixel = ivec2(int(gl_FragCoord.x), P.size.y - 1 - int(gl_FragCoord.y));
#else
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
#endif
  const int width = P.size.x, height = P.size.y;
  if (pixel.x >= width || pixel.y >= height) return;
  const int index = pixel.y * width + pixel.x;
  gInverseAtlasSize = 1.0 / vec2(textureSize(distanceAtlas, 0).xy);
  gT2InverseSize = 1.0 / vec2(textureSize(polycubeT2, 0).xy);
  gModel = -1;
  gSelfSurface = -1;
  // Camera::primaryRay
  const float sx = (2.0 * (float(pixel.x) + 0.5) / float(width) - 1.0);
  const float sy = (1.0 - 2.0 * (float(pixel.y) + 0.5) / float(height));
  const vec3 eye = P.eye.xyz;
  const vec3 direction = normalize(P.forward.xyz + sx * P.right.xyz + sy * P.up.xyz);
  // One pixel's angle: the cone a mesh hit's texture footprint grows with (CpuBackend::pixelSpread).
  const float spread = 2.0 * length(P.up.xyz) / float(height);
  int model;
  const Hit hit = traceScene(eye, direction, model);
  MeshHit meshHit;
  int mesh = CR_POLYCUBE ? pcTraceMeshes(eye, direction, hit.cell >= 0 ? hit.t : CR_INF, meshHit) : -1;
  ChartHit chartHit;
  uint samples = hit.steps;
  const int charts = CR_GEOTEX ? gtTraceModels(eye, direction, mesh >= 0 ? meshHit.t : (hit.cell >= 0 ? hit.t : CR_INF),
                                               chartHit, samples) : -1;
  if (charts >= 0) mesh = -1;  // nearer than both
  SurfaceHit surfaceHit;
  const int surface = CR_PARALLAX ? pxTraceSurfaces(eye, direction, charts >= 0 ? chartHit.t : (mesh >= 0 ? meshHit.t : (hit.cell >= 0 ? hit.t : CR_INF)),
                                                    surfaceHit, samples) : -1;
  if (surface >= 0) mesh = -1;  // nearer than all
  if (CR_OUT_STEPS) frameWords[P.offsets.w + index] = floatBitsToUint(float(samples));
  if (hit.cell < 0 && mesh < 0 && charts < 0 && surface < 0) {
    if (CR_OUT_COLOR) {
      const uvec4 bg = uvec4(floor(255.0 * clamp(P.background, 0.0, 1.0) + 0.5));
      frameWords[P.flags.z + index] = bg.r | (bg.g << 8) | (bg.b << 16) | (bg.a << 24);
    }
    if (CR_OUT_DEPTH) frameWords[P.flags.w + index] = floatBitsToUint(CR_INF);
    if (CR_OUT_NORMAL)
      for (int c = 0; c < 3; ++c) frameWords[P.offsets.x + 3 * index + c] = 0u;
    if (CR_OUT_MASK) frameWords[P.offsets.y + index] = 0u;
    if (CR_OUT_CELL) frameWords[P.offsets.z + index] = floatBitsToUint(-1.0);
    return;
  }
  vec3 shadingNormal, base;
  float t, offset;
  if (surface >= 0) {
    pxShade(surface, surfaceHit, shadingNormal, base);
    t = surfaceHit.t;
    offset = pxSurfaceOffset(surface);
    gSelfSurface = surface;
    gSelfHit = surfaceHit;
  } else if (charts >= 0) {
    gtShade(charts, chartHit, shadingNormal, base);
    t = chartHit.t;
    offset = gtSurfaceOffset(charts);
  } else if (mesh >= 0) {
    pcShade(mesh, meshHit, direction, spread, shadingNormal, base);
    t = meshHit.t;
    offset = pcSurfaceOffset(mesh);
  } else {
    selectCell(hit.cell);
    shadeHit(hit, direction, shadingNormal, base);
    t = hit.t;
    offset = surfaceOffset();
  }
  const vec3 n = facing(shadingNormal, direction);
  if (CR_OUT_DEPTH) frameWords[P.flags.w + index] = floatBitsToUint(t);
  if (CR_OUT_NORMAL)
    for (int c = 0; c < 3; ++c) frameWords[P.offsets.x + 3 * index + c] = floatBitsToUint(n[c]);
  if (CR_OUT_MASK) frameWords[P.offsets.y + index] = 1u;
  if (CR_OUT_CELL)
    frameWords[P.offsets.z + index] =
        floatBitsToUint(mesh >= 0 || charts >= 0 || surface >= 0 ? -1.0 : float(hit.cell - models[model].cellOffset));
  if (!CR_OUT_COLOR) return;
  // CpuBackend::shade, its recursion unrolled: each bounce's local color weighs (1 - r) r^k.
  vec3 position = eye + t * direction;
  vec3 normalK = n;
  vec3 baseK = base;
  float offsetK = offset;
  vec3 rayDirection = direction;
  vec3 result = vec3(0.0);
  float weight = 1.0;
  for (int bounce = 0;; ++bounce) {
    const vec3 local = shadeLocal(position, normalK, baseK, offsetK);
    if (CR_REFLECTIONS && bounce < P.steps.w) {
      const float r = P.tuning.y;
      result += weight * (1.0 - r) * local;
      weight *= r;
      const vec3 mirrorDirection = reflect(normalize(rayDirection), normalK);
      const vec3 mirrorOrigin = position + offsetK * normalK;
      int next;
      const Hit h = traceScene(mirrorOrigin, mirrorDirection, next);
      MeshHit mh;
      int nextMesh = CR_POLYCUBE ? pcTraceMeshes(mirrorOrigin, mirrorDirection, h.cell >= 0 ? h.t : CR_INF, mh) : -1;
      ChartHit ch;
      uint unused = 0u;
      const int nextCharts = CR_GEOTEX ? gtTraceModels(mirrorOrigin, mirrorDirection,
                                                       nextMesh >= 0 ? mh.t : (h.cell >= 0 ? h.t : CR_INF), ch, unused)
                                       : -1;
      if (nextCharts >= 0) nextMesh = -1;
      SurfaceHit sh;
      const int nextSurface = CR_PARALLAX ? pxTraceSurfaces(mirrorOrigin, mirrorDirection,
                                                            nextCharts >= 0 ? ch.t : (nextMesh >= 0 ? mh.t : (h.cell >= 0 ? h.t : CR_INF)),
                                                            sh, unused) : -1;
      if (nextSurface >= 0) nextMesh = -1;
      if (h.cell < 0 && nextMesh < 0 && nextCharts < 0 && nextSurface < 0) {
        result += weight * P.background.rgb;
        break;
      }
      vec3 nextNormal;
      float nextT;
      gSelfSurface = nextSurface;
      gSelfHit = sh;
      if (nextSurface >= 0) {
        pxShade(nextSurface, sh, nextNormal, baseK);
        nextT = sh.t;
        offsetK = pxSurfaceOffset(nextSurface);
      } else if (nextCharts >= 0) {
        gtShade(nextCharts, ch, nextNormal, baseK);
        nextT = ch.t;
        offsetK = gtSurfaceOffset(nextCharts);
      } else if (nextMesh >= 0) {
        pcShade(nextMesh, mh, mirrorDirection, spread, nextNormal, baseK);
        nextT = mh.t;
        offsetK = pcSurfaceOffset(nextMesh);
      } else {
        selectCell(h.cell);
        shadeHit(h, mirrorDirection, nextNormal, baseK);
        nextT = h.t;
        offsetK = surfaceOffset();
      }
      normalK = facing(nextNormal, mirrorDirection);
      position = mirrorOrigin + nextT * mirrorDirection;
      rayDirection = mirrorDirection;
      continue;
    }
    result += weight * local;
    break;
  }
  const vec3 c = clamp(result, vec3(0.0), vec3(1.0));
  const uvec3 display = uvec3(floor(255.0 * pow(c, vec3(1.0 / 2.2)) + 0.5));
  frameWords[P.flags.z + index] = display.r | (display.g << 8) | (display.b << 16) | (255u << 24);
}
