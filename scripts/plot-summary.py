#!/usr/bin/env python3
"""Plots a cc_crowd run's frames.csv into one picture: cloth ms per frame against the budget,
garments per LOD level over time (stacked), and the garments' predicted error over time.

    /usr/bin/python3 scripts/plot-summary.py crowd_out/frames.csv crowd_out/summary.png

Exit code 3 when matplotlib is missing (Debian: apt-get install python3-matplotlib)."""
import csv
import sys

try:
    import matplotlib
    matplotlib.use("Agg")  # headless: no display on CI or a render node
    import matplotlib.pyplot as plt
except ImportError:
    print("plot-summary.py needs matplotlib: apt-get install python3-matplotlib", file=sys.stderr)
    sys.exit(3)


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no frames")
    return {key: [float(row[key]) for row in rows] for key in rows[0]}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot-summary.py FRAMES_CSV OUTPUT_PNG")
    csv_path, png_path = sys.argv[1], sys.argv[2]
    c = read_columns(csv_path)
    t = c["time"]
    levels = [k for k in c if k.startswith("L") and k[1:].isdigit() and any(c[k])]

    fig, (ms, lod, err) = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    ms.plot(t, c["totalMs"], lw=0.8, label="cloth ms per frame")
    ms.plot(t, c["budgetMs"], "r--", lw=1.2, label="budget")
    ms.set_ylabel("ms")
    ms.set_ylim(bottom=0)
    ms.legend(loc="upper right")
    ms.set_title("cloth time per frame")

    lod.stackplot(t, [c[k] for k in levels], labels=levels)
    lod.plot(t, c["visible"], "k:", lw=1.0, label="visible")
    lod.set_ylabel("garments")
    lod.legend(loc="upper right", ncol=len(levels) + 1, fontsize="small")
    lod.set_title("garments per level (L0 coarsest)")

    err.plot(t, c["errorMedianPx"], lw=0.8, label="median")
    err.plot(t, c["errorMaxPx"], lw=0.8, label="max")
    err.axhline(1.0, color="r", ls="--", lw=1.0, label="1 px")
    # Log: typical errors are fractions of a pixel, a close-up's a few pixels (frames with no
    # garment in view, error 0, leave gaps).
    err.set_yscale("log")
    err.set_ylabel("px")
    err.set_xlabel("time [s]")
    err.legend(loc="upper right")
    err.set_title("predicted error of the garments in view")

    fig.tight_layout()
    fig.savefig(png_path, dpi=100)


if __name__ == "__main__":
    main()
