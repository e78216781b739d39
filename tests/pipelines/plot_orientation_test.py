#!/usr/bin/python3
"""ctest "pipelines/plot draws the set means slice-info gives, right for steep sets".

    plot_orientation_test.py TOOLS_DIR SOURCE_DIR

- plot's orientation_stats recovers Fisher sets drawn here (numpy, fixed seeds) at every dip
  from 0 to 90 (exactly vertical and near-vertical included) and every 30 degrees of dip
  direction: the mean within the angle kappa and N allow (probability 1e-6), kappa within the
  chi-square factors; the old way (summed upward normals) is wrong for the vertical set.
- A FAB of steep sets (the hillside's J1 77.1/020 and J2 69.3/140, and J3 88/290), drawn by
  slice-joints and written by slice-export --format fab, read back as a [[dfn]]: plot's set
  means and kappas are slice-info --json's (mean_dip, mean_dip_direction, fisher_kappa) to
  1e-6, both near the truth; the stereonet's legend gives those means, no "(one orientation)";
  Markland's mean planes are the same; /sets holds the same mean.

Any failure, a missing tool or module included, fails the test: nothing is skipped.
"""
import importlib.machinery
import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise AssertionError("%s exited %d:\n%s%s" % (" ".join(cmd), r.returncode, r.stdout,
                                                      r.stderr))
    return r


def load_plot(source):
    path = os.path.join(source, "pipelines", "plot")
    loader = importlib.machinery.SourceFileLoader("rockslice_plot", path)
    spec = importlib.util.spec_from_loader("rockslice_plot", loader)
    mod = importlib.util.module_from_spec(spec)
    loader.exec_module(mod)
    return mod


def normal(dip, ddir):
    d, a = math.radians(dip), math.radians(ddir)
    return np.array([math.sin(d) * math.sin(a), math.sin(d) * math.cos(a), math.cos(d)])


