"""Plots results/stability.csv (stability.sh): slice-stability's time against blocks, log-log,
per part (contact search, bodies, analysis of the exposed bodies) on 1 and 2 threads, with the
fastest of each spacing's runs; and peak memory. Prints the table docs/benchmarks.md quotes.

Run by /usr/bin/python3 (Debian's python3-matplotlib): plot_stability.py in.csv out.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    best = {}  # (spacing, threads) -> the row of the fastest run
    for r in rows:
        key = (float(r["spacing"]), int(r["threads"]))
        if key not in best or float(r["tool_s"]) < float(best[key]["tool_s"]):
            best[key] = r
    fig, (ax, mem) = plt.subplots(1, 2, figsize=(11, 4.5))
    print("| blocks | threads | contacts | exposed | failing | rounds | contacts s | bodies s | "
          "analysis s | tool s | peak MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for threads, style in ((1, "--"), (2, "-")):
        sel = sorted((r for (s, t), r in best.items() if t == threads),
                     key=lambda r: int(r["blocks"]))
        if not sel:
            continue
        blocks = [int(r["blocks"]) for r in sel]
        for part, marker in (("contacts_s", "o"), ("bodies_s", "s"), ("analysis_s", "^"),
                             ("tool_s", "x")):
            ax.loglog(blocks, [max(float(r[part]), 1e-4) for r in sel], marker + style,
                      label="%s, %d thread%s" % (part[:-2], threads, "s" if threads > 1 else ""))
        mem.loglog(blocks, [float(r["peak_mb"]) for r in sel], "o" + style,
                   label="%d thread%s" % (threads, "s" if threads > 1 else ""))
        for r in sel:
            print("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                format(int(r["blocks"]), ","), threads, format(int(r["contacts"]), ","),
                format(int(r["exposed"]), ","), format(int(r["failing"]), ","), r["rounds"],
                r["contacts_s"], r["bodies_s"], r["analysis_s"], r["tool_s"], r["peak_mb"]))
    ax.set_xlabel("blocks")
    ax.set_ylabel("seconds")
    ax.set_title("slice-stability, Table 3 persistent, free +z,+x,-y")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    mem.set_xlabel("blocks")
    mem.set_ylabel("peak resident MB (the whole tool)")
    mem.legend(fontsize=8)
    mem.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(dst, dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:3])
