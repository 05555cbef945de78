#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The tour of docs/python.md, step by step: convert a mesh, render it on two backends, show both
with matplotlib, trace rays from NumPy, and compute an indirection map.

    PYTHONPATH=build/release/python python3 apps/python/examples/tour.py ../shared/data out/tour
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt
import numpy as np

import cellrelief as cr

data = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/data")
out = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else "out/tour")
out.mkdir(parents=True, exist_ok=True)

# 1. A mesh (or cr.Mesh(vertices, faces) from arrays) to a relief model, with a progress bar.
mesh = cr.read_mesh(data / "meshes/small/spot__common-3d-test-models.obj")
print(mesh, "bounds", mesh.bounds().tolist())
model, report = cr.convert(mesh, grid=8, report=True,
                           progress=lambda f: print(f"\r  converting {f:4.0%}", end="", flush=True) if sys.stdout.isatty() else None)
print(f"\n{model}: {report['grey_cells']} grey cells in {report['seconds']:.2f} s")
model.save(out / "spot.crm")

# 2. The same scene on the CPU reference and on a GPU backend (OpenGL or Vulkan where one runs).
scene = cr.Scene()
scene.add(cr.load_model(out / "spot.crm"))
low, high = mesh.bounds()
centre = (low + high) / 2
camera = cr.Camera(eye=centre + np.array([1.7, 1.1, 2.9]), target=centre, fov=40)
gpu = next((b["name"] for b in cr.backends() if b["name"] != "cpu" and b["available"]), "cpu")
frames = {name: cr.render(scene, camera, backend=name, width=320, height=240) for name in ("cpu", gpu)}
for name, frame in frames.items():
    print(f"{name:7s} {frame.mask.sum()} pixels hit, depth {frame.depth[frame.mask].min():.3f} to "
          f"{frame.depth[frame.mask].max():.3f}")
mask_difference = int((frames["cpu"].mask != frames[gpu].mask).sum())
print(f"cpu and {gpu} differ in {mask_difference} pixels of the mask")

# 3. Both with matplotlib, and the depth buffer.
figure, axes = plt.subplots(1, 3, figsize=(12, 3.4), constrained_layout=True)
for axis, name in zip(axes, ("cpu", gpu)):
    axis.imshow(frames[name].color)
    axis.set_title(f"{name} backend")
    axis.axis("off")
depth = np.where(frames["cpu"].mask, frames["cpu"].depth, np.nan)
image = axes[2].imshow(depth, cmap="viridis")
axes[2].set_title("depth (world units)")
axes[2].axis("off")
figure.colorbar(image, ax=axes[2], shrink=0.8)
figure.savefig(out / "tour_backends.png", dpi=100)

# 4. Rays from NumPy: 10,000 rays at the mesh's centre from a sphere around it.
radius = np.linalg.norm(high - low)
rng = np.random.default_rng(1)
directions = rng.normal(size=(10000, 3))
directions /= np.linalg.norm(directions, axis=1, keepdims=True)
hits = cr.trace(scene, centre - radius * directions, directions)
print(f"rays: {hits['hit'].mean():.1%} hit, distance to the surface {np.median(radius - hits['t'][hits['hit']]):.3f} "
      f"(median), {len(np.unique(hits['cell'][hits['hit']]))} cells hit")

# 5. An indirection map of a height map, and its two channels.
I, r = cr.indirection_map(data / "heightmaps/sponza/lion_bump.png", grid=64, report=True)
print(f"indirection map {I.shape}: L2 stretch {r['l2_stretch_before']:.4f} -> {r['l2_stretch']:.4f}")
figure, axes = plt.subplots(1, 2, figsize=(8, 3.6), constrained_layout=True)
for c, axis in enumerate(axes):
    image = axis.imshow(I[:, :, c], cmap="coolwarm")
    axis.set_title(f"I_{'uv'[c]} (texture units)")
    axis.axis("off")
    figure.colorbar(image, ax=axis, shrink=0.8)
figure.savefig(out / "tour_indirection.png", dpi=100)
print("wrote", out / "tour_backends.png", "and", out / "tour_indirection.png")
