#!/usr/bin/python3
"""ctest "pipelines/summary counts a cluster as one body" (issue 24, item 5).

    summary_test.py TOOLS_DIR SOURCE_DIR

Slices data/slope.toml (construction joints outline the slope face: clusters, and removed air
blocks) for seeds 1 and 2 with the real tools, runs pipelines/summary and pipelines/plot on the
two geom.h5, and checks every by-body and by-piece figure of realizations.csv, volume-cdf.csv
and volume-band.csv against figures computed here from the files with h5py in plain Python
(dictionaries, sorted lists and loops; no code shared with the scripts). Any failure, a missing
tool or module included, fails the test: nothing is skipped.
"""
import bisect
import csv
import os
import statistics
import subprocess
import sys
import tempfile

import h5py

SEEDS = (1, 2)
REL = 1e-8  # the scripts write 9 significant digits


def close(a, b, what):
    if not abs(a - b) <= REL * max(abs(a), abs(b), 1e-300):
        raise AssertionError("%s: summary has %.12g, the file gives %.12g" % (what, a, b))


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise AssertionError("%s exited %d:\n%s%s" % (" ".join(cmd), r.returncode, r.stdout,
                                                      r.stderr))
    return r


def expected(path):
    """Bodies and pieces of one geom.h5, read with h5py and summed by hand."""
    with h5py.File(path, "r") as f:
        volume = [float(x) for x in f["geometry/volume"][:]]
        flags = [int(x) for x in f["blocks/flags"][:]]
        cluster = [int(x) for x in f["blocks/cluster"][:]]
        seed = int(f.attrs["seed"])
    pieces, free, joined, removed = [], [], {}, 0
    for v, fl, c in zip(volume, flags, cluster):
        if fl & 2:  # bit 1: removed, left out
            removed += 1
            continue
        pieces.append(v)
        if c < 0:
            free.append(v)
        else:
            joined[c] = joined.get(c, 0.0) + v
    return {"seed": seed, "pieces": sorted(pieces), "bodies": sorted(free + list(joined.values())),
            "clusters": len(joined), "removed": removed,
            "largest_cluster": max((sum(1 for c, fl in zip(cluster, flags) if c == k and not fl & 2)
                                    for k in joined), default=0)}


def v50(sorted_volumes):
    """The smallest volume v such that the volumes up to v hold at least half the total."""
    half, acc = 0.5 * sum(sorted_volumes), 0.0
    for v in sorted_volumes:
        acc += v
        if acc >= half:
            return v
    return sorted_volumes[-1]


def fractions(sorted_volumes, x):
    """Fractions by number and by volume of the volumes of at most x."""
    n = bisect.bisect_right(sorted_volumes, x)
    return n / len(sorted_volumes), sum(sorted_volumes[:n]) / sum(sorted_volumes)


