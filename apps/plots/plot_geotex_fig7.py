#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""bench_geotex's Fig. 7 (de Toledo, Wang, Levy 2008): frame time against image size, the geometry
textures ray cast by OpenGL from their rasterized boxes beside the full mesh rasterized by OpenGL,
one colour per mesh (solid: ray casting from the boxes, dotted: the same cast by a compute pass over
every pixel, dash-dot: Vulkan casting from the boxes, dashed: rasterizing); where the solid line lies
below its dashed one, ray casting wins.
Device time where the driver times frames, else the wall clock of a frame and its read-back.

    plot_geotex_fig7.py geotex_fig7.csv geotex_fig7.png
"""
from plotting import arguments, groups, plt, read_rows, save, style

csv_path, png_path = arguments("plot_geotex_fig7.py geotex_fig7.csv geotex_fig7.png")
rows = read_rows(csv_path)
# The device's timer where the driver times both (llvmpipe's reads 0 for the ray caster), else the
# wall clock (with read-back).
# Vulkan's column is 0 where the build or the machine has no Vulkan.
has_vulkan = all(r.get("vulkan_raycast_wall_s", 0) > 0 for r in rows)
by_device = all(r["raycast_device_s"] > 0 and r["compute_device_s"] > 0 and r["raster_device_s"] > 0 and
                (not has_vulkan or r["vulkan_raycast_device_s"] > 0) for r in rows)
cast_key, compute_key, vulkan_key, raster_key = (
    ("raycast_device_s", "compute_device_s", "vulkan_raycast_device_s", "raster_device_s") if by_device
    else ("raycast_wall_s", "compute_wall_s", "vulkan_raycast_wall_s", "raster_wall_s"))
figure, axis = plt.subplots(figsize=(10, 7), constrained_layout=True)
for i, ((mesh,), curve) in enumerate(groups(rows, "mesh")):
    colour, marker = style(i)
    pixels = [r["width"] * r["height"] for r in curve]
    triangles = int(curve[0]["triangles"])
    axis.plot(pixels, [1e3 * r[cast_key] for r in curve], color=colour, marker=marker, lw=1.6,
              label=f"{mesh}: geometry textures, ray cast from the boxes")
    axis.plot(pixels, [1e3 * r[compute_key] for r in curve], color=colour, lw=0.9, ls=":",
              label=f"{mesh}: the same, compute pass over every pixel")
    if has_vulkan:
        axis.plot(pixels, [1e3 * r[vulkan_key] for r in curve], color=colour, lw=0.9, ls="-.",
                  label=f"{mesh}: the same, Vulkan from the boxes")
    axis.plot(pixels, [1e3 * r[raster_key] for r in curve], color=colour, marker=marker, lw=1.2, ls="--",
              mfc="none", label=f"{mesh}: mesh rasterized ({triangles:,} triangles)")
sizes = groups(rows, "width", "height")
axis.set_xscale("log")
axis.set_yscale("log")
axis.set_xticks([w * h for (w, h), _ in sizes])
axis.set_xticklabels([f"{int(w)}x{int(h)}" for (w, h), _ in sizes], rotation=30, fontsize=8)
axis.minorticks_off()
axis.set_xlabel("image (pixels, log scale)")
axis.set_ylabel("frame time, device (ms)" if by_device else "frame time with read-back, wall clock (ms)")
axis.grid(True, which="both", alpha=0.3)
axis.legend(fontsize=6.5, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.2))  # below: the lines fill the axes
figure.suptitle("Fig. 7: geometry textures ray cast against the mesh rasterized by OpenGL (lower is better)", fontsize=10)
save(figure, png_path)
