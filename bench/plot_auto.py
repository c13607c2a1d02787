#!/usr/bin/env python3
"""Plots the JSON of pnf_eval_auto: RMS normal error per case for the input, the paper's
setting, the best of the grid and --auto (docs/auto.md).

    ./build/bench/pnf_eval_auto --json auto.json
    python3 bench/plot_auto.py auto.json docs/auto.png

Needs python3-matplotlib (Debian package).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The targets for fandisk with PCA-112 input normals, by noise level.
FANDISK_TARGETS = {"0%": 5.6, "0.125%": 7.4, "0.6%": 14.4, "1.2%": 22.6}
SERIES = [("input", "input", "#bbbbbb"), ("paper", "paper 4/0.5/4", "#e08050"),
          ("best", "best of grid", "#5080c0"), ("auto", "--auto", "#40a040")]


def panel(ax, cases, title, targets=None):
    width = 0.2
    xs = range(len(cases))
    for k, (key, label, colour) in enumerate(SERIES):
        ax.bar([x + (k - 1.5) * width for x in xs], [c[key] for c in cases], width, label=label, color=colour)
    if targets:
        for x, c in zip(xs, cases):
            if c["noise"] in targets:
                ax.plot([x - 0.45, x + 0.45], [targets[c["noise"]]] * 2, "k--", lw=1)
    ax.set_xticks(list(xs))
    ax.set_xticklabels([c["name"] for c in cases], rotation=60, ha="right", fontsize=7)
    ax.set_ylabel("RMS angle to truth (deg)")
    ax.set_title(title, fontsize=9)
    ax.grid(axis="y", alpha=0.3)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_auto.py EVAL.json OUT.png")
    with open(sys.argv[1]) as f:
        cases = json.load(f)["cases"]
    synthetic = [c for c in cases if c["family"] == "synthetic" and "jitter" not in c["name"]]
    jittered = [c for c in cases if c["family"] == "synthetic" and "jitter" in c["name"]]
    fandisk = [c for c in cases if c["family"] == "fandisk"]
    top = [p for p in (synthetic, fandisk) if p]
    rows = [top] + ([[jittered]] if jittered else [])
    fig = plt.figure(figsize=(11, 4 * len(rows)), dpi=90)
    grid = fig.add_gridspec(len(rows), 1)
    axes = []
    for r, panels in enumerate(rows):
        sub = grid[r].subgridspec(1, len(panels), width_ratios=[max(len(p), 3) for p in panels])
        for k, p in enumerate(panels):
            ax = fig.add_subplot(sub[0, k])
            axes.append(ax)
            if p is fandisk:
                panel(ax, p, "fandisk (- - target)", FANDISK_TARGETS)
            elif p is jittered:
                panel(ax, p, "synthetic shapes, true normals tilted at random (4 and 12 deg RMS)")
            else:
                panel(ax, p, "synthetic shapes, 20k points (noise in spacings, PCA neighbours)")
    axes = [axes]
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(sys.argv[2])


if __name__ == "__main__":
    main()
