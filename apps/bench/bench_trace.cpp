// SPDX-License-Identifier: MIT
/// @file bench_trace.cpp
/// Benchmark: ray casting of relief models, run time against error. For each mesh it sweeps the
/// grid size N, the texels T, the linear and binary steps and empty-space skipping (off, in parallel
/// and planar cells only, or in the central ones too), and the SIMD packet tracer (packet_tracer.h;
/// the linear search without skipping, 16 rays at a time, when built with Highway); for each point
/// it measures coherent primary rays and incoherent secondary rays (Mrays/s, same rays and threads
/// for everyone), the depth error against Embree on the original mesh (median and 95th percentile,
/// in sample spacings and as a fraction of the diagonal), hit/miss disagreement and the bytes of the
/// representation. In the same run: Embree's rtcIntersect1 on the original mesh, and OpenVDB's
/// LevelSetRayIntersector on meshToLevelSet grids with the voxel size matched to our error and,
/// separately, to our memory; and memory at equal error, against our smallest setting and our memory
/// curve. Writes trace.csv, and from it (apps/plots, matplotlib) a plot of the Pareto front
/// (trace_pareto.png) and one of bytes against error (trace_memory.png).
///
///   bench_trace [--data DIR] [--out out/bench] [--quick] [--threads 2] [--size 512]
#include <atomic>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include <CLI/CLI.hpp>
#include <cellrelief/core/parallel.h>
#include <cellrelief/embree/embree_scene.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/ray_comparison.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/camera.h>
#include <cellrelief/trace/relief_tracer.h>
#if CELLRELIEF_HAS_PACKETS
#include <cellrelief/trace/packet_tracer.h>
#endif
#include <openvdb/tools/RayIntersector.h>
#include <tbb/enumerable_thread_specific.h>

#include "../common/plot_script.h"
#include "bench_common.h"
#include "bench_programs.h"

namespace cellrelief::bench::trace_program {

namespace {

/// One batch of rays and what each method answered (t, or infinity).
struct RaySet {
  std::vector<Rayf> rays;
  std::vector<float> truth;  ///< Embree's t on the original mesh
};

/// Coherent primary rays: one per pixel of a framing camera, row by row.
RaySet primaryRays(const Aabbd& bounds, int size) {
  RaySet set;
  const render::Camera camera = render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), 35, 20);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Rayd r = camera.primaryRay(x, y, size, size);
      set.rays.emplace_back(Vec3f(r.origin), Vec3f(r.direction));
    }
  return set;
}

/// Incoherent secondary rays: from points just off the surface (Embree's primary hits, pushed
/// out along the normal by `offset`), in uniformly random directions of the outer hemisphere,
/// shuffled: the shadow and reflection rays of a path tracer.
RaySet secondaryRays(const embree::EmbreeScene& scene, const RaySet& primary, float offset) {
  RaySet set;
  std::mt19937 random(12345);
  std::normal_distribution<float> gauss;
  for (std::size_t i = 0; i < primary.rays.size(); ++i) {
    const Hitf hit = scene.intersect(primary.rays[i]);
    if (!hit.valid()) continue;
    Vec3f n = scene.normal(hit);
    if (glm::dot(n, primary.rays[i].direction) > 0) n = -n;
    Vec3f d(gauss(random), gauss(random), gauss(random));
    d = glm::normalize(d);
    if (glm::dot(d, n) < 0) d = -d;
    set.rays.emplace_back(primary.rays[i].at(hit.t) + offset * n, d);
  }
  std::shuffle(set.rays.begin(), set.rays.end(), random);
  return set;
}

/// Runs `trace(ray) -> t` over every ray in parallel; returns the best of `repeats` wall times.
template <class Trace>
double traceAll(const std::vector<Rayf>& rays, std::vector<float>& t, int repeats, Trace&& trace) {
  t.assign(rays.size(), 0);
  double best = INFINITY;
  for (int r = 0; r < repeats; ++r) {
    best = std::min(best, bench::medianSeconds(1, [&] {
      parallelForRange(0, rays.size(), [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) t[i] = trace(rays[i]);
      }, 1024);
    }));
  }
  return best;
}

struct Accuracy {
  double medianError = 0, p95Error = 0;  ///< world units
  std::size_t disagreements = 0;
};

