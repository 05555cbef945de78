// SPDX-License-Identifier: MIT
/// @file command_polycube.cpp
/// `cellrelief polycube <mesh> -o <dir> [--grid N|auto] [--cubes FILE] [--energy E] [--signal S]`:
/// the polycube texture domain of a mesh (PolyCube-Maps), built automatically or read from a cube
/// file, checked (closed 2-manifold, one piece, the mesh's genus), the mesh's map onto it (3D
/// texture positions, without flipped triangles) and its distortion, and a signal baked into T2.
/// Written: the cube file, its surface coloured by vertex case (PLY) and a picture of that, the
/// mesh with its texture positions (OBJ), the distortion table (CSV), T2 (PNG, every mip level)
/// and the mesh rendered with it by the CPU reference (with the normals signal, a decimation of
/// the mesh too, textured through the same map). Nothing is written unless every step succeeds.
#include <cstdio>
#include <memory>

#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/levels_of_detail.h>
#include <cellrelief/polycube/mesh_map.h>
#include <cellrelief/polycube/polycube_file.h>
#include <cellrelief/polycube/polycube_result.h>

#include "commands.h"
#include "preview.h"

namespace cellrelief::app {

namespace {

struct PolycubeCommandOptions {
  std::string mesh, output, grid = "auto", cubes, energy = "extended-mips", signal = "grid";
  int sweeps = 400;
  int coarse = 3000;
  int texels = 16;
  bool removeCase6b = false;
};

/// The mesh signal --signal names; nothing for the grid. Checked before any work is done.
std::optional<polycube::MeshSignalKind> parseSignal(const PolycubeCommandOptions& o, const TriangleMesh& mesh) {
  const std::optional<polycube::MeshSignalKind> kind = polycube::parseSignal(o.signal, "--signal");
  if (kind == polycube::MeshSignalKind::Color && !mesh.hasColors())
    throw Error(ErrorKind::InvalidInput, o.mesh, "--signal color: the mesh has no vertex colours");
  return kind;
}

/// The mesh textured through its map, rendered by the CPU reference from the preview's view.
Image<std::uint8_t> renderTextured(const TriangleMesh& mesh, std::span<const Vec3d> texture,
                                   std::shared_ptr<const polycube::PolycubeTexture> t2, polycube::TextureUse use) {
  auto textured = std::make_shared<polycube::TexturedMesh>();
  textured->mesh = mesh;
  textured->texture.assign(texture.begin(), texture.end());
  textured->t2 = std::move(t2);
  textured->use = use;
  render::Scene scene;
  scene.polycubeMeshes.push_back(textured);
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  const Aabbd bounds = scene.boundsWS();
  render::RenderOptions options;
  options.width = options.height = 800;
  options.channels = render::kColor;
  return cpu.renderFrame(render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), 35, 25), options).color;
}

/// One colour per vertex case, as in the paper's Fig. 11 (cases 3 to 6b).
constexpr Color8 kVertexCaseColours[polycube::kVertexCaseCount] = {
    {234, 67, 53, 255}, {200, 200, 200, 255}, {66, 133, 244, 255},
    {251, 188, 5, 255}, {52, 168, 83, 255},   {171, 71, 188, 255}};

/// The surface with each lattice vertex coloured by its case.
TriangleMesh surfaceByCase(const polycube::Polycube& p, const polycube::PolycubeFrame& frame) {
  // Built in lattice units, where its positions are the vertices' exact integer coordinates.
  TriangleMesh mesh = p.surfaceMesh();
  mesh.colors.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const auto& info = polycube::kVertexConfigurations[p.vertexConfiguration(Vec3i(mesh.positions[v]))];
    mesh.colors[v] = kVertexCaseColours[static_cast<int>(info.vertexCase)];
    mesh.positions[v] = Vec3f(frame.origin + frame.cubeSize * Vec3d(mesh.positions[v]));
  }
  mesh.sourcePolygons = mesh.triangles.size();
  return mesh;
}

