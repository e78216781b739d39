#!/usr/bin/python3
"""ctest "pipelines/summary counts a cluster as one body" (issue 24, item 5) and
"pipelines/summary sums the failed volume of slice-stability outputs" (issue 41, item 6).

    summary_test.py [bodies|stability] TOOLS_DIR SOURCE_DIR

bodies (the default): slices data/slope.toml (construction joints outline the slope face:
clusters, and removed air blocks) for seeds 1 and 2 with the real tools, runs pipelines/summary
and pipelines/plot on the two geom.h5, and checks every by-body and by-piece figure of
realizations.csv, volume-cdf.csv and volume-band.csv against figures computed here from the
files with h5py in plain Python (dictionaries, sorted lists and loops; no code shared with the
scripts).

stability: slices the same two seeds, runs slice-stability on each (free faces +z and +x, a
seismic load of 0.3 towards the East: 18 and 23 blocks fail), runs pipelines/summary on the two
stab.h5, and checks realizations.csv's failed_blocks, failed_volume,
largest_failed_block_volume and min_fos against sums over the kept blocks computed here with
h5py (/stability/generation >= 0, /geometry/volume) and against slice-info --json; that the
body figures are those of the geom.h5 they came from; that stability.png is written; that a
summary of the geom.h5 files has none of this; and that a mixed sweep (one geom.h5, one
stab.h5) leaves the columns empty for the file without /stability.

Any failure, a missing tool or module included, fails the test: nothing is skipped.
"""
import bisect
import csv
import json
import math
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
    args = sys.argv[1:]
    mode = args.pop(0) if args and args[0] in ("bodies", "stability") else "bodies"
    if len(args) != 2:
        raise AssertionError("usage: summary_test.py [bodies|stability] TOOLS_DIR SOURCE_DIR")
    return bodies(*args) if mode == "bodies" else stability(*args)


def slice_seeds(tools, scene, tmp):
    """joints, cut --prune and vertices for each seed: the geom.h5 files."""
    geoms = []
    for seed in SEEDS:
        d = os.path.join(tmp, "seed-%d" % seed)
        os.makedirs(d)
        j, b, g = (os.path.join(d, n) for n in ("joints.h5", "blocks.h5", "geom.h5"))
        run([os.path.join(tools, "slice-joints"), "-q", scene, "--seed", str(seed), "-o", j])
        run([os.path.join(tools, "slice-cut"), "-q", j, "-o", b, "--prune"])
        run([os.path.join(tools, "slice-vertices"), "-q", b, "-o", g])
        geoms.append(g)
    return geoms


def failures(path):
    """What summary's stability columns must hold, summed here over the kept blocks."""
    with h5py.File(path, "r") as f:
        volume = [float(x) for x in f["geometry/volume"][:]]
        flags = [int(x) for x in f["blocks/flags"][:]]
        generation = [int(x) for x in f["stability/generation"][:]]
        fos = [float(x) for x in f["stability/fos"][:]]
    failed = [v for v, fl, g in zip(volume, flags, generation) if not fl & 2 and g >= 0]
    return {"failed_blocks": len(failed), "failed_volume": math.fsum(failed),
            "largest_failed_block_volume": max(failed, default=0.0),
            "min_fos": min((x for x, fl in zip(fos, flags) if not fl & 2), default=math.inf)}


