// SPDX-License-Identifier: MIT
/// @file mesh_rasterizer.h
/// The full triangle mesh drawn the conventional way by OpenGL: the peer the paper of geometry
/// textures measures ray casting against (its Fig. 7, frame time as the image grows). Vertex
/// positions and normals in buffers, a depth-tested RGBA8 frame, Lambert under the scene's default
/// light. Its projection is the rasterized entry's (gpu::cameraProjection): pixel centres where
/// Camera::primaryRay puts them, so its pixels line up with the ray casters' (the test compares the masks). Its own EGL context, beside any backend's.
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "cellrelief/core/image.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/gl/egl_context.h"
#include "cellrelief/gpu/gpu_frame.h"
#include "cellrelief/render/camera.h"
#include "cellrelief/render/scene.h"

namespace cellrelief::gl {

class MeshRasterizer {
 public:
  /// Uploads `mesh` (its normals, or area-weighted vertex normals where it has none). Throws
  /// Unsupported when no OpenGL 4.5 context comes up, InvalidArgument for a mesh without triangles.
  explicit MeshRasterizer(const TriangleMesh& mesh) : mContext(std::make_unique<EglContext>()) {
    if (mesh.triangles.empty()) throw Error(ErrorKind::InvalidArgument, "mesh rasterizer: the mesh has no triangles");
    mContext->makeCurrent();
    mBounds = Aabbd(Vec3d(mesh.surfaceBounds().min), Vec3d(mesh.surfaceBounds().max));
    mIndexCount = GLsizei(3 * mesh.triangles.size());
    const std::vector<Vec3f> normals = mesh.normals.size() == mesh.positions.size() ? mesh.normals
                                                                                     : computeVertexNormals(mesh);
    glCreateVertexArrays(1, &mVertexArray);
    glCreateBuffers(3, mBuffers);
    glNamedBufferStorage(mBuffers[0], GLsizeiptr(mesh.positions.size() * sizeof(Vec3f)), mesh.positions.data(), 0);
    glNamedBufferStorage(mBuffers[1], GLsizeiptr(normals.size() * sizeof(Vec3f)), normals.data(), 0);
    glNamedBufferStorage(mBuffers[2], GLsizeiptr(mesh.triangles.size() * sizeof(mesh.triangles[0])),
                         mesh.triangles.data(), 0);
    for (GLuint attribute = 0; attribute < 2; ++attribute) {
      glVertexArrayVertexBuffer(mVertexArray, attribute, mBuffers[attribute], 0, sizeof(Vec3f));
      glVertexArrayAttribFormat(mVertexArray, attribute, 3, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(mVertexArray, attribute, attribute);
      glEnableVertexArrayAttrib(mVertexArray, attribute);
    }
    glVertexArrayElementBuffer(mVertexArray, mBuffers[2]);
    mProgram = linkProgram();
    glCreateQueries(GL_TIME_ELAPSED, 1, &mTimer);
    checkErrors("uploading the mesh");
  }
  MeshRasterizer(const MeshRasterizer&) = delete;
  MeshRasterizer& operator=(const MeshRasterizer&) = delete;
  ~MeshRasterizer() {
    try {
      mContext->makeCurrent();
    } catch (const Error&) {
      return;  // the context is gone, and its objects with it
    }
    glDeleteQueries(1, &mTimer);
    glDeleteProgram(mProgram);
    releaseTarget();
    glDeleteBuffers(3, mBuffers);
    glDeleteVertexArrays(1, &mVertexArray);
  }

  const EglContext& context() const { return *mContext; }

  /// Draws one frame of width x height pixels (y down, as Image is) and returns its colour: grey
  /// Lambert shading with alpha 255 where a triangle covers the pixel centre, (0, 0, 0, 0) elsewhere.
  Image<std::uint8_t> render(const render::Camera& camera, int width, int height) {
    draw(camera, width, height);
    Image<std::uint8_t> color(width, height, 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    std::vector<std::uint8_t> rows(std::size_t(width) * std::size_t(height) * 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    checkErrors("reading the frame back");
    const std::size_t rowBytes = std::size_t(width) * 4;
    auto out = color.levelData(0);
    for (int y = 0; y < height; ++y)  // OpenGL's rows run bottom up
      std::copy_n(rows.data() + std::size_t(height - 1 - y) * rowBytes, rowBytes, out.data() + std::size_t(y) * rowBytes);
    return color;
  }

  /// The last frame's time on the device by a timer query; 0 before the first frame. llvmpipe's
  /// readings are not frame times (0, or a part of the frame).
  double deviceSeconds() const {
    if (!mDrawn) return 0;
    mContext->makeCurrent();
    GLuint64 nanoseconds = 0;
    glGetQueryObjectui64v(mTimer, GL_QUERY_RESULT, &nanoseconds);
    return double(nanoseconds) * 1e-9;
  }

 private:
  static constexpr const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 0) uniform mat4 viewProjection;
out vec3 vNormal;
void main() {
  gl_Position = viewProjection * vec4(position, 1.0);
  vNormal = normal;
}
)";
  static constexpr const char* kFragmentShader = R"(#version 450 core
in vec3 vNormal;
layout(location = 1) uniform vec3 lightDirection;
layout(location = 2) uniform vec3 ambientAndLight;
out vec4 color;
void main() {
  float lambert = max(dot(normalize(vNormal), lightDirection), 0.0);
  color = vec4(vec3(ambientAndLight.x + ambientAndLight.y * lambert), 1.0);
}
)";

