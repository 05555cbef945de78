// SPDX-License-Identifier: MIT
// The fragment pass of the rasterized entry: one triangle over the whole frame (the stencil of
// the grey cells limits it to the covered pixels).
#version 450
#ifdef CR_VULKAN
#define CR_VERTEX_ID gl_VertexIndex
#else
#define CR_VERTEX_ID gl_VertexID
#endif
void main() {
  const vec2 p = vec2(float((CR_VERTEX_ID << 1) & 2), float(CR_VERTEX_ID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