def quantile(values, q):
    """numpy's default (linear) percentile, by hand."""
    s = sorted(values)
    pos = q / 100.0 * (len(s) - 1)
    lo = int(pos)
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (pos - lo)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    tools, source = sys.argv[1], sys.argv[2]
    scene = os.path.join(source, "data", "slope.toml")
    with tempfile.TemporaryDirectory(prefix="rockslice-summary.") as tmp:
        geoms = []
        for seed in SEEDS:
            d = os.path.join(tmp, "seed-%d" % seed)
            os.makedirs(d)
            j, b, g = (os.path.join(d, n) for n in ("joints.h5", "blocks.h5", "geom.h5"))
            run([os.path.join(tools, "slice-joints"), "-q", scene, "--seed", str(seed), "-o", j])
            run([os.path.join(tools, "slice-cut"), "-q", j, "-o", b, "--prune"])
            run([os.path.join(tools, "slice-vertices"), "-q", b, "-o", g])
            geoms.append(g)
        out = os.path.join(tmp, "summary")
        r = run(["/usr/bin/python3", os.path.join(source, "pipelines", "summary")] + geoms
                + ["-o", out])
        # It says so: the line names the rule and the clusters it counted once.
        want = {s: expected(g) for s, g in zip(SEEDS, geoms)}
        clusters = sum(e["clusters"] for e in want.values())
        check("block sizes by body (%d clusters counted once each" % clusters in r.stderr,
              "summary's line does not say it counts by body: " + r.stderr)

        # The scene must exercise the rule: clusters of several pieces, removed blocks.
        for s, e in want.items():
            check(e["clusters"] > 0 and e["largest_cluster"] >= 2 and e["removed"] > 0,
                  "seed %d of slope.toml has no clusters of 2+ pieces or no removed blocks" % s)
            check(len(e["bodies"]) < len(e["pieces"]), "seed %d: bodies == pieces" % s)

        rows = read_csv(os.path.join(out, "realizations.csv"))
        check([int(row["seed"]) for row in rows] == list(SEEDS), "rows are not seeds 1, 2")
        for row in rows:
            e = want[int(row["seed"])]
            s = row["seed"]
            check(int(row["blocks"]) == len(e["pieces"]), "seed %s: blocks" % s)
            check(int(row["bodies"]) == len(e["bodies"]), "seed %s: bodies %s, file %d"
                  % (s, row["bodies"], len(e["bodies"])))
            check(int(row["clusters"]) == e["clusters"], "seed %s: clusters" % s)
            check(int(row["removed"]) == e["removed"], "seed %s: removed" % s)
            close(float(row["rock_volume"]), sum(e["bodies"]), "seed %s rock_volume" % s)
            close(float(row["rock_volume"]), sum(e["pieces"]), "seed %s rock_volume (pieces)" % s)
            for prefix, v in (("", e["bodies"]), ("piece_", e["pieces"])):
                close(float(row[prefix + "mean_volume"]), statistics.fmean(v),
                      "seed %s %smean_volume" % (s, prefix))
                close(float(row[prefix + "median_volume"]), statistics.median(v),
                      "seed %s %smedian_volume" % (s, prefix))
                close(float(row[prefix + "v50"]), v50(v), "seed %s %sv50" % (s, prefix))
            # Joining pieces makes the typical body larger, never smaller.
            check(float(row["median_volume"]) >= float(row["piece_median_volume"]),
                  "seed %s: median by body below median by piece" % s)
        check(any(float(row["median_volume"]) > float(row["piece_median_volume"]) for row in rows),
              "by body and by piece give the same median on every seed: clusters not counted")

        # The distributions on the shared grid: by body (unprefixed) and by piece.
        cdf = read_csv(os.path.join(out, "volume-cdf.csv"))
        band = read_csv(os.path.join(out, "volume-band.csv"))
        check(len(cdf) == 200 and len(band) == 200, "grids are not 200 rows")
        smallest = min(e["pieces"][0] for e in want.values())
        largest = max(e["bodies"][-1] for e in want.values())
        close(float(cdf[0]["volume"]), smallest, "grid start (smallest piece)")
        close(float(cdf[-1]["volume"]), largest, "grid end (largest body)")
        for k, (crow, brow) in enumerate(zip(cdf, band)):
            x = float(crow["volume"])
            close(float(brow["volume"]), x, "band grid row %d" % k)
            for prefix, key in (("", "bodies"), ("piece_", "pieces")):
                by_number, by_volume = [], []
                for s in SEEDS:
                    # The CSV's grid volume has 9 digits: a block within that rounding of it may
                    # be on either side, so the fractions lie between those just below and above.
                    n_lo, v_lo = fractions(want[s][key], x * (1 - REL))
                    n_hi, v_hi = fractions(want[s][key], x * (1 + REL))
                    got_n = float(crow["%snumber_seed%d" % (prefix, s)])
                    got_v = float(crow["%svolume_seed%d" % (prefix, s)])
                    check(n_lo - 1e-8 <= got_n <= n_hi + 1e-8, "row %d %snumber_seed%d: %g, file "
                          "%g..%g" % (k, prefix, s, got_n, n_lo, n_hi))
                    check(v_lo - 1e-8 <= got_v <= v_hi + 1e-8, "row %d %svolume_seed%d: %g, file "
                          "%g..%g" % (k, prefix, s, got_v, v_lo, v_hi))
                    by_number.append(got_n)
                    by_volume.append(got_v)
                for q, name in ((5, "p05"), (50, "median"), (95, "p95")):
                    check(abs(float(brow["%snumber_%s" % (prefix, name)])
                              - quantile(by_number, q)) <= 1e-8, "band row %d %snumber_%s"
                          % (k, prefix, name))
                    check(abs(float(brow["%svolume_%s" % (prefix, name)])
                              - quantile(by_volume, q)) <= 1e-8, "band row %d %svolume_%s"
                          % (k, prefix, name))
        # Where bodies and pieces differ, so do the curves.
        check(any(float(c["number_seed1"]) != float(c["piece_number_seed1"]) for c in cdf),
              "volume-cdf.csv: by body equals by piece on every row")

        # pipelines/plot draws the volumes by body and labels them so.
        plots = os.path.join(tmp, "plots")
        r = run(["/usr/bin/python3", os.path.join(source, "pipelines", "plot"), geoms[0], "-o",
                 plots])
        png = os.path.join(plots, "geom-volumes.png")
        with open(png, "rb") as f:
            check(f.read(8) == b"\x89PNG\r\n\x1a\n", png + " is not a PNG")
        check("geom-volumes.png" in r.stderr, "plot did not name the volumes plot")
    print("summary_test: ok: %s" % ", ".join(
        "seed %d: %d pieces -> %d bodies (%d clusters), median %.4g by body, %.4g by piece"
        % (s, len(e["pieces"]), len(e["bodies"]), e["clusters"], statistics.median(e["bodies"]),
           statistics.median(e["pieces"])) for s, e in want.items()))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except AssertionError as e:
        print("summary_test: FAILED: %s" % e, file=sys.stderr)
        sys.exit(1)