def fisher_poles(dip, ddir, kappa, n, seed):
    """n poles from the Fisher distribution about the upward normal, each with a random sign."""
    g = np.random.Generator(np.random.PCG64(seed))
    m = normal(dip, ddir)
    e1 = np.cross(m, [0.0, 0.0, 1.0] if abs(m[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(m, e1)
    u, phi, sign = g.random(n), 2 * np.pi * g.random(n), np.where(g.random(n) < 0.5, -1.0, 1.0)
    c = 1 + np.log1p(u * np.expm1(-2 * kappa)) / kappa
    s = np.sqrt(np.maximum(0, 1 - c * c))
    p = c[:, None] * m + s[:, None] * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    return p * sign[:, None]


def axis_angle(dip1, ddir1, dip2, ddir2):
    c = abs(float(normal(dip1, ddir1) @ normal(dip2, ddir2)))
    return math.degrees(math.acos(min(1.0, c)))


def mean_tolerance(kappa, n):
    return math.degrees(math.acos(max(-1.0, 1 - math.log(1e6) / (kappa * n))))


def kappa_factors(n):
    df, z = 2.0 * (n - 1), 4.753
    q = [(1 - 2 / (9 * df) + zz * math.sqrt(2 / (9 * df))) ** 3 for zz in (z, -z)]
    return 1 / q[0], 1 / q[1]


def synthetic(plot):
    dips = [0, 0.5, 2] + list(range(5, 90, 5)) + [87, 88, 89, 89.5, 89.9, 90]
    seed, cases = 100, 0
    for dip in dips:
        for ddir in range(0, 360, 30):
            for kappa, n in ((10, 50), (60, 200)):
                seed += 1
                st = plot.orientation_stats(fisher_poles(dip, ddir, kappa, n, seed))
                off = axis_angle(st["dip"], st["dip_direction"], dip, ddir)
                lo, hi = kappa_factors(n)
                what = "dip %g ddir %g kappa %g n %d seed %d: %.3f/%.3f kappa %.3g off %.3g" % (
                    dip, ddir, kappa, n, seed, st["dip"], st["dip_direction"], st["kappa"], off)
                check(off < mean_tolerance(kappa, n), what)
                check(kappa * lo < st["kappa"] < kappa * hi, what)
                check(st["count"] == n and 0 <= st["dip"] <= 90
                      and 0 <= st["dip_direction"] < 360, what)
                cases += 1
    # The old way, upward normals summed, is far off for a vertical set.
    p = fisher_poles(90, 90, 50, 400, 7)
    up = np.where(p[:, 2:3] < 0, -p, p).sum(axis=0)
    old_dip = math.degrees(math.atan2(math.hypot(up[0], up[1]), up[2]))
    check(old_dip < 85, "summed upward normals give %.1f" % old_dip)
    check(abs(plot.orientation_stats(p)["dip"] - 90) < 0.5, "the folded mean is vertical")
    print("synthetic: %d sets recovered" % cases)


SETS = [("J1", 77.1, 20, 25), ("J2", 69.3, 140, 15), ("J3", 88, 290, 40)]


def dfn(plot, tools, tmp):
    domain = "[domain]\nbox = { min = [0, 0, 0], max = [60, 60, 60] }\n"
    scene = "[scene]\nname = \"source\"\nseed = 43\n" + domain
    for name, dip, ddir, kappa in SETS:
        scene += ("[[sets]]\nname = \"%s\"\ndip = %g\ndip_direction = %g\nfisher_kappa = %g\n"
                  "count = 300\nsize = { distribution = \"fixed\", value = 8 }\n"
                  % (name, dip, ddir, kappa))
    src, fab, h5 = (os.path.join(tmp, n) for n in ("source.toml", "net.fab", "dfn.h5"))
    with open(src, "w") as f:
        f.write(scene)
    run([os.path.join(tools, "slice-joints"), "-q", src, "-o", os.path.join(tmp, "source.h5")])
    run([os.path.join(tools, "slice-export"), "-q", os.path.join(tmp, "source.h5"), "--format",
         "fab", "-o", fab])
    with open(os.path.join(tmp, "dfn.toml"), "w") as f:
        f.write("[scene]\nname = \"dfn\"\n" + domain + "[[dfn]]\nfile = \"net.fab\"\n")
    run([os.path.join(tools, "slice-joints"), "-q", os.path.join(tmp, "dfn.toml"), "-o", h5])
    info = json.loads(run([os.path.join(tools, "slice-info"), h5, "--json"]).stdout)
    by_set = {s["name"]: s for s in info["joints"]["by_set"]}

    import h5py
    with h5py.File(h5, "r") as f:
        sets = plot.read_sets(f)
        normals, set_of = f["joints/normal"][:], f["joints/set"][:]
        names = [s["name"] for s in sets]
        for i, (name, dip, ddir, kappa) in enumerate(SETS):
            k = names.index(name)
            st = plot.orientation_stats(normals[set_of == k])
            s = by_set[name]
            what = "%s: plot %.4f/%.4f kappa %.5g, slice-info %.4f/%.4f kappa %.5g" % (
                name, st["dip"], st["dip_direction"], st["kappa"], s["mean_dip"],
                s["mean_dip_direction"], s["fisher_kappa"])
            print(what)
            check(axis_angle(st["dip"], st["dip_direction"], s["mean_dip"],
                             s["mean_dip_direction"]) < 1e-6, what)
            check(abs(st["kappa"] / s["fisher_kappa"] - 1) < 1e-6, what)
            check(axis_angle(st["dip"], st["dip_direction"], dip, ddir)
                  < mean_tolerance(kappa, st["count"]), what + ": far from the truth")
            # joints.h5's own mean of the set is the same folded mean.
            check(axis_angle(float(sets[k]["dip"]), float(sets[k]["dip_direction"]), st["dip"],
                             st["dip_direction"]) < 1e-6, what + ": /sets differs")
        # Markland's mean planes.
        for p in plot.set_planes(f, sets):
            s = by_set[p["name"]]
            check(axis_angle(p["dip"], p["dip_direction"], s["mean_dip"], s["mean_dip_direction"])
                  < 1e-6, "Markland's plane of %s" % p["name"])
        # The stereonet's legend: the measured means, kappa, no "(one orientation)".
        figs = []
        subplots = plot.plt.subplots

        def keep(*a, **k):
            fig, ax = subplots(*a, **k)
            figs.append(ax)
            return fig, ax
        plot.plt.subplots = keep
        try:
            plot.stereonet(f, sets, "dfn", os.path.join(tmp, "dfn-stereonet.png"))
        finally:
            plot.plt.subplots = subplots
        labels = [t.get_text() for t in figs[0].get_legend().get_texts()]
        print("legend: %s" % labels)
        for name, _, _, _ in SETS:
            s = by_set[name]
            want = "%s (%d): %.1f/%03.0f, kappa" % (name, s["joints"], s["mean_dip"],
                                                    s["mean_dip_direction"])
            check(any(t.startswith(want) for t in labels), "no legend entry %r" % want)
        check(not any("one orientation" in t for t in labels), "a DFN set said one orientation")
    run([sys.executable, os.path.join(plot.__file__), h5, "-o", os.path.join(tmp, "png")])
    check(os.path.getsize(os.path.join(tmp, "png", "dfn-stereonet.png")) > 0, "no stereonet")


def main():
    tools, source = sys.argv[1], sys.argv[2]
    plot = load_plot(source)
    synthetic(plot)
    with tempfile.TemporaryDirectory() as tmp:
        dfn(plot, tools, tmp)
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
