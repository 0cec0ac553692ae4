#!/usr/bin/env python3
"""Plot of `welkin bench clouds`: the clouds' error against their frame cost.

    python3 scripts/plots/plot_bench_clouds.py bench_clouds.csv bench_clouds.png

Reads the bench's CSV (lines starting with '#' are comments; columns by header name: size, mode,
samples, reprojection, frame_ms, ratio_sky, rms_rel) and draws with matplotlib (Agg backend):
  * x: the clouds frame / the sky frame of the same size and run (default elements without
    clouds), log scale; the dashed vertical line is the issue's target (the clouds' own cost 2x
    the sky frame: the frame with clouds 3x);
  * y: relative RMS luminance error against the 512-sample reference, %, log scale;
  * one colour per frame size, filled markers with reprojection, open without, each labelled
    with its samples per ray; the time-running rows (no error: the camera moves) are drawn as
    stars on the x axis.
Exit status: 0 drawn, 2 bad arguments or CSV, 3 matplotlib missing.
"""
import argparse
import csv
import math
import sys

COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red"]


def read_rows(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(line for line in f if not line.lstrip().startswith("#"))
        required = {"size", "mode", "samples", "reprojection", "frame_ms", "ratio_sky", "rms_rel"}
        missing = required - set(reader.fieldnames or [])
        if missing:
            raise ValueError(f"{path}: missing columns {', '.join(sorted(missing))}")
        rows = []
        for n, rec in enumerate(reader, start=2):
            row = {"size": rec["size"], "mode": rec["mode"]}
            for key in ("samples", "reprojection", "frame_ms", "ratio_sky", "rms_rel"):
                text = rec[key]
                try:
                    row[key] = float(text) if text not in ("", None) else math.nan
                except ValueError:
                    raise ValueError(f"{path}: record {n}: column '{key}': '{text}' is not a number")
            rows.append(row)
        if not rows:
            raise ValueError(f"{path}: no rows")
        return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    args = ap.parse_args()
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.ticker import FuncFormatter
    except ImportError as e:
        print(f"plot_bench_clouds.py: matplotlib is missing ({e}); Debian: apt-get install python3-matplotlib", file=sys.stderr)
        return 3
    try:
        rows = read_rows(args.csv)
    except (OSError, ValueError) as e:
        print(f"plot_bench_clouds.py: {e}", file=sys.stderr)
        return 2
    sizes = []
    for r in rows:
        if r["size"] not in sizes:
            sizes.append(r["size"])
    fig, ax = plt.subplots(figsize=(7.5, 4.8), dpi=100)
    static = [r for r in rows if r["mode"] == "static" and math.isfinite(r["rms_rel"]) and r["rms_rel"] > 0]
    floor = min([r["rms_rel"] * 100 for r in static] or [0.1]) / 2
    for k, size in enumerate(sizes):
        colour = COLOURS[k % len(COLOURS)]
        for reproj in (0, 1):
            pts = sorted((r for r in static if r["size"] == size and int(r["reprojection"]) == reproj), key=lambda r: r["samples"])
            if not pts:
                continue
            xs = [r["ratio_sky"] for r in pts]
            ys = [r["rms_rel"] * 100 for r in pts]
            ax.plot(xs, ys, "-" if reproj else "--", color=colour, linewidth=1, alpha=0.6)
            ax.scatter(xs, ys, s=36, marker="o", facecolors=colour if reproj else "none", edgecolors=colour,
                       label=f"{size}, reprojection {'on' if reproj else 'off'}")
            for r, x, y in zip(pts, xs, ys):
                ax.annotate(f"{int(r['samples'])}", (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
        for r in rows:
            if r["mode"] == "moving" and r["size"] == size and math.isfinite(r["ratio_sky"]):
                ax.scatter([r["ratio_sky"]], [floor], s=90, marker="*", color=colour, label=f"{size}, moving, reprojection on")
    ax.axvline(3.0, color="grey", linestyle=":", linewidth=1)
    ax.text(3.0, ax.get_ylim()[1] if static else 1, " target: clouds 2x sky", fontsize=8, color="grey", va="top")
    ax.set_xscale("log")
    ax.set_yscale("log")
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(plain)
        axis.set_minor_formatter(plain)
    ax.tick_params(which="minor", labelsize=7)
    ax.set_xlabel("frame with clouds / sky frame of the same run")
    ax.set_ylabel("relative RMS luminance error vs 512 samples, %")
    ax.set_title("welkin bench clouds (numbers: samples per view ray)", fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(args.png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
