#!/usr/bin/python3
"""Plots results/cut-threads.csv (pipelines/bench/cut-threads.sh): the cut's stage time on 1 and
2 threads per density, every run as a point, the medians' ratio (speed-up) written above.
  plot_cut_threads.py cut-threads.csv cut-threads.png"""
import csv
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
densities = list(dict.fromkeys(r["density"] for r in rows))
fig, ax = plt.subplots(figsize=(7, 4.2))
for i, d in enumerate(densities):
    mine = [r for r in rows if r["density"] == d]
    med = {}
    for t, c in (("1", "#1f77b4"), ("2", "#ff7f0e")):
        v = [float(r["seconds_cut"]) for r in mine if r["threads"] == t]
        if not v:
            continue
        med[t] = statistics.median(v)
        x = i + (-0.15 if t == "1" else 0.15)
        ax.bar(x, med[t], width=0.3, color=c, alpha=0.6,
               label="%s thread%s (median)" % (t, "" if t == "1" else "s") if i == 0 else None)
        ax.plot([x] * len(v), v, "k.", markersize=4)
    if len(med) == 2:
        ax.text(i, max(med.values()) * 1.05, "%.2fx" % (med["1"] / med["2"]), ha="center",
                fontsize=9)
ax.set_xticks(range(len(densities)))
ax.set_xticklabels(["%s per m3\n%s blocks" % (d, format(int(next(
    r["blocks"] for r in rows if r["density"] == d)), ",")) for d in densities], fontsize=8)
ax.set_ylabel("cut stage [s] (slice-cut --stats seconds_cut)")
ax.set_title("table3-lognormal: the cut on 1 and 2 threads (load %s-%s)" % (
    min(r["load"] for r in rows), max(r["load"] for r in rows)), fontsize=9)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
