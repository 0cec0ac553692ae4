#!/usr/bin/env python3
"""Plots of `welkin bench all` (docs/BENCHMARKS.md).

    python3 scripts/plots/plot_bench_all.py bench_all_elements.csv bench_all_elements.png
    python3 scripts/plots/plot_bench_all.py bench_all_work.csv bench_all_work.png

The CSV's header says which plot (matplotlib, Agg backend):
  * element costs (columns element, size, still_ratio, running_ratio): one group of bars per
    element, one bar per frame size, time stopped (filled) and running at 600x (hatched); y: the
    element's cost per frame / a trivial fullscreen pass timed with it, log scale;
  * cost against work (columns series, unit, work, cost, cost_unit, exponent): one panel per kind
    of work, log-log, one line per element with its fitted growth exponent in the legend.
The PNG is written beside the target and renamed into place. Exit status: 0 drawn, 2 bad
arguments or CSV, 3 matplotlib missing.
"""
import csv
import os
import sys


def main():
    if len(sys.argv) != 3:
        print("usage: plot_bench_all.py CSV PNG", file=sys.stderr)
        return 2
    src, png = sys.argv[1], sys.argv[2]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is missing", file=sys.stderr)
        return 3
    with open(src, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.lstrip().startswith("#")))
    if not rows:
        print(f"{src}: no rows", file=sys.stderr)
        return 2
    cols = set(rows[0].keys())
    if {"element", "size", "still_ratio", "running_ratio"} <= cols:
        fig = plot_elements(plt, rows)
    elif {"series", "unit", "work", "cost", "cost_unit", "exponent"} <= cols:
        fig = plot_work(plt, rows)
    else:
        print(f"{src}: unknown columns {sorted(cols)}", file=sys.stderr)
        return 2
    tmp = os.path.join(os.path.dirname(os.path.abspath(png)), "." + os.path.basename(png) + ".tmp.png")
    fig.savefig(tmp, dpi=60)
    os.replace(tmp, png)
    return 0


def plot_elements(plt, rows):
    elements = list(dict.fromkeys(r["element"] for r in rows))
    sizes = list(dict.fromkeys(r["size"] for r in rows))
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    fig, ax = plt.subplots(figsize=(8.0, 4.2))
    width = 0.8 / (2 * len(sizes))
    for si, size in enumerate(sizes):
        for mode, (col, hatch) in enumerate((("still_ratio", None), ("running_ratio", "//"))):
            xs, ys = [], []
            for ei, e in enumerate(elements):
                for r in rows:
                    if r["element"] == e and r["size"] == size:
                        xs.append(ei - 0.4 + width * (2 * si + mode + 0.5))
                        ys.append(max(float(r[col]), 1e-3))
            label = f"{size}, " + ("time stopped" if mode == 0 else "time 600x")
            ax.bar(xs, ys, width, color=colours[si % len(colours)], hatch=hatch,
                   edgecolor="black", linewidth=0.3, label=label, alpha=1.0 if mode == 0 else 0.6)
    ax.set_yscale("log")
    ax.axhline(1.0, color="grey", linestyle=":", linewidth=1)
    ax.set_xticks(range(len(elements)))
    ax.set_xticklabels(elements, rotation=20)
    ax.set_ylabel("cost per frame / trivial pass (ratio)")
    ax.set_title("welkin bench all: each element's cost per frame")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def plot_work(plt, rows):
    units = list(dict.fromkeys(r["unit"] for r in rows))
    fig, axes = plt.subplots(1, len(units), figsize=(3.2 * len(units) + 0.8, 3.6), squeeze=False)
    for ax, unit in zip(axes[0], units):
        sub = [r for r in rows if r["unit"] == unit]
        for series in dict.fromkeys(r["series"] for r in sub):
            pts = sorted((float(r["work"]), float(r["cost"])) for r in sub if r["series"] == series)
            exp = sub[[r["series"] for r in sub].index(series)]["exponent"]
            try:
                label = f"{series} (exponent {float(exp):.2f})"
            except ValueError:
                label = series
            ax.plot([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], marker="o", markersize=3, label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(f"work ({unit})")
        ax.set_ylabel("cost per frame (" + sub[0]["cost_unit"] + ")")
        ax.legend(fontsize=6)
        ax.grid(True, which="both", linewidth=0.3)
    fig.suptitle("welkin bench all: cost against work, with the fitted growth exponent", fontsize=9)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    sys.exit(main())