/// The mesh coloured by where the map puts each vertex: the hue says which way the polycube's
/// face there looks (x red, y green, z blue; darker when it looks the negative way), and a
/// checker of half cubes (squarelets) in texture space shows how the map stretches. A smooth checker
/// without folds or jumps on the mesh is a good map.
TriangleMesh meshByTexture(const TriangleMesh& mesh, std::span<const Vec3d> texture,
                           const polycube::PolycubeSurface& surface) {
  TriangleMesh out = mesh;
  out.colors.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3d n = surface.normal(texture[v]);
    const int axis = std::abs(n.x) >= std::abs(n.y) && std::abs(n.x) >= std::abs(n.z) ? 0 : std::abs(n.y) >= std::abs(n.z) ? 1 : 2;
    const Vec3i cell(glm::floor(2.0 * texture[v]));
    const bool odd = ((cell.x + cell.y + cell.z) & 1) != 0;
    const double level = (n[axis] > 0 ? 1.0 : 0.6) * (odd ? 1.0 : 0.55);
    Vec3d rgb(0.25);
    rgb[axis] = 1.0;
    rgb *= 255.0 * level;
    out.colors[v] = Color8{std::uint8_t(rgb.x), std::uint8_t(rgb.y), std::uint8_t(rgb.z), 255};
  }
  return out;
}

/// The paper's Table 1 columns for this map, before and after optimization.
void writeDistortionTable(const PolycubeCommandOptions& o, const TriangleMesh& mesh, const polycube::Polycube& cubes,
                          const polycube::PolycubeParameterization& map, const std::filesystem::path& path) {
  io::writeTextAtomically(path, [&](std::ostream& out) {
    out << "mesh,triangles,cubes,energy,stage,area_distortion,angle_distortion,stretch_efficiency,flipped,sweeps,"
           "seconds\n";
    const std::string name = std::filesystem::path(o.mesh).filename().string();
    const auto row = [&](const char* stage, const polycube::Distortion& d, int sweeps, double seconds) {
      out << name << ',' << mesh.triangleCount() << ',' << cubes.size() << ',' << o.energy << ',' << stage << ','
          << d.area << ',' << d.angle << ',' << d.stretchEfficiency << ',' << d.flipped << ',' << sweeps << ','
          << seconds << '\n';
    };
    row("start", map.initial, 0, 0.0);
    row("optimized", map.final, map.sweeps, map.seconds);
  });
}

