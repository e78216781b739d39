#!/usr/bin/python3
"""ctest "pipelines/plot draws the Markland test of a slice-stability output" (issue 41, item 6).

    plot_test.py TOOLS_DIR SOURCE_DIR

Slices data/slope.toml (a 45 degree face dipping East, the +x side free too) with the real
tools, runs slice-stability (--free-faces +z,+x) and pipelines/plot on stab.h5, and checks:

- stab-markland.png is written (a PNG) and plot's line names it;
- the free face on plot's line is the one computed here in plain Python with h5py (the
  area-weighted mean outward normal of the free contacts dipping 20 degrees or more), with the
  count and area of those contacts, and phi is the smallest friction angle of the sets;
- with --slope 60/120 --friction 5, the sets and pairs it says can slide are those Markland's
  conditions give when computed here (set means from /joints, their lines of intersection),
  and some can (planar and wedge), so both paths are exercised;
- geom.h5 (no /stability) gets no Markland plot, unless --slope is given;
- data/cube-3sets.toml with four sides free (the free faces face every way) gets none, and a
  line that says to give --slope; exit 0;
- a bad --slope or --friction: exit 1, one line on stderr, nothing written.

Any failure, a missing tool or module included, fails the test: nothing is skipped.
"""
import math
import os
import re
import subprocess
import sys
import tempfile

import h5py

PNG = b"\x89PNG\r\n\x1a\n"


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def run(cmd, code=0):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != code:
        raise AssertionError("%s exited %d, expected %d:\n%s%s" % (
            " ".join(cmd), r.returncode, code, r.stdout, r.stderr))
    return r


def slice_scene(tools, scene, folder, free_faces):
    os.makedirs(folder)
    j, b, g, s = (os.path.join(folder, n) for n in ("joints.h5", "blocks.h5", "geom.h5",
                                                    "stab.h5"))
    run([os.path.join(tools, "slice-joints"), "-q", scene, "-o", j])
    run([os.path.join(tools, "slice-cut"), "-q", j, "-o", b, "--prune"])
    run([os.path.join(tools, "slice-vertices"), "-q", b, "-o", g])
    run([os.path.join(tools, "slice-stability"), "-q", g, "-o", s, "--free-faces", free_faces])
    return g, s


def expected_face(path):
    """dip, dip direction, count, area: the area-weighted mean outward normal of the free
    contacts that dip 20 degrees or more, summed in plain Python."""
    with h5py.File(path, "r") as f:
        c = f["contacts"]
        rows = zip(c["free"][:].tolist(), c["normal"][:].tolist(), c["area"][:].tolist())
        sx = sy = sz = total = 0.0
        count = 0
        for free, (nx, ny, nz), area in rows:
            if free == 1 and abs(nz) < math.cos(math.radians(20)):
                sx, sy, sz, total, count = (sx + area * nx, sy + area * ny, sz + area * nz,
                                            total + area, count + 1)
    length = math.sqrt(sx * sx + sy * sy + sz * sz)
    dip = math.degrees(math.acos(sz / length))
    return dip, math.degrees(math.atan2(sx, sy)) % 360, count, total


def normal(dip, ddir):
    d, a = math.radians(dip), math.radians(ddir)
    return (math.sin(a) * math.sin(d), math.cos(a) * math.sin(d), math.cos(d))


def apparent(face_dip, delta):
    return math.degrees(math.atan2(math.sin(math.radians(face_dip)) * math.cos(math.radians(delta)),
                                   math.cos(math.radians(face_dip))))


def wrap(a):
    return (a + 180.0) % 360.0 - 180.0


