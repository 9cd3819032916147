#!/usr/bin/env python3
"""Plots cc_crowd --tradeoff's tradeoff.csv: per scene, cost per update against the median RMS
error over the windows (log-log; the front is judged on the per-window RMS), one marker per sweep
(level, substeps, iterations, grid, strain limit), the presets ringed in red, the reference's own
checks hollow, the front's points dotted red.

    /usr/bin/python3 scripts/plot-tradeoff.py crowd_out/tradeoff.csv crowd_out/tradeoff.png

Exit code 3 when matplotlib is missing (Debian: apt-get install python3-matplotlib)."""
import csv
import sys

try:
    import matplotlib
    matplotlib.use("Agg")  # headless
    import matplotlib.pyplot as plt
except ImportError:
    print("plot-tradeoff.py needs matplotlib: apt-get install python3-matplotlib", file=sys.stderr)
    sys.exit(3)

MARKERS = {"level": "o", "substeps": "s", "iterations": "^", "grid": "x", "no-limit": "D", "preset-fast": "*", "preset-balanced": "*", "preset-quality": "*", "solver-only": "P", "ref-time": "v", "ref-space": "<"}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot-tradeoff.py TRADEOFF_CSV OUTPUT_PNG")
    with open(sys.argv[1], newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["ok"] == "1"]
    if not rows:
        sys.exit(f"{sys.argv[1]}: no rows")
    scenes = sorted({r["scene"] for r in rows})
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        mine = [r for r in rows if r["scene"] == scene]
        for knob, marker in MARKERS.items():
            pts = [r for r in mine if r["knob"] == knob]
            if not pts:
                continue
            hollow = knob.startswith("ref-")
            ax.scatter([float(r["ms"]) for r in pts], [max(float(r["rms_mm"]), 1e-3) for r in pts], marker=marker,
                       facecolors="none" if hollow else None, edgecolors="k" if hollow else None, label=knob, zorder=3)
            for r in pts:
                label = {"level": "L" + r["level"], "substeps": r["substeps"] + "s", "iterations": r["iterations"] + "i",
                         "grid": r["substeps"] + "s" + r["iterations"] + "i"}.get(knob, "")
                if label:
                    ax.annotate(label, (float(r["ms"]), max(float(r["rms_mm"]), 1e-3)), fontsize=7,
                                xytext=(3, 3), textcoords="offset points")
        presets = [r for r in mine if r.get("preset")]
        ax.scatter([float(r["ms"]) for r in presets], [max(float(r["rms_mm"]), 1e-3) for r in presets], s=160,
                   facecolors="none", edgecolors="r", linewidths=1.2, label="preset", zorder=4)
        for r in presets:
            ax.annotate(r["preset"], (float(r["ms"]), max(float(r["rms_mm"]), 1e-3)), fontsize=7, color="r",
                        xytext=(4, -9), textcoords="offset points")
        front = sorted((float(r["ms"]), max(float(r["rms_mm"]), 1e-3)) for r in mine if r["front"] == "1")
        if front:
            ax.scatter([p[0] for p in front], [p[1] for p in front], s=12, c="r", label="front (not measurably beaten)",
                       zorder=5)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(scene)
        ax.set_xlabel("ms per update (one thread)")
        ax.set_ylabel("median RMS error [mm] at the window's end")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=7, loc="best")
    fig.suptitle("crowdcloth: cost against error, windows restarted from a converged reference")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
