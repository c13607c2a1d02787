#!/usr/bin/python3
"""Plots the size sweep of a pnf_bench JSON file: time per pass and neighbour-list build time
against the number of points, for every variant; writes a PNG.

    /usr/bin/python3 bench/plot_bench.py docs/bench.json docs/bench_sweep.png

Uses Debian's python3-matplotlib (hence /usr/bin/python3, not a virtualenv's python)."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source, target):
    with open(source) as f:
        data = json.load(f)
    rows = [r for r in data["results"] if r["workload"].startswith("sweep-")]
    if not rows:
        sys.exit(f"{source}: no sweep-* workloads to plot")
    fig, (time_ax, rate_ax) = plt.subplots(1, 2, figsize=(10, 4))
    for variant in sorted({r["variant"] for r in rows}):
        mine = sorted((r for r in rows if r["variant"] == variant), key=lambda r: r["points"])
        points = [r["points"] for r in mine]
        time_ax.plot(points, [r["pass_s"] for r in mine], "o-", label=f"{variant}: one pass")
        rate_ax.plot(points, [r["mpairs_per_s"] for r in mine], "o-", label=variant)
        if variant == "opencl":
            time_ax.plot(points, [r["list_build_s"] for r in mine], "s--", label="neighbour lists (once)")
    time_ax.set(xscale="log", yscale="log", xlabel="points", ylabel="seconds",
                title="cost grows linearly with the points")
    rate_ax.set(xscale="log", xlabel="points", ylabel="million neighbour pairs / s",
                title=f"throughput ({data['flops_per_pair']:.0f} flop per pair)")
    for ax in (time_ax, rate_ax):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    device = rows[0]["device"].split("'")[1] if "'" in rows[0]["device"] else rows[0]["device"]
    fig.suptitle(f"pnf size sweep, sigma_f 4 mean radii, ~200 neighbours a point - {device}, {data['date'][:10]}",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(target, dpi=80)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_bench.py BENCH.json OUT.png")
    main(sys.argv[1], sys.argv[2])