Accuracy accuracy(const std::vector<float>& truth, const std::vector<float>& t) {
  Accuracy a;
  std::vector<double> errors;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool h0 = std::isfinite(truth[i]), h1 = std::isfinite(t[i]);
    if (h0 != h1)
      ++a.disagreements;
    else if (h0)
      errors.push_back(std::abs(double(truth[i]) - double(t[i])));
  }
  const metrics::Distribution d = metrics::distributionOf(std::move(errors));
  a.medianError = d.median;
  a.p95Error = d.p95;
  return a;
}

/// OpenVDB's level-set ray intersector, one copy per thread (it holds a value accessor).
struct LevelSetTracer {
  using Intersector = openvdb::tools::LevelSetRayIntersector<openvdb::FloatGrid>;
  openvdb::FloatGrid::Ptr grid;
  std::unique_ptr<tbb::enumerable_thread_specific<Intersector>> intersectors;

  explicit LevelSetTracer(openvdb::FloatGrid::Ptr g) : grid(std::move(g)) {
    intersectors = std::make_unique<tbb::enumerable_thread_specific<Intersector>>(Intersector(*grid));
  }
  float operator()(const Rayf& ray) const {
    Intersector& is = intersectors->local();
    // OpenVDB asserts (in a Debug build) that the direction is unit length in double: one that is
    // unit length in float is not, so it is normalized again here.
    const openvdb::Vec3d direction =
        openvdb::Vec3d(ray.direction.x, ray.direction.y, ray.direction.z).unitSafe();
    const openvdb::math::Ray<double> r(openvdb::Vec3d(ray.origin.x, ray.origin.y, ray.origin.z), direction);
    openvdb::Vec3d world;
    // intersectsWS(ray, time) reads the time before the search in OpenVDB 10: use the position.
    if (!is.intersectsWS(r, world)) return INFINITY;
    return float((world - r.eye()).length());
  }
};

struct SweepPoint {
  int n = 0, texels = 0, minLinear = 4, maxLinear = 64, binary = 8;
  /// empty-space skipping: 0 off, 1 parallel and planar cells, 2 central cells too; 3: SIMD packets
  /// (skipping off, the same answers as 0)
  int skip = 2;
  int bits = 16;  ///< distance quantization
};

const char* skipName(int skip) { return skip == 0 ? "off" : skip == 1 ? "flat" : skip == 2 ? "all" : "pkt"; }

#if CELLRELIEF_HAS_PACKETS
constexpr bool kPackets = true;
/// Rays per block of the packet tracer: one sort gathers a block's rays by cell into packets.
constexpr std::size_t kPacketBlock = 4096;

/// traceAll for the packet tracer: blocks of rays in parallel.
double traceAllPackets(const std::vector<Rayf>& rays, std::vector<float>& t, int repeats,
                       const trace::ReliefPacketTracer<>& tracer) {
  t.assign(rays.size(), 0);
  std::vector<trace::ReliefHit<float>> hits(rays.size());
  double best = INFINITY;
  for (int r = 0; r < repeats; ++r) {
    best = std::min(best, bench::medianSeconds(1, [&] {
      parallelForRange(0, rays.size(), [&](std::size_t b, std::size_t e) {
        tracer.intersect(std::span(rays).subspan(b, e - b), std::span(hits).subspan(b, e - b));
        for (std::size_t i = b; i < e; ++i) t[i] = hits[i].t;
      }, kPacketBlock);
    }));
  }
  return best;
}
#else
constexpr bool kPackets = false;
#endif

/// Field evaluations and skip steps per ray, over every ray (hits and misses).
double meanSteps(const trace::ReliefTracerf& tracer, const std::vector<Rayf>& rays) {
  std::atomic<std::uint64_t> total{0};
  parallelForRange(0, rays.size(), [&](std::size_t b, std::size_t e) {
    std::uint64_t local = 0;
    for (std::size_t i = b; i < e; ++i) local += tracer.intersect(rays[i]).steps;
    total += local;
  }, 1024);
  return double(total) / double(std::max<std::size_t>(1, rays.size()));
}

/// One point of a memory curve: median depth error (fraction of the diagonal) and bytes.
struct MemoryPoint {
  double error = 0, bytes = 0;
};

