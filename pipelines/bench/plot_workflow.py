#!/usr/bin/python3
"""Plots results/workflow.csv (pipelines/bench/workflow.sh): full run and no-change rerun times
of the 8-seed sweep, per density and core count.  plot_workflow.py workflow.csv workflow.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
fig, ax = plt.subplots(figsize=(9, 4.2))
labels, full, rerun = [], [], []
for r in rows:
    labels.append("%s blocks/seed\n--cores %s" % (format(int(r["blocks_per_seed"]), ","), r["cores"]))
    full.append(float(r["full_s"]))
    rerun.append(float(r["rerun_s"]))
x = range(len(rows))
ax.bar([i - 0.2 for i in x], full, width=0.4, label="full run", color="#1f77b4")
ax.bar([i + 0.2 for i in x], rerun, width=0.4, label="rerun, nothing changed", color="#d62728")
for i in x:
    ax.text(i + 0.2, rerun[i], "%.1f %%" % (100 * rerun[i] / full[i]), ha="center", va="bottom",
            fontsize=8)
ax.set_xticks(list(x))
ax.set_xticklabels(labels, fontsize=8)
ax.set_ylabel("wall time [s]")
ax.set_title("Snakemake sweep of table3-lognormal, 8 seeds (joints, cut, vertices, VTU, plots, summary)",
             fontsize=9)
ax.legend(fontsize=9)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
