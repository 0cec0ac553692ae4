#!/usr/bin/env python3
"""Plot of `welkin bench sky`: luminance error against frame cost, one colour per quality preset.

    python3 scripts/plots/plot_bench_sky.py bench_sky.csv bench_sky.png [--min-sun-alt -10]

Reads the bench's CSV (lines starting with '#' are comments; columns by header name: preset,
wavelengths, sun_alt_deg, ratio_1280x720, ratio_512x256, rms_rel, max_rel, frame_1280x720_ms,
frame_512x256_ms) and draws with matplotlib (Agg backend, no display needed):
  * x: frame time / trivial fullscreen pass of the same size (log scale), at 1280x720, or at
    512x256 for rows without a 1280x720 frame (the `reference` preset unless --full);
  * y: relative RMS luminance error, % (log scale), one marker per Sun altitude;
  * dashed lines: the accuracy targets (high <= 2 % RMS, medium <= 4 % RMS, Sun >= -4 deg).
Rows without an error (a --timing-only run) are drawn as frame time (ms) against Sun altitude.
Exit status: 0 drawn, 2 bad arguments or CSV, 3 matplotlib missing.
"""
import argparse
import csv
import math
import sys

PRESETS = {0: "low", 1: "medium", 2: "high", 3: "reference"}
COLOURS = {0: "tab:green", 1: "tab:blue", 2: "tab:orange", 3: "tab:red"}
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]


def read_rows(path):
    """Rows of the CSV as dicts of floats (empty or 'nan' -> NaN)."""
    with open(path, newline="") as f:
        reader = csv.DictReader(line for line in f if not line.lstrip().startswith("#"))
        required = {"preset", "wavelengths", "sun_alt_deg", "ratio_1280x720", "ratio_512x256", "rms_rel"}
        missing = required - set(reader.fieldnames or [])
        if missing:
            raise ValueError(f"{path}: missing columns {', '.join(sorted(missing))}")
        rows = []
        for n, rec in enumerate(reader, start=2):
            row = {}
            for key, text in rec.items():
                try:
                    row[key] = float(text) if text not in ("", None) else math.nan
                except ValueError:
                    raise ValueError(f"{path}: record {n}: column '{key}': '{text}' is not a number")
            rows.append(row)
        return rows


def nice_log_ticks(lo, hi):
    """At least 3 round values in [lo, hi] for a log axis: decades, else 1-2-5, else finer."""
    for mantissas in ((1,), (1, 2, 5), (1, 1.5, 2, 3, 5, 7), (1, 1.2, 1.4, 1.6, 1.8, 2, 2.5, 3, 3.5, 4, 5, 6, 7, 8, 9)):
        ticks = [m * 10.0**e for e in range(-3, 7) for m in mantissas if lo <= m * 10.0**e <= hi]
        if len(ticks) >= 3:
            return ticks
    return None


