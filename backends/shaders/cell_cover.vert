// SPDX-License-Identifier: MIT
// The raster entry of the paper's way (gpu/gpu_frame.h, RayEntry::Rasterized): every
// grey cell as a box, a little enlarged, drawn into the stencil only, so that the traversal's
// fragment pass runs on exactly the pixels whose rays meet a grey cell. One instance per cell,
// 36 vertices of a unit cube; the cell table is the traversal's (binding 2).
#version 450

#ifdef CR_VULKAN
#define CR_VERTEX_ID gl_VertexIndex
#define CR_INSTANCE_ID gl_InstanceIndex
#define CR_CELLS_BINDING set = 0, binding = 2
#else
#define CR_VERTEX_ID gl_VertexID
#define CR_INSTANCE_ID gl_InstanceID
#define CR_CELLS_BINDING binding = 2
#endif

struct CellRecord {
  uint packedIjk;
  uint info;
  uint firstLayer;
  float point[3];
};
layout(std430, CR_CELLS_BINDING) readonly buffer Cells { CellRecord cells[]; };

// gpu::CoverParams: a uniform block in OpenGL, push constants in Vulkan (one per model's draw).
#ifdef CR_VULKAN
layout(std430, push_constant) uniform Cover {
#else
layout(std140, binding = 10) uniform Cover {
#endif
  mat4 viewProjection;
  vec4 originAndCellSize;  // the model's grid origin and cell size (world units)
  vec4 dilation;           // x: how far each box is enlarged, in cell units
  ivec4 cellOffset;        // x: the model's first cell in the table
} C;

// The 12 triangles of the unit cube, as corner indices (bit 0: x, bit 1: y, bit 2: z).
const int kCorners[36] = int[36](0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3);

void main() {
  const uint ijk = cells[C.cellOffset.x + CR_INSTANCE_ID].packedIjk;
  const vec3 cell = vec3(float(ijk & 1023u), float((ijk >> 10) & 1023u), float((ijk >> 20) & 1023u));
  const int corner = kCorners[CR_VERTEX_ID];
  const vec3 unit = vec3(float(corner & 1), float((corner >> 1) & 1), float((corner >> 2) & 1));
  const vec3 local = cell + unit * (1.0 + 2.0 * C.dilation.x) - C.dilation.x;
  gl_Position = C.viewProjection * vec4(C.originAndCellSize.xyz + local * C.originAndCellSize.w, 1.0);
}
