"""Plots lps-per-split.csv (lps-per-split.sh): cut LPs per split before and after the cut's
geometric shortcuts, per scene and density, on a scale linear below 1 and logarithmic above (so
that none, where geometry settles every pair, still shows), with the goal of issue 29 (10).

Run by /usr/bin/python3 (Debian's python3-matplotlib): plot_lps_per_split.py in.csv out.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    labels = [f"{r['scene']}\n{r['density']}\n{int(r['blocks']):,} blocks" for r in rows]
    before = [float(r["lps_per_split_before"]) for r in rows]
    after = [float(r["lps_per_split_after"]) for r in rows]
    x = range(len(rows))
    fig, ax = plt.subplots(figsize=(max(6, 1.3 * len(rows)), 4.5))
    w = 0.38
    ax.bar([i - w / 2 for i in x], before, w, label="before: every pair past the index to the LP")
    ax.bar([i + w / 2 for i in x], after, w,
           label="after: geometry first, misses and cuts proved (cut_reject.hpp)")
    for i, (b, a) in enumerate(zip(before, after)):
        ax.text(i - w / 2, b, f"{b:.1f}", ha="center", va="bottom", fontsize=8)
        ax.text(i + w / 2, a, f"{a:.2f}", ha="center", va="bottom", fontsize=8)
    ax.axhline(10, color="k", ls=":", lw=1, label="goal: at most 10")
    ax.set_yscale("symlog", linthresh=1)
    ax.set_ylim(0, 6 * max(before))  # room for the legend above the bars
    ax.set_ylabel("cut LPs per split")
    ax.set_xticks(list(x))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_title("Cut LPs per split (density: joint centres per m3 per set); same blocks")
    ax.legend(fontsize=8, loc="upper right")
    fig.subplots_adjust(left=0.08, right=0.98, top=0.9, bottom=0.2)
    fig.savefig(dst, dpi=110)
    for r in rows:
        print(f"{r['scene']} {r['density']}: {r['lps_per_split_before']} -> "
              f"{r['lps_per_split_after']} cut LPs per split, identical {r['identical']}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