def expected_markland(path, face_dip, face_ddir, phi):
    """The sets that can slide on one plane and the pairs that can slide as wedges, computed
    here: each set's mean plane from its joints' normals (made to agree in sense with the
    set's requested pole), then Markland's conditions (Hoek & Bray)."""
    with h5py.File(path, "r") as f:
        sets = []
        for i in range(int(f["sets"].attrs["count"])):
            a = f["sets/%03d" % i].attrs
            name = a["name"].decode() if isinstance(a["name"], bytes) else str(a["name"])
            sets.append((name, float(a["dip"]), float(a["dip_direction"])))
        joint_set = f["joints/set"][:].tolist()
        normals = f["joints/normal"][:].tolist()
    planes = []
    for i, (name, dip, ddir) in enumerate(sets):
        ref = normal(dip, ddir)
        s = [0.0, 0.0, 0.0]
        for k, n in zip(joint_set, normals):
            if k == i:
                sign = 1.0 if sum(p * q for p, q in zip(n, ref)) >= 0 else -1.0
                s = [s[m] + sign * n[m] for m in range(3)]
        length = math.sqrt(sum(x * x for x in s))
        s = [x / length for x in s]
        if s[2] < 0:
            s = [-x for x in s]
        planes.append((name, math.degrees(math.acos(s[2])),
                       math.degrees(math.atan2(s[0], s[1])) % 360, s))
    planar = [name for name, dip, ddir, _ in planes
              if dip > phi and abs(wrap(ddir - face_ddir)) <= 20
              and dip < apparent(face_dip, wrap(ddir - face_ddir))]
    wedges = []
    for i in range(len(planes)):
        for j in range(i + 1, len(planes)):
            u, v = planes[i][3], planes[j][3]
            line = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0])
            length = math.sqrt(sum(x * x for x in line))
            line = [x / length for x in line]
            if line[2] > 0:
                line = [-x for x in line]
            plunge = math.degrees(math.asin(-line[2]))
            trend = math.degrees(math.atan2(line[0], line[1])) % 360
            delta = wrap(trend - face_ddir)
            if plunge > phi and abs(delta) < 90 and plunge < apparent(face_dip, delta):
                wedges.append("%s x %s" % (planes[i][0], planes[j][0]))
    return planar, wedges


LINE = re.compile(r"^plot: Markland's test of (.*): face ([0-9.]+)/([0-9.]+) \((.*)\), phi "
                  r"([0-9.]+) \((.*)\): planar sliding possible on (.*); wedge sliding possible "
                  r"on (.*)$", re.M)


def markland_line(stderr):
    m = LINE.search(stderr)
    check(m is not None, "no Markland line in plot's output:\n" + stderr)
    names = [] if m.group(7) == "none" else m.group(7).split(", ")
    pairs = [] if m.group(8) == "none" else m.group(8).split(", ")
    return {"dip": float(m.group(2)), "ddir": float(m.group(3)), "how": m.group(4),
            "phi": float(m.group(5)), "phi_how": m.group(6), "planar": names, "wedges": pairs}


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == PNG


