// SPDX-License-Identifier: MIT
/// @file gl_backend.h
/// The OpenGL 4.5 backend: the scene in the GPU layout (gpu/gpu_layout.h: cell table and hash
/// lookup in storage buffers, maps in integer array-texture atlases) and the one GLSL traversal
/// (backends/shaders/relief_trace.comp), on a headless EGL context (egl_context.h).
///
/// The traversal runs the paper's way, the grey cells (and geometry textures' chart boxes)
/// rasterized into a stencil and the traversal as a fragment pass on the covered pixels only
/// (early fragment tests), or as a compute pass over all pixels, with the same frame. The default
/// (RayEntry::Fastest) takes the fragment pass on llvmpipe, where it measured 1.3x to 2.1x the
/// compute pass (docs/backends.md), and on a GPU whichever its clock finds faster (on an H100 the
/// compute pass, 4x to 19x). The compute pass is also used whenever the eye is inside the scene's
/// bounds (gpu::rasterizedEntryServes).
///
/// A scene pays only for what it uses: each (scene, options) pair compiles a shader variant with
/// only the projection types, maps and features present (gpu/shader_preamble.h); variants are
/// cached. setGeneralShader(true) renders with the one shader that holds everything instead.
#pragma once

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "cellrelief/gl/egl_context.h"
#include "cellrelief/gpu/gpu_frame.h"
#include "cellrelief/gpu/gpu_layout.h"
#include "cellrelief/gpu/shader_preamble.h"
#include "cellrelief/render/backend.h"

namespace cellrelief::gl {

using gpu::kMaxLights;

using gpu::CoverParams;
using gpu::FrameLayout;
using gpu::FrameParams;
using gpu::RayEntry;

class GlBackend final : public render::Backend, public gpu::TraversalControls {
 public:
  GlBackend() : mContext(std::make_unique<EglContext>()) { queryLimits(); }
  ~GlBackend() override {
    try {
      mContext->makeCurrent();
    } catch (const Error&) {
      return;  // the context is gone: so is everything it held
    }
    releaseScene();
    for (auto& [name, program] : mPrograms) glDeleteProgram(program);
    if (mFrameBuffer) glDeleteBuffers(1, &mFrameBuffer);
    if (mParamsBuffer) glDeleteBuffers(1, &mParamsBuffer);
    if (mCoverBuffer) glDeleteBuffers(1, &mCoverBuffer);
    if (mCoverProgram) glDeleteProgram(mCoverProgram);
    if (mStencilFramebuffer) glDeleteFramebuffers(1, &mStencilFramebuffer);
    if (mStencil) glDeleteRenderbuffers(1, &mStencil);
    if (mEmptyVertexArray) glDeleteVertexArrays(1, &mEmptyVertexArray);
    if (mTimer) glDeleteQueries(1, &mTimer);
  }

  render::BackendKind kind() const override { return render::BackendKind::OpenGL; }
  std::string description() const override { return "OpenGL: " + mContext->description(); }
  const EglContext& context() const { return *mContext; }
  const gpu::DeviceLimits& limits() const { return mLimits; }