int runPolycube(const PolycubeCommandOptions& o) {
  if (o.removeCase6b && !o.cubes.empty())
    throw Error(ErrorKind::InvalidArgument, "--remove-case-6b changes an automatic polycube only, not a --cubes file");
  const TriangleMesh mesh = io::readMesh(o.mesh);
  std::printf("mesh          %s: %zu triangles\n", o.mesh.c_str(), mesh.triangleCount());
  polycube::PolycubeDomain domain;
  if (!o.cubes.empty()) {
    domain = polycube::givenDomain(mesh, polycube::readPolycube(o.cubes), o.cubes);
    std::printf("polycube      %s: %zu cubes\n", o.cubes.c_str(), domain.polycube.size());
  } else {
    polycube::PolycubeOptions options;
    options.cubesPerSide = parseGridSize(o.grid);
    options.removeCase6b = o.removeCase6b;
    domain = withPath(o.mesh, [&] { return polycube::automaticDomain(mesh, options); });
    for (const polycube::PolycubeTrial& t : domain.search->trials)
      std::printf("lattice       N = %3d: %5zu cubes (%zu added for manifoldness, %zu toggled for case 6b), %zu "
                  "case-6b vertices, %s\n",
                  t.cubesPerSide, t.cubes, t.addedForManifold, t.case6bToggled, t.case6bLeft,
                  t.genus ? ("genus " + std::to_string(*t.genus)).c_str() : "not a closed manifold");
    std::printf("chosen        N = %d, %.2f s\n", domain.search->cubesPerSide, domain.search->seconds);
  }
  const polycube::Polycube& cubes = domain.polycube;
  const polycube::PolycubeFrame& frame = domain.frame;
  const std::optional<int>& meshGenus = domain.meshGenus;
  const polycube::SurfaceStats s = cubes.surfaceStats();
  std::printf("surface       %zu faces, %zu vertices, genus %d (mesh: %s)\n", s.faces, s.vertices, s.genus().value_or(-1),
              meshGenus ? std::to_string(*meshGenus).c_str() : "unknown: not one manifold piece");
  std::printf("vertex cases ");
  for (int c = 0; c < polycube::kVertexCaseCount; ++c)
    std::printf(" %s: %zu", polycube::kVertexCaseNames[c].data(), s.perCase[c]);
  std::printf("\n");

  const std::optional<polycube::PolycubeEnergy> energy = polycube::parsePolycubeEnergy(o.energy);
  if (!energy) throw Error(ErrorKind::InvalidArgument, "--energy: '" + o.energy + "' is not mvc, mips or extended-mips");
  const std::optional<polycube::MeshSignalKind> signalKind = parseSignal(o, mesh);
  const auto sharedDomain = withPath(o.cubes.empty() ? o.mesh : o.cubes, [&] {
    return std::make_shared<const polycube::PolycubeSurface>(cubes);
  });
  const polycube::PolycubeSurface& surface = *sharedDomain;
  polycube::ParameterizationOptions mapOptions;
  mapOptions.energy = *energy;
  mapOptions.maxSweeps = o.sweeps;
  mapOptions.coarseVertices = std::size_t(o.coarse);
  mapOptions.progress = [](int sweep, const polycube::Distortion& d) {
    if (sweep % 50 == 0)
      std::printf("  sweep %4d   area %.4f, angle %.4f, stretch efficiency %.3f, %zu flipped\n", sweep, d.area, d.angle,
                  d.stretchEfficiency, d.flipped);
  };
  const polycube::PolycubeParameterization map =
      withPath(o.mesh, [&] { return polycube::parameterize(mesh, surface, frame, mapOptions); });
  if (map.coarseVertices > 0)
    std::printf("map           started from its decimation to %zu vertices (%d sweeps)\n", map.coarseVertices,
                map.coarseSweeps);
  std::printf("map           %s, %d sweeps, %.2f s\n", o.energy.c_str(), map.sweeps, map.seconds);
  std::printf("distortion    %-9s %8s %8s %10s %8s\n", "", "area", "angle", "stretch", "flipped");
  for (const auto& [name, d] : {std::pair{"start", map.initial}, std::pair{"optimized", map.final}})
    std::printf("              %-9s %8.4f %8.4f %10.3f %8zu\n", name, d.area, d.angle, d.stretchEfficiency, d.flipped);
  polycube::requireUnfolded(map, mesh, o.mesh,
                            "try another --grid or --coarse, more --sweeps or a polycube of your own (--cubes)");

  const auto t2 = std::make_shared<const polycube::PolycubeTexture>(
      withPath(o.mesh, [&] {
        return polycube::bakeSignal(mesh, map.texture, sharedDomain, signalKind, o.texels);
      }));
  std::printf("T2            %s, %d texels per squarelet, %u squarelets, %d x %d texels with %d mip levels (%.1f MB)\n",
              o.signal.c_str(), o.texels, surface.lut().tileCount(), t2->atlas().width(), t2->atlas().height(),
              t2->levelCount(), t2->byteSize() / 1e6);
  const polycube::TextureUse use = polycube::textureUseOf(signalKind);
  const Image<std::uint8_t> picture = renderTextured(mesh, map.texture, t2, use);
  Image<std::uint8_t> coarsePicture;
  if (use == polycube::TextureUse::Normal) {
    // One map, several levels of detail: a decimation takes its texture positions from the
    // nearest points of the mesh and shows the full mesh's normals.
    const TriangleMesh coarse = polycube::decimate(mesh, std::max<std::size_t>(200, mesh.positions.size() / 10));
    const std::vector<Vec3d> coarseTexture = polycube::transferTexturePositions(
        polycube::latticePositions(mesh, frame), mesh.triangles, map.texture,
        polycube::latticePositions(coarse, frame), surface);
    coarsePicture = renderTextured(coarse, coarseTexture, t2, use);
    std::printf("level of detail %zu of %zu triangles, textured through the same map\n", coarse.triangleCount(),
                mesh.triangleCount());
  }

  const std::filesystem::path dir(o.output);
  std::filesystem::create_directories(dir);
  polycube::writePolycubeResult(dir, cubes, frame, mesh, map.texture, *t2, use);
  const TriangleMesh casesMesh = surfaceByCase(cubes, frame);
  io::writeMesh(casesMesh, dir / "polycube_surface.ply");
  writePreview(casesMesh, dir / "polycube_cases.png");
  writePreview(meshByTexture(mesh, map.texture, surface), dir / "polycube_map.png");
  writeDistortionTable(o, mesh, cubes, map, dir / "distortion.csv");
  io::writePng(picture, dir / "polycube_render.png");
  if (!coarsePicture.isEmpty()) io::writePng(coarsePicture, dir / "polycube_render_lod.png");
  std::printf("wrote         %s: polycube.txt, polycube_surface.ply, polycube_cases.png (vertices coloured by "
              "case: 3 red, 4a grey, 4b blue, 5 yellow, 6a green, 6b purple), mesh_texture.obj (vt: texture "
              "positions in lattice coordinates), polycube_map.png (the mesh coloured by its map: hue by the face's "
              "direction, a checker of squarelets), distortion.csv, polycube_texture.png (T2: a tile per squarelet with a "
              "border, mip levels below) and .txt (what it holds), polycube_render.png (the CPU reference's render)%s\n", dir.string().c_str(),
              coarsePicture.isEmpty() ? "" : ", polycube_render_lod.png (a decimation, the same map and T2)");
  return 0;
}

}  // namespace

