// SPDX-License-Identifier: MIT
/// @file preview.cpp
/// The preview rasterizer: orthographic three-quarter view fitted to the bounding sphere,
/// half-space triangle rasterization with a depth buffer, parallel over image rows.
#include "preview.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <cellrelief/core/parallel.h>
#include <cellrelief/io/image_io.h>

namespace cellrelief::app {

void writePreview(const TriangleMesh& mesh, const std::filesystem::path& path,
                  const PreviewOptions& o) {
  const Aabbf box = mesh.bounds();
  const Vec3f centre = box.center();
  const float radius = std::max(1e-20f, 0.5f * box.diagonal());
  const float yaw = glm::radians(o.yawDegrees), pitch = glm::radians(o.pitchDegrees);
  // Camera basis: looking at the centre from yaw/pitch, y up.
  const Vec3f forward = -Vec3f(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                               std::cos(pitch) * std::cos(yaw));
  const Vec3f right = glm::normalize(glm::cross(forward, Vec3f(0, 1, 0)));
  const Vec3f up = glm::cross(right, forward);
  const float scale = 0.5f * float(std::min(o.width, o.height)) / (radius * 1.05f);
  std::vector<Vec3f> screen(mesh.positions.size());
  for (std::size_t i = 0; i < screen.size(); ++i) {
    const Vec3f d = mesh.positions[i] - centre;
    screen[i] = Vec3f(0.5f * o.width + scale * glm::dot(d, right),
                      0.5f * o.height - scale * glm::dot(d, up), glm::dot(d, forward));
  }
  const Vec3f light = glm::normalize(-forward + 0.6f * up + 0.3f * right);
  std::vector<float> depth(std::size_t(o.width) * o.height, std::numeric_limits<float>::infinity());
  Image<std::uint8_t> image(o.width, o.height, 3);
  for (int y = 0; y < o.height; ++y)  // background gradient
    for (int x = 0; x < o.width; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = std::uint8_t(235 - 40 * y / o.height);

  // Rows are independent: each task rasterizes every triangle clipped to its band of rows.
  const int band = 16;
  parallelFor(0, std::size_t((o.height + band - 1) / band), [&](std::size_t b) {
    const int yBegin = int(b) * band, yEnd = std::min(o.height, yBegin + band);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const Vec3u& t = mesh.triangles[f];
      const Vec3f &a = screen[t[0]], &bb = screen[t[1]], &c = screen[t[2]];
      const float minY = std::min({a.y, bb.y, c.y}), maxY = std::max({a.y, bb.y, c.y});
      if (maxY < float(yBegin) || minY > float(yEnd)) continue;
      const float area = (bb.x - a.x) * (c.y - a.y) - (bb.y - a.y) * (c.x - a.x);
      if (area == 0) continue;
      const Vec3f n = glm::normalize(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                                                mesh.positions[t[2]] - mesh.positions[t[0]]));
      float shade = std::abs(glm::dot(n, light));  // two-sided: open meshes look right
      shade = 0.25f + 0.75f * shade;
      const int x0 = std::max(0, int(std::floor(std::min({a.x, bb.x, c.x}))));
      const int x1 = std::min(o.width - 1, int(std::ceil(std::max({a.x, bb.x, c.x}))));
      const int y0 = std::max(yBegin, int(std::floor(minY)));
      const int y1 = std::min(yEnd - 1, int(std::ceil(maxY)));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const float px = float(x) + 0.5f, py = float(y) + 0.5f;
          const float w0 = ((bb.x - px) * (c.y - py) - (bb.y - py) * (c.x - px)) / area;
          const float w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
          const float w2 = 1.0f - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const float z = w0 * a.z + w1 * bb.z + w2 * c.z;
          float& zbuf = depth[std::size_t(y) * o.width + x];
          if (z >= zbuf) continue;
          zbuf = z;
          Vec3f colour(0.80f, 0.78f, 0.74f);
          if (mesh.hasColors())
            colour = (w0 * Vec3f(mesh.colors[t[0]]) + w1 * Vec3f(mesh.colors[t[1]]) +
                      w2 * Vec3f(mesh.colors[t[2]])) / 255.0f;
          for (int ch = 0; ch < 3; ++ch)
            image.at(x, y, ch) = std::uint8_t(std::clamp(colour[ch] * shade, 0.0f, 1.0f) * 255.0f);
        }
    }
  }, 1);
  io::writePng(image, path);
}

}  // namespace cellrelief::app