  void upload(const render::Scene& scene) override {
    mContext->makeCurrent();
    releaseScene();
    forgetEntryTimes();  // another scene: the entries' times were its own
    gpu::checkSceneSupported(scene, "the OpenGL backend");
    // Polycube meshes use storage binding 10, geometry textures 12, relief surfaces 13; OpenGL 4.3 promises only 8
    // (llvmpipe and the GPU drivers have more).
    const auto needBindings = [&](bool present, int bindings, const char* what) {
      if (present && mStorageBindings < bindings)
        throw Error(ErrorKind::Unsupported, "the OpenGL backend on " + mContext->renderer() + " has " +
                                                std::to_string(mStorageBindings) + " storage buffer bindings; " + what +
                                                " need " + std::to_string(bindings) + " (use vulkan or cpu)");
    };
    needBindings(!scene.polycubeMeshes.empty(), 11, "polycube meshes");
    needBindings(!scene.geotexModels.empty(), 13, "geometry textures");
    needBindings(!scene.reliefSurfaces.empty(), 14, "relief surfaces");
    mScene = scene;
    mGpu = gpu::packScene(scene, mLimits, true);
    for (int i = 0; i < 64 && glGetError() != GL_NO_ERROR; ++i) {
    }  // earlier errors are not this upload's (bounded: a lost context reports forever)
    mBuffers[0] = storageBuffer(mGpu.models.data(), mGpu.models.size() * sizeof(gpu::ModelInfo));
    mBuffers[1] = storageBuffer(mGpu.cells.data(), mGpu.cells.size() * sizeof(gpu::GpuCell));
    mBuffers[2] = storageBuffer(mGpu.hashSlots.data(), mGpu.hashSlots.size() * sizeof(std::uint32_t));
    mBuffers[3] = storageBuffer(mGpu.pyramid.data(), mGpu.pyramid.size() * sizeof(std::uint16_t));
    mBuffers[4] = storageBuffer(mGpu.polycube.words.data(), mGpu.polycube.words.size() * sizeof(std::uint32_t));
    mBuffers[5] = storageBuffer(mGpu.geotex.words.data(), mGpu.geotex.words.size() * sizeof(std::uint32_t));
    mBuffers[6] = storageBuffer(mGpu.parallax.words.data(), mGpu.parallax.words.size() * sizeof(std::uint32_t));
    mTextures[0] = atlasTexture(mGpu.distances, GL_R16UI, GL_RED_INTEGER, GL_UNSIGNED_SHORT);
    mTextures[1] = atlasTexture(mGpu.normalsOct, GL_RG16UI, GL_RG_INTEGER, GL_UNSIGNED_SHORT);
    mTextures[2] = atlasTexture(mGpu.normalsRgba, GL_RGBA8UI, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE);
    mTextures[3] = atlasTexture(mGpu.colors, GL_RGBA8UI, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE);
    mTextures[4] = polycubeTexture(mGpu.polycube);
    glFinish();
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
      releaseScene();
      throw Error(e == GL_OUT_OF_MEMORY ? ErrorKind::ResourceLimit : ErrorKind::Unsupported,
                  "the scene (" + gpu::detail::mib(mGpu.bytes()) + ") could not be uploaded to " +
                      mContext->renderer() + (e == GL_OUT_OF_MEMORY ? ": out of device memory" : ": GL error " + std::to_string(e)));
    }
    mGpuBytes = mGpu.bytes();
    mGpu.dropTexels();
    mUploaded = true;
  }

  void render(const render::Camera& camera, const render::RenderOptions& options) override {
    if (!mUploaded) throw Error(ErrorKind::InvalidArgument, "OpenGL backend: render() before upload()");
    if (options.width < 1 || options.height < 1)
      throw Error(ErrorKind::InvalidArgument, "OpenGL backend: empty frame size");
    mContext->makeCurrent();
    mRendered = false;  // a render that fails leaves nothing to read back
    checkFrameSize(options);
    const gpu::ShaderVariant variant = variantFor(options);
    // The cover's vertex shader reads two storage buffers, which OpenGL does not promise (the
    // minimum is none): without them the compute pass renders the same frame, as it does for a
    // frame larger than a renderbuffer.
    const bool rasterized = takeRasterized(variant, options,
                                           mVertexStorageBlocks >= 2 && rasterFits(options) &&
                                               gpu::rasterizedEntryServes(mScene, camera),
                                           !mContext->isSoftware());
    const GLuint program = programFor(variant, rasterized);
    if (rasterized) prepareRasterized(options);  // before the timer query: these may throw
    // The layout holds every channel the shader writes (the general one writes all of them);
    // readBack() copies those the caller asked for.
    const FrameLayout layout = gpu::frameLayout(options, variant.channels, mLimits.maxStorageBytes);
    ensureFrameBuffer(layout.words);
    const FrameParams params = gpu::frameParams(mScene, camera, options, layout);
    if (!mParamsBuffer) glCreateBuffers(1, &mParamsBuffer), glNamedBufferStorage(mParamsBuffer, sizeof(FrameParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferSubData(mParamsBuffer, 0, sizeof(FrameParams), &params);
    glUseProgram(program);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, mParamsBuffer);
    for (int i = 0; i < 4; ++i) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(1 + i), mBuffers[i]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, mBuffers[4]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, mBuffers[5]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, mBuffers[6]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, mFrameBuffer);
    for (int i = 0; i < 4; ++i) glBindTextureUnit(GLuint(6 + i), mTextures[i]);
    glBindTextureUnit(11, mTextures[4]);
    if (!mTimer) glGenQueries(1, &mTimer);
    glBeginQuery(GL_TIME_ELAPSED, mTimer);
    mLastEntry = rasterized ? RayEntry::Rasterized : RayEntry::Compute;
    if (rasterized) {
      renderRasterized(camera, options, layout, program);
    } else {
      const int gw = gpu::kGroupWidth, gh = gpu::kGroupHeight;
      glDispatchCompute(GLuint((options.width + gw - 1) / gw), GLuint((options.height + gh - 1) / gh), 1);
    }
    glEndQuery(GL_TIME_ELAPSED);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    mLayout = layout;
    mRendered = true;
  }