def stability(tools, source):
    scene = os.path.join(source, "data", "slope.toml")
    names = ("failed_blocks", "failed_volume", "largest_failed_block_volume", "min_fos")
    with tempfile.TemporaryDirectory(prefix="rockslice-summary.") as tmp:
        geoms = slice_seeds(tools, scene, tmp)
        stabs = []
        for g in geoms:
            s = os.path.join(os.path.dirname(g), "stab.h5")
            run([os.path.join(tools, "slice-stability"), "-q", g, "-o", s, "--free-faces",
                 "+z,+x", "--seismic", "0.3", "--seismic-azimuth", "90"])
            stabs.append(s)
        summary = os.path.join(source, "pipelines", "summary")
        out, plain, mixed = (os.path.join(tmp, n) for n in ("stab", "geom", "mixed"))
        r = run(["/usr/bin/python3", summary] + stabs + ["-o", out])
        check("stability.png" in r.stderr and "failed volume median" in r.stderr,
              "summary's line does not name stability.png and the failed volume: " + r.stderr)
        run(["/usr/bin/python3", summary] + geoms + ["-o", plain])
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(out, "realizations.csv"))}
        plain_rows = {int(row["seed"]): row
                      for row in read_csv(os.path.join(plain, "realizations.csv"))}
        check(sorted(rows) == list(SEEDS), "rows are not seeds 1, 2")
        for seed, stab in zip(SEEDS, stabs):
            row, want = rows[seed], failures(stab)
            info = json.loads(run([os.path.join(tools, "slice-info"), "--json", stab]).stdout)
            info = info["stability"]
            check(int(row["failed_blocks"]) == want["failed_blocks"] == info["failing"],
                  "seed %d: failed_blocks %s, the file %d, slice-info %d"
                  % (seed, row["failed_blocks"], want["failed_blocks"], info["failing"]))
            close(float(row["failed_volume"]), want["failed_volume"],
                  "seed %d failed_volume" % seed)
            close(float(row["failed_volume"]), info["failing_volume"],
                  "seed %d failed_volume (slice-info)" % seed)
            close(float(row["largest_failed_block_volume"]), want["largest_failed_block_volume"],
                  "seed %d largest_failed_block_volume" % seed)
            close(float(row["largest_failed_block_volume"]),
                  info["largest_failing_block"]["volume"],
                  "seed %d largest_failed_block_volume (slice-info)" % seed)
            close(float(row["min_fos"]), want["min_fos"], "seed %d min_fos" % seed)
            # The scene must exercise the sums: several blocks fail, the largest is not all.
            check(want["failed_blocks"] >= 2 and want["largest_failed_block_volume"]
                  < want["failed_volume"], "seed %d: fewer than 2 blocks fail" % seed)
            # stab.h5 holds geom.h5: the same bodies.
            for k, v in plain_rows[seed].items():
                check(row[k] == v, "seed %d: %s is %s from stab.h5, %s from geom.h5"
                      % (seed, k, row[k], v))
        png = os.path.join(out, "stability.png")
        with open(png, "rb") as f:
            check(f.read(8) == b"\x89PNG\r\n\x1a\n", png + " is not a PNG")
        # Without /stability: no columns, no plot.
        with open(os.path.join(plain, "realizations.csv")) as f:
            header = f.readline().strip().split(",")
        check(not set(names) & set(header), "geom.h5 summary has stability columns: %s" % header)
        check(not os.path.exists(os.path.join(plain, "stability.png")),
              "geom.h5 summary wrote stability.png")
        # A mixed sweep: the columns are empty for the file without /stability.
        run(["/usr/bin/python3", summary, geoms[0], stabs[1], "-o", mixed])
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(mixed, "realizations.csv"))}
        check(all(rows[SEEDS[0]][n] == "" for n in names), "mixed: seed 1 (geom.h5) not empty")
        close(float(rows[SEEDS[1]]["failed_volume"]), failures(stabs[1])["failed_volume"],
              "mixed: seed 2 failed_volume")
        check(os.path.exists(os.path.join(mixed, "stability.png")), "mixed: no stability.png")
        done = {s: failures(p) for s, p in zip(SEEDS, stabs)}
    print("summary_test: ok: %s" % ", ".join(
        "seed %d: %d blocks fail, %.4g m3, the largest %.4g m3" % (
            s, d["failed_blocks"], d["failed_volume"], d["largest_failed_block_volume"])
        for s, d in done.items()))
    return 0


def bodies(tools, source):
    scene = os.path.join(source, "data", "slope.toml")
    with tempfile.TemporaryDirectory(prefix="rockslice-summary.") as tmp:
        geoms = slice_seeds(tools, scene, tmp)
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
