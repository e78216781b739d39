#!/usr/bin/python3
"""Plots slice-bench-lp's CSV: time per solve against error vs exact, log-log.

usage: /usr/bin/python3 plot_lp.py lp.csv lp.png

One point per (backend, problem, rows): x = median time per solve, y = largest |error| against
the exact backend. An error of exactly 0 (exact against itself, or a backend that matched it to
the last bit) cannot sit on a log axis: it is drawn at FLOOR and the axis says so.
Runs under Debian's /usr/bin/python3 with python3-matplotlib (the python3 first on PATH may
lack it).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-17
COLOURS = {"native": "tab:green", "exact": "tab:blue", "ipopt": "tab:red",
           "ipopt_batch": "tab:orange"}
MARKERS = {"cut": "o", "cut_polygon": "s", "chebyshev": "^"}


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 1
    with open(argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    expected = ["backend", "problem", "rows", "count", "median_us", "p90_us", "max_abs_err",
                "wrong_decisions"]
    if not rows or list(rows[0].keys()) != expected:
        sys.stderr.write(f"plot_lp.py: {argv[1]}: expected the columns {','.join(expected)}\n")
        return 1

    fig, ax = plt.subplots(figsize=(11, 6))
    seen = set()
    for r in rows:
        backend, problem = r["backend"], r["problem"]
        t = float(r["median_us"])
        err = float(r["max_abs_err"])
        y = err if err > 0 else FLOOR
        label = f"{backend} ({problem})"
        ax.scatter(t, y, c=COLOURS.get(backend, "k"), marker=MARKERS.get(problem, "x"), s=45,
                   label=None if label in seen else label, alpha=0.85,
                   edgecolors="k" if int(r["wrong_decisions"]) > 0 else "none")
        seen.add(label)
        ax.annotate(r["rows"], (t, y), textcoords="offset points", xytext=(4, 3), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(FLOOR, color="grey", lw=0.6, ls=":")
    ax.text(ax.get_xlim()[0] * 1.1, FLOOR * 1.6, "error exactly 0 (plotted at 1e-17)",
            fontsize=8, color="grey")
    ax.set_xlabel("median time per solve [µs] (LP built from the block's faces included)")
    ax.set_ylabel("max |error| against exact [L = 1]")
    ax.set_title("rockslice LP backends: time per solve against error\n"
                 "(numbers: LP rows; black edge: some decision differs from exact)")
    ax.grid(True, which="major", lw=0.4, alpha=0.5)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