  /// Throws, with the driver's log, unless `object` built (its status by `getStatus`, its log by
  /// `getLog`); a failed object is deleted first.
  static void requireBuilt(GLuint object, GLenum status, void (*getStatus)(GLuint, GLenum, GLint*),
                           void (*getLog)(GLuint, GLsizei, GLsizei*, GLchar*), void (*destroy)(GLuint),
                           const char* failure) {
    GLint ok = 0;
    getStatus(object, status, &ok);
    if (ok) return;
    char log[2048] = {};
    getLog(object, sizeof log, nullptr, log);
    destroy(object);
    throw Error(ErrorKind::Unsupported, std::string("mesh rasterizer: ") + failure + ": " + log);
  }

  static GLuint compile(GLenum stage, const char* source) {
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    requireBuilt(shader, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader,
                 "a shader did not compile");
    return shader;
  }

  static GLuint linkProgram() {
    const GLuint vertex = compile(GL_VERTEX_SHADER, kVertexShader);
    GLuint fragment = 0;
    try {
      fragment = compile(GL_FRAGMENT_SHADER, kFragmentShader);
    } catch (...) {
      glDeleteShader(vertex);
      throw;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vertex);
    glAttachShader(program, fragment);
    glLinkProgram(program);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    requireBuilt(program, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
                 "the program did not link");
    return program;
  }

  void checkErrors(const char* what) const {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR)
      throw Error(ErrorKind::Unsupported, std::string("mesh rasterizer: ") + what + " failed on " +
                                              mContext->renderer() + " (GL error " + std::to_string(e) + ")");
  }

  void releaseTarget() {
    if (mFramebuffer) glDeleteFramebuffers(1, &mFramebuffer);
    if (mRenderbuffers[0]) glDeleteRenderbuffers(2, mRenderbuffers);
    mFramebuffer = 0;
    mRenderbuffers[0] = mRenderbuffers[1] = 0;
  }

  void ensureTarget(int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
      throw Error(ErrorKind::InvalidArgument, "mesh rasterizer: width and height must lie in 1..16384");
    if (mFramebuffer && mWidth == width && mHeight == height) return;
    releaseTarget();
    glCreateRenderbuffers(2, mRenderbuffers);
    glNamedRenderbufferStorage(mRenderbuffers[0], GL_RGBA8, width, height);
    glNamedRenderbufferStorage(mRenderbuffers[1], GL_DEPTH_COMPONENT32F, width, height);
    glCreateFramebuffers(1, &mFramebuffer);
    glNamedFramebufferRenderbuffer(mFramebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, mRenderbuffers[0]);
    glNamedFramebufferRenderbuffer(mFramebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, mRenderbuffers[1]);
    if (glCheckNamedFramebufferStatus(mFramebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      releaseTarget();
      throw Error(ErrorKind::Unsupported, "mesh rasterizer: the frame buffer is incomplete on " + mContext->renderer());
    }
    mWidth = width;
    mHeight = height;
  }

  void draw(const render::Camera& camera, int width, int height) {
    mContext->makeCurrent();
    ensureTarget(width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, mFramebuffer);
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    const float clear[4] = {0, 0, 0, 0};
    const float farDepth = 1;
    glBeginQuery(GL_TIME_ELAPSED, mTimer);
    glClearNamedFramebufferfv(mFramebuffer, GL_COLOR, 0, clear);
    glClearNamedFramebufferfv(mFramebuffer, GL_DEPTH, 0, &farDepth);
    glUseProgram(mProgram);
    glUniformMatrix4fv(0, 1, GL_FALSE, gpu::cameraProjection(camera, width, height, mBounds).viewProjection);
    glUniform3f(1, mTowardsLight.x, mTowardsLight.y, mTowardsLight.z);
    glUniform3f(2, mAmbient, mLightIntensity, 0.0f);
    glBindVertexArray(mVertexArray);
    glDrawElements(GL_TRIANGLES, mIndexCount, GL_UNSIGNED_INT, nullptr);
    glEndQuery(GL_TIME_ELAPSED);
    checkErrors("drawing the mesh");
    mDrawn = true;
  }

  std::unique_ptr<EglContext> mContext;
  Aabbd mBounds;
  // The scene's default light and ambient term, as the ray casters shade.
  Vec3f mTowardsLight = glm::normalize(render::DirectionalLight{}.direction);
  float mAmbient = render::Scene{}.ambient.x;
  float mLightIntensity = render::DirectionalLight{}.intensity;
  GLsizei mIndexCount = 0;
  GLuint mVertexArray = 0, mBuffers[3] = {0, 0, 0}, mProgram = 0, mTimer = 0;
  GLuint mFramebuffer = 0, mRenderbuffers[2] = {0, 0};
  int mWidth = 0, mHeight = 0;
  bool mDrawn = false;
};

}  // namespace cellrelief::gl
