// SPDX-License-Identifier: MIT
/// @file camera.h
/// A pinhole camera set up with look-at, producing one primary ray per pixel centre.
#pragma once

#include <cmath>

#include "cellrelief/core/ray.h"

namespace cellrelief::render {

struct Camera {
  Vec3d eye{0, 0, 3};
  Vec3d target{0};
  Vec3d up{0, 1, 0};
  double verticalFovDegrees = 40;

  /// A camera looking at a sphere (centre, radius) from direction (yaw, pitch), framing it.
  static Camera framing(const Vec3d& centre, double radius, double yawDegrees = 35,
                        double pitchDegrees = 20, double fovDegrees = 40) {
    const double yaw = yawDegrees * M_PI / 180, pitch = pitchDegrees * M_PI / 180;
    const Vec3d dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    const double distance = radius / std::sin(0.5 * fovDegrees * M_PI / 180) * 1.05;
    return {centre + distance * dir, centre, Vec3d(0, 1, 0), fovDegrees};
  }

  /// The orthonormal view frame and the half-height of the image plane at distance 1: what
  /// primaryRay builds its rays from, and what a GPU backend uploads once per frame.
  struct Basis {
    Vec3d forward, right, up;
    double tanHalf = 0;
  };
  Basis basis() const {
    const Vec3d forward = glm::normalize(target - eye);
    // Looking along `up` leaves the roll undefined: take another axis rather than NaN rays.
    Vec3d side = glm::cross(forward, up);
    if (glm::length(side) < 1e-9 * glm::length(up)) side = glm::cross(forward, Vec3d(0, 0, 1));
    if (glm::length(side) < 1e-9) side = glm::cross(forward, Vec3d(1, 0, 0));
    const Vec3d right = glm::normalize(side);
    return {forward, right, glm::cross(right, forward), std::tan(0.5 * verticalFovDegrees * M_PI / 180)};
  }

  /// The frame of primaryRay in float, as a GPU backend uploads it and its shader makes the rays
  /// (the image plane's axes scaled by the half-extents). The CPU backend makes its rays with it
  /// too: rays made in double differ from the shader's in the last bits, and a ray that grazes a
  /// surface or a node boundary then takes another step or even another side of it.
  struct FloatFrame {
    Vec3f eye{0}, forward{0}, right{0}, up{0};
    int width = 1, height = 1;
    /// The ray through the centre of pixel (x, y), in the shader's arithmetic.
    Rayf ray(int x, int y) const {
      const float sx = 2.0f * (float(x) + 0.5f) / float(width) - 1.0f;
      const float sy = 1.0f - 2.0f * (float(y) + 0.5f) / float(height);
      return Rayf(eye, glm::normalize(forward + sx * right + sy * up));
    }
  };
  FloatFrame floatFrame(int width, int height) const {
    const Basis b = basis();
    const double aspect = double(width) / double(height);
    return {Vec3f(eye), Vec3f(b.forward), Vec3f(b.right * (b.tanHalf * aspect)), Vec3f(b.up * b.tanHalf), width,
            height};
  }

  /// The ray through the centre of pixel (x, y) of a width x height image (y down).
  Rayd primaryRay(int x, int y, int width, int height) const {
    const Basis b = basis();
    const double aspect = double(width) / double(height);
    const double sx = (2.0 * (x + 0.5) / width - 1.0) * b.tanHalf * aspect;
    const double sy = (1.0 - 2.0 * (y + 0.5) / height) * b.tanHalf;
    return Rayd(eye, glm::normalize(b.forward + sx * b.right + sy * b.up));
  }
};

}  // namespace cellrelief::render