def main():
    tools, source = sys.argv[1], sys.argv[2]
    plot = ["/usr/bin/python3", os.path.join(source, "pipelines", "plot")]
    with tempfile.TemporaryDirectory(prefix="rockslice-plot.") as tmp:
        geom, stab = slice_scene(tools, os.path.join(source, "data", "slope.toml"),
                                 os.path.join(tmp, "slope"), "+z,+x")

        # The face from the file.
        out = os.path.join(tmp, "plots")
        r = run(plot + [stab, "-o", out])
        png = os.path.join(out, "stab-markland.png")
        check(os.path.isfile(png) and is_png(png), png + " is missing or not a PNG")
        check("stab-markland.png" in r.stderr, "plot's line does not name the Markland plot")
        got = markland_line(r.stderr)
        dip, ddir, count, area = expected_face(stab)
        check(abs(got["dip"] - dip) < 0.006 and abs(wrap(got["ddir"] - ddir)) < 0.006,
              "face %g/%g, computed here %.3f/%.3f" % (got["dip"], got["ddir"], dip, ddir))
        check(got["how"] == "from %d free contacts, %.4g m2" % (count, area),
              "face from %r, expected %d contacts and %.4g m2" % (got["how"], count, area))
        # The slope face dips 45 degrees East; the free +x side is vertical: between the two.
        check(45 < dip < 90 and abs(wrap(ddir - 90)) < 5, "face %g/%g is not the East face"
              % (dip, ddir))
        with h5py.File(stab, "r") as f:
            phi = min(float(f["sets/%03d" % i].attrs["friction_angle"])
                      for i in range(int(f["sets"].attrs["count"])))
        check(got["phi"] == phi and got["phi_how"] == "the smallest of the sets'",
              "phi %g (%s), the sets' smallest is %g" % (got["phi"], got["phi_how"], phi))
        planar, wedges = expected_markland(stab, dip, ddir, phi)
        check((got["planar"], got["wedges"]) == (planar, wedges),
              "planar %s, wedges %s; computed here %s, %s" % (got["planar"], got["wedges"],
                                                               planar, wedges))

        # A face and phi given: what can slide, against the conditions computed here.
        forced = os.path.join(tmp, "forced")
        r = run(plot + [stab, "-o", forced, "--slope", "60/120", "--friction", "5"])
        got = markland_line(r.stderr)
        check((got["dip"], got["ddir"], got["how"], got["phi"], got["phi_how"])
              == (60, 120, "--slope", 5, "--friction"), "not the face and phi given: %s" % got)
        planar, wedges = expected_markland(stab, 60, 120, 5)
        check((got["planar"], got["wedges"]) == (planar, wedges),
              "planar %s, wedges %s; computed here %s, %s" % (got["planar"], got["wedges"],
                                                               planar, wedges))
        check(planar and wedges, "nothing can slide on 60/120 with phi 5: the test does not "
              "exercise the marks (planar %s, wedges %s)" % (planar, wedges))

        # geom.h5: no /stability, no Markland plot; with --slope, one.
        plain = os.path.join(tmp, "plain")
        r = run(plot + [geom, "-o", plain])
        check(not os.path.exists(os.path.join(plain, "geom-markland.png"))
              and "Markland" not in r.stderr, "geom.h5 got a Markland plot: " + r.stderr)
        r = run(plot + [geom, "-o", plain, "--slope", "50/090"])
        check(is_png(os.path.join(plain, "geom-markland.png")), "--slope drew no Markland plot")

        # Free faces all around: no face to test, a line that says so, exit 0.
        _, cube = slice_scene(tools, os.path.join(source, "data", "cube-3sets.toml"),
                              os.path.join(tmp, "cube"), "+x,-x,+y,-y,+z")
        around = os.path.join(tmp, "around")
        r = run(plot + [cube, "-o", around])
        check("plot: no Markland plot: the free faces face every way" in r.stderr
              and "give --slope" in r.stderr, "no line about the free faces: " + r.stderr)
        check(not os.path.exists(os.path.join(around, "stab-markland.png")),
              "a Markland plot of free faces all around")

        # Bad options: exit 1, one line, nothing written.
        for option, value in (("--slope", "95/120"), ("--slope", "60"), ("--friction", "abc"),
                              ("--friction", "90")):
            bad = os.path.join(tmp, "bad")
            r = run(plot + [stab, "-o", bad, option, value], code=1)
            lines = r.stderr.splitlines()
            check(len(lines) == 1 and lines[0].startswith("plot: error: %s %s: " % (option, value)),
                  "%s %s: expected one 'plot: error:' line, got %r" % (option, value, r.stderr))
            check(not os.path.exists(bad), "%s %s: wrote %s" % (option, value, bad))
    print("plot_test: ok: slope.toml's face %.2f/%.2f from %d free contacts; with 60/120 and "
          "phi 5, planar sliding on %s, wedges on %s" % (dip, ddir, count, ", ".join(planar),
                                                        ", ".join(wedges)))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except AssertionError as e:
        print("plot_test: FAILED: %s" % e, file=sys.stderr)
        sys.exit(1)
