// SPDX-License-Identifier: MIT
/// @file scene.h
/// What a backend renders: relief models, geometry textures, polycube-mapped meshes and
/// height-mapped squares (parallax occlusion mapping with an indirection map) placed in world space, and the lights that shade them. The scene holds them by shared pointer so that one
/// converted model can be uploaded to several backends (the backend-switching tests render the
/// same scene on each) without copies.
#pragma once

#include <memory>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/geotex/geotex_model.h"
#include "cellrelief/indirection/relief_surface.h"
#include "cellrelief/polycube/textured_mesh.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::render {

/// A light at infinity: `direction` points from the surface towards the light.
struct DirectionalLight {
  Vec3f direction{0.4f, 0.8f, 0.45f};
  Vec3f color{1.0f};
  float intensity = 0.85f;
};

struct Scene {
  std::vector<std::shared_ptr<const relief::ReliefModel>> models;
  std::vector<std::shared_ptr<const polycube::TexturedMesh>> polycubeMeshes;
  std::vector<std::shared_ptr<const geotex::GeoTexModel>> geotexModels;
  std::vector<std::shared_ptr<const indirection::ReliefSurface>> reliefSurfaces;
  std::vector<DirectionalLight> lights = std::vector<DirectionalLight>(1);  ///< one default light
  Vec3f ambient{0.18f};
  Vec4f background{1.0f, 1.0f, 1.0f, 0.0f};  ///< RGBA of pixels that hit nothing

  /// A scene of one model with the default light.
  static Scene of(std::shared_ptr<const relief::ReliefModel> model) {
    Scene scene;
    scene.models.push_back(std::move(model));
    return scene;
  }

  /// The union of the models' grids, the meshes' bounds, the charts' boxes and the relief
  /// surfaces' slabs (world space).
  Aabbd boundsWS() const {
    Aabbd box;
    for (const auto& m : models) {
      box.extend(m->originWS);
      box.extend(m->originWS + Vec3d(m->cellSizeWS * m->gridSize));
    }
    for (const auto& m : polycubeMeshes) {
      const Aabbf b = m->mesh.surfaceBounds();
      box.extend(Vec3d(b.min));
      box.extend(Vec3d(b.max));
    }
    for (const auto& m : geotexModels) box.extend(m->boundsWS());
    for (const auto& s : reliefSurfaces) box.extend(s->boundsWS());
    return box;
  }
};

}  // namespace cellrelief::render
