// SPDX-License-Identifier: MIT
// The raster entry of the paper's way (gpu/gpu_frame.h, RayEntry::Rasterized): every grey cell
// of a relief model, and every chart box of a geometry-texture model (the geometry-textures
// paper's boxes), as a box a little enlarged, drawn into the stencil only, so that the
// traversal's fragment pass runs on exactly the pixels whose rays meet a grey cell or a box. One
// instance per cell or chart, 36 vertices of a unit cube. The cell table and the geometry-texture
// words are the traversal's (bindings 2 and 12); the backend prepends the version and the
// traversal's constants (gpu::cellCoverShader), so the chart record's layout is never typed here.

#ifdef CR_VULKAN
#define CR_VERTEX_ID gl_VertexIndex
#define CR_INSTANCE_ID gl_InstanceIndex
#define CR_BIND(n) set = 0, binding = n
#else
#define CR_VERTEX_ID gl_VertexID
#define CR_INSTANCE_ID gl_InstanceID
#define CR_BIND(n) binding = n
#endif

struct CellRecord {
  uint packedIjk;
  uint info;
  uint firstLayer;
  float point[3];
  uint reach[2];  // relief::CellReach (gpu::GpuCell)
};
layout(std430, CR_BIND(2)) readonly buffer Cells { CellRecord cells[]; };
layout(std430, CR_BIND(12)) readonly buffer GeoTexWords { uint gtWords[]; };

// gpu::CoverParams: a uniform block in OpenGL, push constants in Vulkan (one per draw).
#ifdef CR_VULKAN
layout(std430, push_constant) uniform Cover {
#else
layout(std140, binding = 10) uniform Cover {
#endif
  mat4 viewProjection;
  vec4 originAndCellSize;  // cells: the model's grid origin and cell size (world units)
  vec4 dilation;           // cells: x, in cell units; chart boxes: y in world units plus z times the box
  ivec4 cellOffset;        // x: the model's first cell in the table, or the geometry-texture model;
                           // y: 0 cells, 1 chart boxes
} C;

// The 12 triangles of the unit cube, as corner indices (bit 0: x, bit 1: y, bit 2: z).
const int kCorners[36] = int[36](0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3);

vec3 cellCorner(vec3 unit) {
  const uint ijk = cells[C.cellOffset.x + CR_INSTANCE_ID].packedIjk;
  const vec3 cell = vec3(float(ijk & 1023u), float((ijk >> 10) & 1023u), float((ijk >> 20) & 1023u));
  const vec3 local = cell + unit * (1.0 + 2.0 * C.dilation.x) - C.dilation.x;
  return C.originAndCellSize.xyz + local * C.originAndCellSize.w;
}

vec3 gtVec3(uint at) { return vec3(uintBitsToFloat(gtWords[at]), uintBitsToFloat(gtWords[at + 1u]), uintBitsToFloat(gtWords[at + 2u])); }

// A chart's box (gpu/geotex_layout.h): chart = rows * (world - origin), the rows orthogonal (x
// and y scaled to texels), so world = origin + sum of chart[a] * row[a] / |row[a]|^2.
vec3 chartBoxCorner(vec3 unit) {
  const uint model = uint(C.cellOffset.x);
  const uint at = gtWords[1u + model * uint(CR_GT_MODEL_INFO_WORDS) + uint(CR_GT_CHART_OFFSET)] +
                  uint(CR_INSTANCE_ID) * uint(CR_GT_CHART_WORDS);
  const vec3 rows[3] = vec3[3](gtVec3(at + uint(CR_GT_ROW_X)), gtVec3(at + uint(CR_GT_ROW_Y)), gtVec3(at + uint(CR_GT_ROW_Z)));
  const vec3 size = gtVec3(at + uint(CR_GT_BOX_SIZE));
  vec3 world = gtVec3(at + uint(CR_GT_ORIGIN));
  for (int a = 0; a < 3; ++a) {
    const float scale = dot(rows[a], rows[a]);
    const float enlarge = C.dilation.y * sqrt(scale) + C.dilation.z * size[a];
    world += (unit[a] * (size[a] + 2.0 * enlarge) - enlarge) / scale * rows[a];
  }
  return world;
}

void main() {
  const int corner = kCorners[CR_VERTEX_ID];
  const vec3 unit = vec3(float(corner & 1), float((corner >> 1) & 1), float((corner >> 2) & 1));
  const vec3 world = C.cellOffset.y == 0 ? cellCorner(unit) : chartBoxCorner(unit);
  gl_Position = C.viewProjection * vec4(world, 1.0);
}
