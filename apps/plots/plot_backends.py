#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""bench_backends' primary rays per second, one group of bars per mesh, one bar per backend and
shader variant (Embree on the original mesh beside them).

    plot_backends.py backends.csv backends.png
"""
from plotting import arguments, groups, plt, read_rows, save, style

csv_path, png_path = arguments("plot_backends.py backends.csv backends.png")
rows = read_rows(csv_path)
meshes = [m for (m,), _ in groups(rows, "mesh")]
backends = [b for (b,), _ in groups(rows, "backend")]
width = 0.8 / len(backends)
figure, axis = plt.subplots(figsize=(max(7, 1.6 * len(meshes) * len(backends) ** 0.5), 5), constrained_layout=True)
for j, backend in enumerate(backends):
    xs, ys = [], []
    for i, mesh in enumerate(meshes):
        for r in rows:
            if r["mesh"] == mesh and r["backend"] == backend:
                xs.append(i - 0.4 + (j + 0.5) * width)
                ys.append(r["primary_mrays"])
    colour, _ = style(j)
    axis.bar(xs, ys, width=width, color=colour, label=backend)
axis.set_xticks(range(len(meshes)), meshes)
axis.set_yscale("log")
axis.set_ylabel("primary rays (Mrays/s)")
axis.set_xlabel("mesh")
axis.set_title("Primary rays per second on each backend (the same frame; higher is better)")
axis.grid(True, axis="y", which="both", alpha=0.3)
axis.legend(fontsize=8, ncol=2)
save(figure, png_path)
