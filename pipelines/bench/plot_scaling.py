"""Plots a scaling CSV (scaling.sh, scaling-nonpersistent.sh): time against blocks, log-log,
with fitted slopes; prints the slopes and the speed-up of the index at 20,000 blocks.

Run by /usr/bin/python3 (Debian's python3-matplotlib): plot_scaling.py in.csv out.png [title]
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def at(blocks, times, x):
    """Time at x blocks, interpolated on the log-log line between the measured points."""
    pts = sorted(zip(blocks, times))
    for (b0, t0), (b1, t1) in zip(pts, pts[1:]):
        if b0 <= x <= b1:
            w = math.log(x / b0) / math.log(b1 / b0)
            return math.exp(math.log(t0) + w * math.log(t1 / t0))
    return float("nan")


def main(src, dst, title="Table 3 scene, persistent sets"):
    rows = list(csv.DictReader(open(src)))
    at_20k = {}
    fig, (ax, mem) = plt.subplots(1, 2, figsize=(11, 4.5))
    for index, style in (("yes", "o-"), ("no", "s--")):
        sel = [r for r in rows if r["index"] == index]
        if len(sel) < 2:
            continue
        b = [int(r["blocks"]) for r in sel]
        t = [float(r["seconds_cut"]) + float(r["seconds_prune"]) for r in sel]
        k = slope(b, t)
        at_20k[index] = at(b, t, 20000)
        print(f"index {index}: slope {k:.3f} over {min(b)}..{max(b)} blocks, {at_20k[index]:.3f} s at 20,000")
        label = ("with" if index == "yes" else "without") + f" spatial index: slope {k:.2f}"
        ax.loglog(b, t, style, label=label)
        mem.loglog(b, [float(r["peak_rss_mb"]) for r in sel], style, label=label.split(":")[0])
    ax.set_xlabel("blocks")
    ax.set_ylabel("cut + prune time [s], one core")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    mem.set_xlabel("blocks")
    mem.set_ylabel("peak RSS [MB]")
    mem.grid(True, which="both", alpha=0.3)
    mem.legend()
    fig.tight_layout()
    fig.savefig(dst, dpi=110)
    if len(at_20k) == 2:
        print(f"speed-up of the index at 20,000 blocks: {at_20k['no'] / at_20k['yes']:.1f}x")


if __name__ == "__main__":
    main(*sys.argv[1:4])