Command addPolycubeCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "polycube", "The polycube texture domain of a mesh (PolyCube-Maps): built automatically or read from a cube file");
  auto o = std::make_shared<PolycubeCommandOptions>();
  cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .off .stl)")->required();
  cmd->add_option("-o,--output", o->output, "Folder to write the polycube into")->required();
  cmd->add_option("--grid", o->grid,
                  "Cubes along the mesh's bounding cube, or 'auto': the coarsest lattice whose polycube keeps the "
                  "mesh's genus")
      ->capture_default_str();
  cmd->add_option("--cubes", o->cubes,
                  "Use this polycube instead: a text file of integer cube coordinates 'x y z', one per line, "
                  "optionally a line 'frame x y z size' placing the lattice in world space")
      ->check(CLI::ExistingFile);
  cmd->add_option("--energy", o->energy,
                  "What the map's optimization lowers: extended-mips (angles and areas, Degener et al., theta = 3), "
                  "mips (angles only) or mvc (mean value coordinates)")
      ->capture_default_str();
  cmd->add_option("--sweeps", o->sweeps, "Most optimization sweeps over the vertices")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--coarse", o->coarse,
                  "A mesh of more than twice this many vertices starts from the map of its decimation to this "
                  "many (0: from the projection along the normals); a thin part the decimation cannot hold "
                  "folds there and stays folded")
      ->check(CLI::Range(0, 100000000))
      ->capture_default_str();
  cmd->add_option("--signal", o->signal,
                  "What T2 holds: grid (the paper's pattern), normals (the mesh's, which a renderer shades with), "
                  "shading or color (the mesh's vertex colours)")
      ->capture_default_str();
  cmd->add_flag("--remove-case-6b", o->removeCase6b,
               "Toggle cubes of the automatic polycube to remove its vertices of case 6b, whose projection "
               "stretches the most (off: the toggled cubes usually cost the map more)");
  cmd->add_option("--texels", o->texels, "Texels per squarelet side (S), a power of two")
      ->check(CLI::IsMember({1, 2, 4, 8, 16, 32, 64, 128, 256}))
      ->capture_default_str();
  return {cmd, [o]() { return runPolycube(*o); }};
}

}  // namespace cellrelief::app