def label(preset, wavelengths, spectral_runs):
    name = PRESETS.get(int(preset), f"preset {int(preset)}")
    if spectral_runs:
        name += " RGB" if int(wavelengths) == 3 else f" {int(wavelengths)} λ"
    return name


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--min-sun-alt", type=float, default=-10.0, help="lowest Sun altitude drawn, degrees (default -10)")
    args = ap.parse_args()
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.lines import Line2D
        from matplotlib.ticker import FuncFormatter, NullFormatter
    except ImportError as e:
        print(f"plot_bench_sky.py: matplotlib is missing ({e}); Debian: apt-get install python3-matplotlib", file=sys.stderr)
        return 3
    try:
        rows = read_rows(args.csv)
    except (OSError, ValueError) as e:
        print(f"plot_bench_sky.py: {e}", file=sys.stderr)
        return 2
    if not rows:
        print(f"plot_bench_sky.py: {args.csv}: no data rows", file=sys.stderr)
        return 2

    groups = {}
    for r in rows:
        groups.setdefault((int(r["preset"]), int(r["wavelengths"])), []).append(r)
    spectral_runs = len({w for _, w in groups}) > 1
    has_error = any(math.isfinite(r["rms_rel"]) for r in rows)

    fig, ax = plt.subplots(figsize=(8.5, 5.0), dpi=100)
    if has_error:
        alts = sorted({r["sun_alt_deg"] for r in rows if r["sun_alt_deg"] >= args.min_sun_alt}, reverse=True)
        marker_of = {a: MARKERS[i % len(MARKERS)] for i, a in enumerate(alts)}
        small_only = set()
        for (preset, wl), grp in sorted(groups.items()):
            pts = []
            for r in sorted(grp, key=lambda r: -r["sun_alt_deg"]):
                if r["sun_alt_deg"] < args.min_sun_alt or not math.isfinite(r["rms_rel"]):
                    continue
                x = r["ratio_1280x720"]
                if not math.isfinite(x):
                    x = r["ratio_512x256"]
                    small_only.add(preset)
                if not math.isfinite(x):
                    continue
                pts.append((x, 100.0 * r["rms_rel"], r["sun_alt_deg"]))
            colour = COLOURS.get(preset, "black")
            face = "none" if spectral_runs and wl != 3 else colour
            for x, y, alt in pts:
                ax.scatter(x, y, marker=marker_of[alt], s=46, facecolors=face, edgecolors=colour, linewidths=1.3, zorder=3)
        ax.set_xscale("log")
        ax.set_yscale("log")
        # Plain numbers on both log axes (x: ×2, ×10, ×100 ... or finer on a narrow range; y: 1, 2, 5, 10 ...).
        ticks = nice_log_ticks(*ax.get_xlim())
        if ticks:
            ax.set_xticks(ticks)
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"×{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if f"{v:g}"[0] in "25" else ""))
        ax.axhline(2.0, color="tab:orange", linestyle="--", linewidth=0.9)
        ax.axhline(4.0, color="tab:blue", linestyle="--", linewidth=0.9)
        ax.text(0.99, 2.0, "high target ≤ 2 %", color="tab:orange", fontsize=8, ha="right", va="bottom",
                transform=ax.get_yaxis_transform())
        ax.text(0.99, 4.0, "medium target ≤ 4 %", color="tab:blue", fontsize=8, ha="right", va="bottom",
                transform=ax.get_yaxis_transform())
        xlabel = "frame time ÷ trivial fullscreen pass of the same size, 1280×720 (log scale)"
        if small_only:
            xlabel += "\n(" + ", ".join(PRESETS.get(p, str(p)) for p in sorted(small_only)) + ": at 512×256)"
        ax.set_xlabel(xlabel)
        ax.set_ylabel("RMS luminance error vs the reference integrator, % (log)")
        ax.set_title("welkin bench sky: accuracy against cost")
        preset_handles = [
            Line2D([], [], linestyle="none", marker="o", markersize=7, color=COLOURS.get(p, "black"),
                   markerfacecolor="none" if spectral_runs and w != 3 else COLOURS.get(p, "black"),
                   label=label(p, w, spectral_runs))
            for p, w in sorted(groups)
        ]
        alt_handles = [
            Line2D([], [], linestyle="none", marker=marker_of[a], markersize=7, color="0.35", label=f"Sun {a:g}°")
            for a in alts
        ]
        # Legends outside the axes, on the right: they never hide a point.
        first = ax.legend(handles=preset_handles, title="preset", loc="upper left", bbox_to_anchor=(1.01, 1.0),
                          fontsize=8, title_fontsize=8)
        ax.add_artist(first)
        ax.legend(handles=alt_handles, title="Sun altitude", loc="lower left", bbox_to_anchor=(1.01, 0.0), fontsize=8,
                  title_fontsize=8)
    else:
        for (preset, wl), grp in sorted(groups.items()):
            grp = sorted(grp, key=lambda r: r["sun_alt_deg"])
            big = [r.get("frame_1280x720_ms", math.nan) for r in grp]
            use_big = any(math.isfinite(v) for v in big)
            ys = big if use_big else [r.get("frame_512x256_ms", math.nan) for r in grp]
            ax.plot([r["sun_alt_deg"] for r in grp], ys, marker="o", color=COLOURS.get(preset, "black"),
                    label=label(preset, wl, spectral_runs) + ("" if use_big else " (512×256)"))
        ax.set_yscale("log")
        ax.set_xlabel("Sun altitude, degrees")
        ax.set_ylabel("frame time, ms (1280×720 unless noted)")
        ax.set_title("welkin bench sky: frame cost (no error columns: --timing-only)")
        ax.legend(title="preset", loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, title_fontsize=8)
    ax.grid(True, which="major", linewidth=0.6, alpha=0.6)
    ax.grid(True, which="minor", linewidth=0.3, alpha=0.35)
    fig.tight_layout()
    try:
        fig.savefig(args.png)
    except OSError as e:
        print(f"plot_bench_sky.py: cannot write {args.png}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
