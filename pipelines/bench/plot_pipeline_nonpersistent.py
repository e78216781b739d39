#!/usr/bin/python3
"""Plots results/pipeline-nonpersistent.csv (pipelines/bench/pipeline-nonpersistent.sh): wall and
CPU seconds of each stage per run, with the run's peak RSS and load average.
  plot_pipeline_nonpersistent.py pipeline-nonpersistent.csv pipeline-nonpersistent.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
stages = [("joints", "joints"), ("cut_prune", "cut + prune"), ("vertices", "vertices"),
          ("export_vtu", "VTU")]
colours = ["#7f7f7f", "#1f77b4", "#ff7f0e", "#2ca02c"]
fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(rows) + 2), 4.4))
for i, r in enumerate(rows):
    for k, key in enumerate(("wall", "cpu")):
        x = i + (-0.2 if key == "wall" else 0.2)
        bottom = 0.0
        for (s, label), c in zip(stages, colours):
            v = float(r["%s_%s_s" % (s, key)])
            ax.bar(x, v, width=0.38, bottom=bottom, color=c, alpha=1.0 if key == "wall" else 0.55,
                   label=label if i == 0 and key == "wall" else None)
            bottom += v
        ax.text(x, bottom, "%s\n%.1f s" % (key, bottom), ha="center", va="bottom", fontsize=7)
ax.axhline(10, color="#d62728", linestyle="--", linewidth=1)
ax.text(len(rows) - 0.5, 10, "goal: 10 s wall", color="#d62728", ha="right", va="bottom", fontsize=8)
ax.set_xticks(range(len(rows)))
ax.set_xticklabels(["run %s, %s thr.\nload %s, %s MB" % (r["run"], r["threads"], r["load"],
                                                        format(int(float(r["peak_rss_mb"])), ","))
                    for r in rows], fontsize=7)
ax.set_ylabel("seconds (wall: solid; CPU, user + sys: light)")
blocks = format(int(rows[-1]["blocks"]), ",") if rows else "?"
ax.set_title("table3-lognormal, %s blocks: joints -> cut + prune -> vertices -> VTU" % blocks,
             fontsize=9)
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