  void readBack(render::Frame& frame) override {
    if (!mRendered) throw Error(ErrorKind::InvalidArgument, "OpenGL backend: readBack() before render()");
    mContext->makeCurrent();
    std::vector<std::uint32_t> words(mLayout.words);
    glGetNamedBufferSubData(mFrameBuffer, 0, GLsizeiptr(words.size() * 4), words.data());
    GLuint64 nanoseconds = 0;
    glGetQueryObjectui64v(mTimer, GL_QUERY_RESULT, &nanoseconds);
    // A frame the driver failed to render must not pass as an image (a reset, an out-of-memory
    // at dispatch): the error is checked once the work has finished.
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
      mRendered = false;
      throw Error(e == GL_OUT_OF_MEMORY ? ErrorKind::ResourceLimit : ErrorKind::Unsupported,
                  "OpenGL backend: rendering the frame failed on " + mContext->renderer() + " (GL error " +
                      std::to_string(e) + ")");
    }
    // llvmpipe's timer queries do not see compute dispatches (they read about 0): no device clock.
    mGpuSeconds = mContext->isSoftware() ? 0.0 : double(nanoseconds) * 1e-9;
    entryTimed(mLastEntry == RayEntry::Rasterized, mGpuSeconds);
    gpu::unpackFrame(words.data(), mLayout, frame);
  }

  std::size_t sceneBytes() const override { return mUploaded ? mGpuBytes : 0; }

  /// GPU time of the last frame's dispatch (a timer query), known after readBack().
  double deviceSeconds() const override { return mGpuSeconds; }
  /// The variant the next render with these options uses.
  gpu::ShaderVariant variantFor(const render::RenderOptions& options) const { return variantOf(mGpu.features, options); }
  /// Seconds spent compiling and linking shader variants so far.
  double compileSeconds() const { return mCompileSeconds; }

 private:
  void queryLimits() {
    GLint size = 0, layers = 0;
    GLint64 block = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &size);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &layers);
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &mStorageBindings);
    glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &mVertexStorageBlocks);
    mLimits.maxTextureSize = size > 0 ? size : 2048;
    mLimits.maxArrayLayers = layers > 0 ? layers : 256;
    mLimits.maxStorageBytes = block > 0 ? std::size_t(block) : std::size_t(1) << 27;
    // The shader indexes buffers with 32-bit ints: no buffer beyond 2^31 bytes, whatever the driver.
    mLimits.maxStorageBytes = std::min<std::size_t>(mLimits.maxStorageBytes, std::size_t(1) << 31);
    mLimits.maxTotalBytes = deviceMemoryBytes();
  }

  /// What the device can hold, so that a scene beyond it is refused by name before the upload:
  /// NVIDIA's total (GL_NVX_gpu_memory_info), AMD's free texture memory (GL_ATI_meminfo), half
  /// the machine's memory for a software rasterizer (its "device memory" is the heap), else
  /// unknown (0: the upload's GL_OUT_OF_MEMORY is the check).
  std::size_t deviceMemoryBytes() const {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    bool nvx = false, ati = false;
    for (GLint i = 0; i < count; ++i) {
      const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
      nvx |= e && std::strcmp(e, "GL_NVX_gpu_memory_info") == 0;
      ati |= e && std::strcmp(e, "GL_ATI_meminfo") == 0;
    }
    GLint kib[4] = {0, 0, 0, 0};
    if (nvx) glGetIntegerv(0x9048 /* GL_GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX */, kib);
    else if (ati) glGetIntegerv(0x87FC /* GL_TEXTURE_FREE_MEMORY_ATI */, kib);
    for (int i = 0; i < 64 && glGetError() != GL_NO_ERROR; ++i) {
    }  // a query the driver refused leaves kib[0] at 0
    if (kib[0] > 0) return std::size_t(kib[0]) * 1024;
    if (mContext->isSoftware()) {
      const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
      if (pages > 0 && page > 0) return std::size_t(pages) * std::size_t(page) / 2;
    }
    return 0;
  }

  void ensureFrameBuffer(std::size_t words) {
    if (mFrameBuffer && mFrameWords >= words) return;
    if (mFrameBuffer) glDeleteBuffers(1, &mFrameBuffer);
    glCreateBuffers(1, &mFrameBuffer);
    glNamedBufferStorage(mFrameBuffer, GLsizeiptr(words * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
    if (glGetError() == GL_OUT_OF_MEMORY) {
      glDeleteBuffers(1, &mFrameBuffer);
      mFrameBuffer = 0;
      throw Error(ErrorKind::ResourceLimit, "OpenGL backend: out of device memory for a frame of " +
                                                gpu::detail::mib(words * 4));
    }
    mFrameWords = words;
  }

  static GLuint storageBuffer(const void* data, std::size_t bytes) {
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    // Never empty: a zero-sized buffer cannot be bound.
    const std::uint32_t zeros[4] = {0, 0, 0, 0};
    if (bytes == 0) data = zeros, bytes = sizeof zeros;
    glNamedBufferStorage(buffer, GLsizeiptr(bytes), data, 0);
    return buffer;
  }

  /// A 2D array texture clamped to its edges, with one filter for both directions.
  static GLuint arrayTexture(GLenum filter) {
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &texture);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GLint(filter));
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    return texture;
  }

  template <class T>
  static GLuint atlasTexture(const gpu::Atlas<T>& atlas, GLenum internalFormat, GLenum format, GLenum type) {
    const GLuint texture = arrayTexture(GL_NEAREST);
    if (atlas.empty()) {  // an unused map: a 1 x 1 placeholder keeps the binding complete
      glTextureStorage3D(texture, 1, internalFormat, 1, 1, 1);
      const std::uint32_t zero[2] = {0, 0};
      glTextureSubImage3D(texture, 0, 0, 0, 0, 1, 1, 1, format, type, zero);
      return texture;
    }
    glTextureStorage3D(texture, 1, internalFormat, atlas.width, atlas.height, atlas.layers);
    glTextureSubImage3D(texture, 0, 0, 0, 0, atlas.width, atlas.height, atlas.layers, format, type,
                        atlas.texels.data());
    return texture;
  }

  /// T2 of every polycube mesh: RGBA8 read as UNORM and filtered by the hardware (its tiles'
  /// borders make bilinear reads seamless, polycube_texture.h); no mip chain (the levels are
  /// stacked in the texture).
  static GLuint polycubeTexture(const gpu::PolycubeGpu& p) {
    const GLuint texture = arrayTexture(GL_LINEAR);
    glTextureStorage3D(texture, 1, GL_RGBA8, p.width, p.height, 1);
    glTextureSubImage3D(texture, 0, 0, 0, 0, p.width, p.height, 1, GL_RGBA, GL_UNSIGNED_BYTE, p.t2.data());
    return texture;
  }

  GLuint programFor(const gpu::ShaderVariant& variant, bool fragment) {
    const std::string key = variant.name() + "#" + std::to_string(variant.channels) + (fragment ? "#fragment" : "");
    if (auto it = mPrograms.find(key); it != mPrograms.end()) return it->second;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string what = "the traversal shader (variant " + variant.name() + (fragment ? ", fragment" : "") + ")";
    const GLuint program = fragment ? linkProgram({{GL_VERTEX_SHADER, std::string(gpu::kFullScreenVert)},
                                                   {GL_FRAGMENT_SHADER, gpu::reliefTraceShader(variant, true)}},
                                                  what)
                                    : linkProgram({{GL_COMPUTE_SHADER, gpu::reliefTraceShader(variant)}}, what);
    mCompileSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    mPrograms[key] = program;
    return program;
  }

  /// Compiles and links the stages; an Error with the driver's log when one fails.
  GLuint linkProgram(const std::vector<std::pair<GLenum, std::string>>& stages, const std::string& what) {
    const GLuint program = glCreateProgram();
    std::vector<GLuint> shaders;
    auto fail = [&](const std::string& verb, const std::string& log) {
      for (GLuint sh : shaders) glDeleteShader(sh);
      glDeleteProgram(program);
      throw Error(ErrorKind::Unsupported,
                  "OpenGL backend: " + what + " does not " + verb + " on " + mContext->renderer() + ":\n" + log);
    };
    for (const auto& [stage, source] : stages) {
      const GLuint shader = glCreateShader(stage);
      shaders.push_back(shader);
      const char* text = source.c_str();
      glShaderSource(shader, 1, &text, nullptr);
      glCompileShader(shader);
      GLint ok = 0;
      glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
      if (!ok) fail("compile", shaderLog(shader, false));
      glAttachShader(program, shader);
    }
    glLinkProgram(program);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) fail("link", shaderLog(program, true));
    for (GLuint sh : shaders) glDeleteShader(sh);
    return program;
  }

  /// What the rasterized entry needs, made before a frame starts (creation may throw).
  void prepareRasterized(const render::RenderOptions& o) {
    ensureStencil(o.width, o.height);
    if (!mCoverProgram)
      mCoverProgram = linkProgram({{GL_VERTEX_SHADER, gpu::cellCoverShader()},
                                   {GL_FRAGMENT_SHADER, "#version 450\nvoid main() {}\n"}},
                                  "the cell cover shader");
    if (!mEmptyVertexArray) glCreateVertexArrays(1, &mEmptyVertexArray);
    if (!mCoverBuffer) glCreateBuffers(1, &mCoverBuffer), glNamedBufferStorage(mCoverBuffer, sizeof(CoverParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  }

  /// A frame the device cannot dispatch in one piece is refused by its size.
  void checkFrameSize(const render::RenderOptions& o) const {
    GLint groupsX = 0, groupsY = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groupsX);
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1, &groupsY);
    if ((o.width + gpu::kGroupWidth - 1) / gpu::kGroupWidth > groupsX ||
        (o.height + gpu::kGroupHeight - 1) / gpu::kGroupHeight > groupsY)
      throw Error(ErrorKind::ResourceLimit, "OpenGL backend: a " + std::to_string(o.width) + "x" +
                                                std::to_string(o.height) + " frame is beyond what " +
                                                mContext->renderer() + " renders in one pass");
  }

  /// Whether the stencil of the rasterized entry can be as large as the frame.
  static bool rasterFits(const render::RenderOptions& o) {
    GLint renderbuffer = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
    return o.width <= renderbuffer && o.height <= renderbuffer;
  }

  /// The paper's way: grey cells and chart boxes into the stencil, then the traversal on the
  /// covered pixels. Pixels nothing covers get the miss values first (their rays meet nothing).
  void renderRasterized(const render::Camera& camera, const render::RenderOptions& o, const FrameLayout& layout,
                        GLuint traversal) {
    clearToMisses(layout);
    glBindFramebuffer(GL_FRAMEBUFFER, mStencilFramebuffer);
    glViewport(0, 0, o.width, o.height);
    const GLint zero = 0;
    glClearNamedFramebufferiv(mStencilFramebuffer, GL_STENCIL, 0, &zero);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 1, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glBindVertexArray(mEmptyVertexArray);
    glUseProgram(mCoverProgram);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, mBuffers[1]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, mBuffers[5]);
    glBindBufferBase(GL_UNIFORM_BUFFER, 10, mCoverBuffer);
    const auto drawCover = [&](const CoverParams& cover, std::size_t instances) {
      if (instances == 0) return;
      glNamedBufferSubData(mCoverBuffer, 0, sizeof cover, &cover);
      glDrawArraysInstanced(GL_TRIANGLES, 0, 36, GLsizei(instances));
    };
    for (std::size_t m = 0; m < mScene.models.size(); ++m)
      drawCover(gpu::coverParams(mScene, mGpu, camera, o, m, mCoverDilation), mScene.models[m]->cells.size());
    for (std::size_t m = 0; m < mScene.geotexModels.size(); ++m)
      drawCover(gpu::chartCoverParams(mScene, camera, o, m, mCoverDilation), mScene.geotexModels[m]->charts.size());
    glStencilFunc(GL_EQUAL, 1, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glUseProgram(traversal);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_STENCIL_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  /// The miss values of every channel: what a ray that meets no grey cell writes.
  void clearToMisses(const FrameLayout& layout) const {
    for (const gpu::WordFill& f : gpu::missFills(layout, mScene))
      glClearNamedBufferSubData(mFrameBuffer, GL_R32UI, GLintptr(f.offset * 4), GLsizeiptr(f.words * 4), GL_RED_INTEGER,
                                GL_UNSIGNED_INT, &f.value);
  }

  void ensureStencil(int width, int height) {
    if (mStencil && mStencilWidth == width && mStencilHeight == height) return;
    if (mStencil) glDeleteRenderbuffers(1, &mStencil);
    if (!mStencilFramebuffer) glCreateFramebuffers(1, &mStencilFramebuffer);
    glCreateRenderbuffers(1, &mStencil);
    glNamedRenderbufferStorage(mStencil, GL_STENCIL_INDEX8, width, height);
    glNamedFramebufferRenderbuffer(mStencilFramebuffer, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER, mStencil);
    glNamedFramebufferDrawBuffer(mStencilFramebuffer, GL_NONE);
    if (glCheckNamedFramebufferStatus(mStencilFramebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw Error(ErrorKind::Unsupported, "OpenGL backend: a stencil-only framebuffer is not supported on " +
                                              mContext->renderer());
    mStencilWidth = width;
    mStencilHeight = height;
  }

  static std::string shaderLog(GLuint object, bool program) {
    GLint length = 0;
    program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(std::max(length, 1)), '\0');
    program ? glGetProgramInfoLog(object, length, nullptr, log.data())
            : glGetShaderInfoLog(object, length, nullptr, log.data());
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return log;
  }

  void releaseScene() {
    for (GLuint& b : mBuffers)
      if (b) glDeleteBuffers(1, &b), b = 0;
    for (GLuint& t : mTextures)
      if (t) glDeleteTextures(1, &t), t = 0;
    mUploaded = false;
    mRendered = false;
    mGpuBytes = 0;
  }

  std::unique_ptr<EglContext> mContext;
  gpu::DeviceLimits mLimits;
  render::Scene mScene;
  gpu::GpuScene mGpu;
  std::size_t mGpuBytes = 0;
  GLint mStorageBindings = 0;  ///< GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
  GLint mVertexStorageBlocks = 0;  ///< GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS (the cover reads two)
  GLuint mBuffers[7] = {0, 0, 0, 0, 0, 0, 0};  ///< models, cells, hash, pyramid, polycube meshes, geometry textures, relief surfaces
  GLuint mTextures[5] = {0, 0, 0, 0, 0};  ///< distances, octahedral normals, RGBA normals, colors, polycube T2
  GLuint mFrameBuffer = 0, mParamsBuffer = 0, mTimer = 0;
  GLuint mCoverProgram = 0, mCoverBuffer = 0, mStencilFramebuffer = 0, mStencil = 0, mEmptyVertexArray = 0;
  int mStencilWidth = 0, mStencilHeight = 0;
  std::size_t mFrameWords = 0;
  std::map<std::string, GLuint> mPrograms;
  FrameLayout mLayout;
  bool mUploaded = false, mRendered = false;
  double mGpuSeconds = 0, mCompileSeconds = 0;
};

/// What an OpenGL 4.5 context here runs on, or why none comes up (probed once per process).
struct Probe {
  render::Availability availability;
  std::string renderer;   ///< e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or the GPU's name
  bool software = false;  ///< a software rasterizer (llvmpipe)
};
inline const Probe& probe() {
  static const Probe result = [] {
    try {
      EglContext context;
      return Probe{{true, ""}, context.renderer(), context.isSoftware()};
    } catch (const Error& e) {
      return Probe{{false, e.what()}, "", false};
    }
  }();
  return result;
}
inline render::Availability probeAvailability() { return probe().availability; }

}  // namespace cellrelief::gl
