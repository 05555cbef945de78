#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""bench_trace's run time against error: primary rays per second over the median depth error of
every relief setting (the SIMD packet tracer's marked), its Pareto front, OpenVDB's level sets and Embree (exact, drawn at 1e-7).

    plot_trace_pareto.py trace.csv trace_pareto.png
"""
from plotting import arguments, groups, pareto, plt, read_rows, save, style

EXACT = 1e-7  # where Embree's zero error is drawn on the log axis
csv_path, png_path = arguments("plot_trace_pareto.py trace.csv trace_pareto.png")
rows = read_rows(csv_path)
figure, axis = plt.subplots(figsize=(9, 6), constrained_layout=True)
for i, ((mesh,), mesh_rows) in enumerate(groups(rows, "mesh")):
    colour, _ = style(i)
    relief = [(r["median_error_diag"], r["primary_mrays"]) for r in mesh_rows if r["method"] == "relief"]
    if relief:
        axis.scatter(*zip(*relief), s=12, color=colour, alpha=0.35, label=f"{mesh}: relief settings")
        axis.plot(*zip(*pareto(relief)), color=colour, lw=2, label=f"{mesh}: relief, Pareto front")
    # skip 3: the SIMD packet tracer (bench_trace.cpp), also part of the relief settings above
    packets = [(r["median_error_diag"], r["primary_mrays"]) for r in mesh_rows
               if r["method"] == "relief" and int(r["skip"]) == 3]
    if packets:
        axis.scatter(*zip(*packets), s=22, marker="D", facecolor="none", edgecolor=colour,
                     label=f"{mesh}: relief, SIMD packets")
    vdb = sorted((r["median_error_diag"], r["primary_mrays"]) for r in mesh_rows if r["method"] == "openvdb")
    if vdb:
        axis.plot(*zip(*vdb), color=colour, ls="--", marker="s", ms=5, label=f"{mesh}: OpenVDB level sets")
    embree = [r["primary_mrays"] for r in mesh_rows if r["method"] == "embree"]
    if embree:
        axis.scatter([EXACT], embree, color=colour, marker="*", s=140, edgecolor="black", linewidth=0.5,
                     label=f"{mesh}: Embree (exact, at 1e-7)")
axis.set_xscale("log")
axis.set_yscale("log")
axis.set_xlabel("median depth error / bounding-box diagonal")
axis.set_ylabel("primary rays (Mrays/s)")
axis.set_title("Relief ray casting against Embree and OpenVDB level sets (higher and further left is better)")
axis.grid(True, which="both", alpha=0.3)
axis.legend(fontsize=7, ncol=2)
save(figure, png_path)
