#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""compare-optimizers' convergence: L2 stretch of the map as it stands over optimizer time, one
panel per height map, one curve per optimizer (the paper's springs among them).

    plot_convergence.py indirection_convergence.csv indirection_convergence.png
"""
from plotting import arguments, groups, plt, read_rows, save, style

csv_path, png_path = arguments("plot_convergence.py indirection_convergence.csv indirection_convergence.png")
rows = read_rows(csv_path)
maps = groups(rows, "heightmap")
optimizers = [o for (o,), _ in groups(rows, "optimizer")]
figure, axes = plt.subplots(1, len(maps), figsize=(5 * len(maps), 4.2), constrained_layout=True, squeeze=False)
for axis, ((name,), map_rows) in zip(axes[0], maps):
    best = min(r["l2_stretch"] for r in map_rows)
    for (optimizer,), curve in groups(map_rows, "optimizer"):
        colour, marker = style(optimizers.index(optimizer))
        seconds = [max(r["seconds"], 1e-4) for r in curve]  # the identity at t = 0 on the log axis
        axis.plot(seconds, [r["l2_stretch"] - 1 for r in curve], color=colour, marker=marker, ms=3, lw=1.2,
                  label=optimizer)
    axis.axhline((best - 1) * 1.01, color="grey", ls=":", lw=1, label="within 1% of the best")
    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set_xlabel("optimizer time (s)")
    axis.set_ylabel("L2 stretch - 1 (per texel)")
    axis.set_title(str(name))
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=7)
figure.suptitle("Convergence of the indirection optimizers (lower is better)")
save(figure, png_path)