/// The points no other point beats in both error and bytes, by increasing error (so decreasing
/// bytes): the least memory that reaches each error.
std::vector<MemoryPoint> memoryFront(std::vector<MemoryPoint> points) {
  std::sort(points.begin(), points.end(), [](const MemoryPoint& a, const MemoryPoint& b) {
    return a.error < b.error || (a.error == b.error && a.bytes < b.bytes);
  });
  std::vector<MemoryPoint> front;
  for (const MemoryPoint& p : points)
    if (front.empty() || p.bytes < front.back().bytes) front.push_back(p);
  return front;
}

/// Bytes of the smallest point of `front` at least as accurate as `error` (a setting that was
/// measured), or NaN when none is.
double bytesOfSetting(const std::vector<MemoryPoint>& front, double error) {
  double bytes = NAN;
  for (const MemoryPoint& p : front)
    if (p.error <= error) bytes = p.bytes;
  return bytes;
}

/// Bytes on the front at `error`, interpolated log-log between its neighbouring points (grids
/// and texel counts between the measured ones), or NaN below the front's least error.
double bytesOnCurve(const std::vector<MemoryPoint>& front, double error) {
  if (front.empty() || error < front.front().error) return NAN;
  for (std::size_t i = 0; i + 1 < front.size(); ++i)
    if (error < front[i + 1].error) {
      const double s = std::log(error / front[i].error) / std::log(front[i + 1].error / front[i].error);
      return std::exp(std::log(front[i].bytes) + s * std::log(front[i + 1].bytes / front[i].bytes));
    }
  return front.back().bytes;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"Relief ray casting: run time against error; Embree and OpenVDB peers", "bench_trace"};
  bench::BenchOptions options;
  options.threads = 2;
  int size = 512;
  options.addTo(app);
  app.add_option("--size", size, "Primary rays: size x size pixels")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const ThreadLimit limit{std::size_t(options.threads)};
  const bool quick = options.quick;
  if (quick) size = std::min(size, 128);
  const int repeats = quick ? 1 : 3;
  openvdb::initialize();

  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  try {
    if (quick) {
      meshes.emplace_back("fertility", io::readMesh(options.data + "/meshes/small/fertility_9k__libigl-tutorial-data.off"));
    } else {
      TriangleMesh igea = io::readMesh(options.data + "/meshes/large/igea__common-3d-test-models.ply");
      TriangleMesh igea1M = bench::loopSubdivide(igea);
      meshes.emplace_back("igea", std::move(igea));
      meshes.emplace_back("igea-loop1", std::move(igea1M));
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_trace: %s\n", e.what());
    return 1;
  }

  bench::CsvWriter csv(std::filesystem::path(options.out) / "trace.csv",
                       "mesh,method,N,T,bits,min_linear,max_linear,binary,skip,bytes,primary_mrays,"
                       "secondary_mrays,steps_per_ray,median_error_texels,p95_error_texels,median_error_diag,"
                       "p95_error_diag,disagreements_per_million,secondary_disagreements_per_million");
  std::printf("threads: %d; primary rays %dx%d from a framing camera; secondary rays: random outer "
              "hemisphere directions from points on the surface, shuffled\n", options.threads, size, size);
#if CELLRELIEF_HAS_PACKETS
  std::printf("skip pkt: the SIMD packet tracer on %s (Highway), blocks of %zu rays\n",
              trace::ReliefPacketTracer<>::instructionSet(), kPacketBlock);
#endif
  for (const auto& [name, mesh] : meshes) {
    const Aabbd bounds(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max));
    const double diagonal = bounds.diagonal();
    const embree::EmbreeScene embree(mesh);
    RaySet primary = primaryRays(bounds, size);
    std::vector<float> t;
    const double embreePrimary = traceAll(primary.rays, primary.truth, repeats,
                                          [&](const Rayf& r) { return embree.intersect(r).t; });
    // Secondary rays start 0.1% of the diagonal off the surface, past every representation's error.
    RaySet secondary = secondaryRays(embree, primary, float(1e-3 * diagonal));
    const double embreeSecondary = traceAll(secondary.rays, secondary.truth, repeats,
                                            [&](const Rayf& r) { return embree.intersect(r).t; });
    const double primaryCount = double(primary.rays.size()), secondaryCount = double(secondary.rays.size());
    const double embreeMraysPrimary = primaryCount / embreePrimary * 1e-6;
    const double embreeMraysSecondary = secondaryCount / embreeSecondary * 1e-6;
    std::printf("\n%s: %zu triangles; Embree rtcIntersect1: %.2f Mrays/s primary, %.2f secondary; "
                "mesh + BVH %s bytes\n", name.c_str(), mesh.triangleCount(), embreeMraysPrimary,
                embreeMraysSecondary, std::to_string(embree.byteSize()).c_str());
    csv.row(name, "embree", 0, 0, 0, 0, 0, 0, 0, embree.byteSize(), embreeMraysPrimary,
            embreeMraysSecondary, 0, 0, 0, 0, 0, 0, 0);
    std::printf("%5s %4s %4s %8s %3s %4s %10s %9s %9s %7s %8s %8s %10s %8s %8s | %7s %7s %7s\n", "N", "T",
                "bits", "linear", "bin", "skip", "bytes", "prim Mr/s", "sec Mr/s", "steps", "med tx", "p95 tx",
                "med diag", "dis/M", "sec dis/M", "vs Emb", "sec vs", "memory");

    // The sweep: grids around the automatic choice, texels, search parameters, skipping.
    const relief::ReliefModel automatic = relief::convert(mesh);
    std::vector<SweepPoint> sweep;
    const std::vector<int> grids = quick ? std::vector<int>{automatic.gridSize}
                                         : std::vector<int>{automatic.gridSize, 8, 16, 32};
    const std::vector<int> texelChoices = quick ? std::vector<int>{17} : std::vector<int>{17, 33, 65};
    for (int n : grids)
      for (int texels : texelChoices) {
        const std::vector<int> skips = kPackets ? std::vector<int>{2, 1, 0, 3} : std::vector<int>{2, 1, 0};
        // Linear steps (fewest, most) and bisections; three bisections, because the secant step
        // after them leaves the error of more.
        struct Search { int minLinear, maxLinear, binary; };
        const std::vector<Search> searches =
            quick ? std::vector<Search>{{4, 64, 8}} : std::vector<Search>{{4, 64, 8}, {2, 32, 6}, {2, 32, 3}};
        for (const Search& search : searches)
          for (int skip : skips) sweep.push_back({n, texels, search.minLinear, search.maxLinear, search.binary, skip});
        if (!quick) {
          // 8-bit distances: half the bytes, for the memory curve.
          sweep.push_back({n, texels, 4, 64, 8, 2, 8});
        }
      }
    // Coarse grids with fine texels: at N = 1 and 2 the packet tracer's rate hardly depends on T
    // while the error falls with it, so these reach the fine end of the curve (OpenVDB at
    // diagonal/256 to /1024) faster than finer grids do. The packet tracer with each search, and
    // the scalar skipping tracer with one.
    if (!quick)
      for (const auto& [n, texels] : std::vector<std::pair<int, int>>{{1, 129}, {1, 257}, {1, 513}, {1, 1025}, {2, 129}, {2, 257}}) {
        const int fastest = kPackets ? 3 : 2;
        for (const int maxLinear : {16, 32, 64}) sweep.push_back({n, texels, 2, maxLinear, 3, fastest});
        if (kPackets) sweep.push_back({n, texels, 2, 32, 3, 2});
      }
    // Coarse grids between the automatic one and 8, for the memory curve only.
    if (!quick)
      for (int n : {2, 4})
        if (n > automatic.gridSize)
          for (int texels : texelChoices)
            for (int skip : {2, 0}) sweep.push_back({n, texels, 4, 64, 8, skip});
    std::vector<double> allError, allSpeed, allBytes;
    std::vector<MemoryPoint> memoryPoints;
    double bestMatchedError = INFINITY, ourBytesAtBest = 0, ourSpeedAtBest = 0;
    std::shared_ptr<relief::ReliefModel> model;
    int modelN = -1, modelT = -1, modelBits = -1;
    for (const SweepPoint& p : sweep) {
      if (p.n != modelN || p.texels != modelT || p.bits != modelBits) {
        model = std::make_shared<relief::ReliefModel>(
            relief::convert(mesh, {.gridSize = p.n, .texels = p.texels, .distanceBits = p.bits}));
        modelN = p.n;
        modelT = p.texels;
        modelBits = p.bits;
      }
      const trace::TraceOptions to{.minLinearSteps = p.minLinear, .maxLinearSteps = p.maxLinear,
                                   .binarySteps = p.binary, .skipEmptySpace = p.skip == 1 || p.skip == 2,
                                   .skipCentralCells = p.skip == 2};
      const trace::ReliefTracerf tracer(*model, to);
      auto traceOne = [&](const Rayf& r) { return tracer.intersect(r).t; };
#if CELLRELIEF_HAS_PACKETS
      std::optional<trace::ReliefPacketTracer<>> packets;
      if (p.skip == 3) packets.emplace(*model, to);
#endif
      auto traceSet = [&](const std::vector<Rayf>& rays) {
#if CELLRELIEF_HAS_PACKETS
        if (packets) return traceAllPackets(rays, t, repeats, *packets);
#endif
        return traceAll(rays, t, repeats, traceOne);
      };
      const double s1 = traceSet(primary.rays);
      const Accuracy a = accuracy(primary.truth, t);
      const double s2 = traceSet(secondary.rays);
      const Accuracy a2 = accuracy(secondary.truth, t);
      const double spacing = model->sampleSpacingWS();
      const std::size_t bytes = model->byteSize() + tracer.accelerationBytes();
      const double mr1 = primaryCount / s1 * 1e-6, mr2 = secondaryCount / s2 * 1e-6;
      const double steps = meanSteps(tracer, primary.rays);
      char linear[16];
      std::snprintf(linear, sizeof linear, "%d-%d", p.minLinear, p.maxLinear);
      std::printf("%5d %4d %4d %8s %3d %4s %10zu %9.2f %9.2f %7.1f %8.3f %8.3f %10.2e %8.0f %8.0f | %6.2fx %6.2fx %6.1fx\n",
                  model->gridSize, model->texels, p.bits, linear, p.binary, skipName(p.skip), bytes, mr1, mr2, steps,
                  a.medianError / spacing, a.p95Error / spacing, a.medianError / diagonal,
                  1e6 * a.disagreements / primaryCount, 1e6 * a2.disagreements / secondaryCount,
                  mr1 / embreeMraysPrimary, mr2 / embreeMraysSecondary,
                  double(embree.byteSize()) / double(bytes));
      csv.row(name, "relief", model->gridSize, model->texels, p.bits, p.minLinear, p.maxLinear, p.binary,
              p.skip, bytes, mr1, mr2, steps, a.medianError / spacing, a.p95Error / spacing,
              a.medianError / diagonal, a.p95Error / diagonal, 1e6 * a.disagreements / primaryCount,
              1e6 * a2.disagreements / secondaryCount);
      allError.push_back(a.medianError / diagonal);
      allSpeed.push_back(mr1);
      allBytes.push_back(double(bytes));
      memoryPoints.push_back({a.medianError / diagonal, double(bytes)});
      // The fastest point within a texel of median error is our headline for the matched peers.
      if (a.medianError <= spacing && mr1 > ourSpeedAtBest) {
        ourSpeedAtBest = mr1;
        bestMatchedError = a.medianError;
        ourBytesAtBest = double(bytes);
      }
    }
    // OpenVDB level sets: voxel = diagonal / 2^k. Matched to our error: the coarsest whose median
    // depth error is at most ours; matched to our memory: the one closest to our bytes.
    struct LevelSetRun {
      double voxel, mrays, median;
      std::size_t bytes, disagreements;
    };
    std::vector<LevelSetRun> runs;
    const std::vector<MemoryPoint> leastMemory = memoryFront(memoryPoints);
    for (int k = 6; k <= (quick ? 8 : 11); ++k) {
      const double voxel = diagonal / double(1 << k);
      LevelSetTracer ls(bench::levelSet(mesh, voxel));
      const double s = traceAll(primary.rays, t, 1, ls);
      const Accuracy a = accuracy(primary.truth, t);
      runs.push_back({voxel, primaryCount / s * 1e-6, a.medianError, ls.grid->memUsage(), a.disagreements});
      std::printf("  OpenVDB level set, voxel diagonal/%d: %.2f Mrays/s, median error %.2e of the "
                  "diagonal, %.0f disagreements per million, %zu bytes\n",
                  1 << k, runs.back().mrays, a.medianError / diagonal,
                  1e6 * double(a.disagreements) / primaryCount, runs.back().bytes);
      csv.row(name, "openvdb", 1 << k, 0, 32, 0, 0, 0, 0, runs.back().bytes, runs.back().mrays, 0, 0,
              0, 0, a.medianError / diagonal, a.p95Error / diagonal,
              1e6 * double(a.disagreements) / primaryCount, 0);
      // Our fastest point at least as accurate as this level set: the ratio at equal error.
      std::size_t match = allError.size();
      for (std::size_t i = 0; i < allError.size(); ++i)
        if (allError[i] * diagonal <= a.medianError && (match == allError.size() || allSpeed[i] > allSpeed[match]))
          match = i;
      if (match < allError.size())
        std::printf("    at this error our fastest: %.2f Mrays/s (%.2fx), %.0f bytes (%.1fx smaller)\n",
                    allSpeed[match], allSpeed[match] / runs.back().mrays, allBytes[match],
                    double(runs.back().bytes) / allBytes[match]);
      else
        std::printf("    at this error: none of our points is as accurate\n");
      const double setting = bytesOfSetting(leastMemory, a.medianError / diagonal);
      const double curve = bytesOnCurve(leastMemory, a.medianError / diagonal);
      if (std::isfinite(setting))
        std::printf("    at this error our smallest: %.0f bytes (%.1fx smaller); on our memory curve "
                    "%.0f bytes (%.1fx smaller)\n", setting, double(runs.back().bytes) / setting, curve,
                    double(runs.back().bytes) / curve);
    }
    if (std::isfinite(bestMatchedError)) {
      const LevelSetRun* byError = nullptr;
      for (const auto& r : runs)
        if (r.median > 0 && r.median <= bestMatchedError) {
          byError = &r;
          break;
        }
      const LevelSetRun* byMemory = &runs.front();
      for (const auto& r : runs)
        if (std::abs(std::log(double(r.bytes) / ourBytesAtBest)) <
            std::abs(std::log(double(byMemory->bytes) / ourBytesAtBest)))
          byMemory = &r;
      std::printf("  ours at <= 1 texel median error: %.2f Mrays/s (%.2fx Embree), %s bytes (Embree's "
                  "mesh + BVH / ours = %.1fx)\n",
                  ourSpeedAtBest, ourSpeedAtBest / embreeMraysPrimary,
                  std::to_string(std::size_t(ourBytesAtBest)).c_str(), double(embree.byteSize()) / ourBytesAtBest);
      if (byError)
        std::printf("  OpenVDB at matched error (voxel diagonal/%.0f): %.2f Mrays/s: ours is %.1fx faster, "
                    "%.1fx smaller\n", diagonal / byError->voxel, byError->mrays, ourSpeedAtBest / byError->mrays,
                    double(byError->bytes) / ourBytesAtBest);
      else
        std::printf("  OpenVDB at matched error: no voxel size down to diagonal/%.0f reached our error\n",
                    diagonal / runs.back().voxel);
      std::printf("  OpenVDB at matched memory (voxel diagonal/%.0f, %zu bytes): %.2f Mrays/s, median "
                  "error %.2e of the diagonal (ours %.2e)\n", diagonal / byMemory->voxel, byMemory->bytes,
                  byMemory->mrays, byMemory->median / diagonal, bestMatchedError / diagonal);
    }
  }
  // The figures, drawn from the CSV by matplotlib (apps/plots).
  const std::filesystem::path png = std::filesystem::path(options.out) / "trace_pareto.png";
  const std::filesystem::path memoryPng = std::filesystem::path(options.out) / "trace_memory.png";
  const bool plotted = app::drawPlot("plot_trace_pareto", csv.path(), png) &&
                       app::drawPlot("plot_trace_memory", csv.path(), memoryPng);
  std::printf("\nvs Emb = our rays per second / Embree's on the same rays and threads; memory = Embree's "
              "mesh + BVH bytes / ours (model + pyramid); med tx = median depth error in sample spacings "
              "(texels); dis/M = hit/miss disagreements with Embree per million rays. Embree is drawn at "
              "1e-7 (exact).\nwrote %s\n", csv.path().c_str());
  if (plotted) std::printf("plots: %s and %s\n", png.c_str(), memoryPng.c_str());
  return 0;
}

}  // namespace cellrelief::bench::trace_program
