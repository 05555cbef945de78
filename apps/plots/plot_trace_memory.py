#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""bench_trace's memory at equal error: bytes over the median depth error of every relief setting,
the least memory per error, and OpenVDB's level sets.

    plot_trace_memory.py trace.csv trace_memory.png
"""
from plotting import arguments, groups, pareto, plt, read_rows, save, style

csv_path, png_path = arguments("plot_trace_memory.py trace.csv trace_memory.png")
rows = read_rows(csv_path)
figure, axis = plt.subplots(figsize=(9, 6), constrained_layout=True)
for i, ((mesh,), mesh_rows) in enumerate(groups(rows, "mesh")):
    colour, _ = style(i)
    relief = [(r["median_error_diag"], r["bytes"]) for r in mesh_rows if r["method"] == "relief"]
    if relief:
        axis.scatter(*zip(*relief), s=12, color=colour, alpha=0.35, label=f"{mesh}: relief settings")
        axis.plot(*zip(*pareto(relief, min, min)), color=colour, lw=2, label=f"{mesh}: relief, least memory")
    vdb = sorted((r["median_error_diag"], r["bytes"]) for r in mesh_rows if r["method"] == "openvdb")
    if vdb:
        axis.plot(*zip(*vdb), color=colour, ls="--", marker="s", ms=5, label=f"{mesh}: OpenVDB level sets")
axis.set_xscale("log")
axis.set_yscale("log")
axis.set_xlabel("median depth error / bounding-box diagonal")
axis.set_ylabel("bytes (model + acceleration; level set: its tree)")
axis.set_title("Memory at equal error: relief models against OpenVDB level sets (lower is better)")
axis.grid(True, which="both", alpha=0.3)
axis.legend(fontsize=7, ncol=2)
save(figure, png_path)
