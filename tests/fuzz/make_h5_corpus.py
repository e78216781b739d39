#!/usr/bin/python3
"""Makes the HDF5 seed corpora of fuzz_h5 (tests/fuzz/corpus/h5/): the files the tools write
from a small scene (joints, blocks, pruned blocks, blocks with /geometry) and a few crafted
variants that the readers must refuse with a message (other element types, shapes, string
layouts, storage); and of fuzz_export (corpus/export/): geom.h5 files of small scenes that the
exporters write, with names that must not break a script, a [rock] table (rock bridges), a 2-D
section, and a scene name that is no UTF-8. Run by hand after a schema change, with the
release tools built:

    /usr/bin/python3 tests/fuzz/make_h5_corpus.py [build/tools]

Debian's h5py (python3-h5py) writes the crafted files; /usr/bin/python3 has it.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "corpus", "h5")
OUT_EXPORT = os.path.join(HERE, "corpus", "export")

# A small scene that still fills every group: a regular and a stochastic set, a polygon
# joint, a boundary joint (boundary blocks), a construction joint (clusters) and a zone.
SCENE = """\
[scene]
seed = 3
[domain]
box = { min = [0, 0, 0], max = [4, 3, 2] }
[[joints]]
dip = 30
dip_direction = 45
point = [2, 1.5, 1]
polygon_uv = [[-1, -1], [1, -1], [1, 1], [-1, 1]]
kind = "construction"
[[joints]]
dip = 0
dip_direction = 0
point = [0, 0, 0.5]
kind = "boundary"
keep = "below"
[[sets]]
name = "s"
dip = 80
dip_direction = 100
spacing = 1.5
[[sets]]
name = "r"
dip = 70
dip_direction = 250
count = 2
size = { distribution = "fixed", value = 2 }
[[zones]]
box = { min = [0, 0, 1.5], max = [1, 1, 2] }
"""


# The same scene with a [rock] table and a finite rock joint (rock-bridge contacts in 3DEC), and
# names that must stay inside their strings and comments: quotes, a backslash, line breaks
# ("\r" ends a Python line too), a bell.
SCENE_NAMES = SCENE.replace("seed = 3", r'''seed = 3
name = "it's \"quoted\" \\ a\rb\nc \u0007 \u00e9"''').replace(
    'name = "s"', r'name = "s\r\nimport os"') + """
[[joints]]
dip = 60
dip_direction = 300
point = [2, 2, 1]
polygon_uv = [[-0.8, -0.8], [0.8, -0.8], [0.8, 0.8], [-0.8, 0.8]]
[rock]
friction_angle = 50
cohesion = 3e6
tension = 1.5e6
"""

# A 2-D section (docs/2d.md): the YADE export writes prisms, the 3DEC export refuses it.
SECTION = """\
[scene]
dimension = 2
[domain]
box = { min = [0, 0], max = [4, 3] }
[[joints]]
dip = 0
dip_direction = 0
point = [0, 0.5]
kind = "boundary"
keep = "below"
[[sets]]
name = "a"
dip = 60
dip_direction = 90
spacing = 1.5
[[sets]]
name = "b"
dip = 30
dip_direction = 270
spacing = 2
"""


def geometry_of(tools, scene, tmp, name):
    """geom.h5 of `scene` (text) by the real tools, as corpus/export/<name>."""
    with open(os.path.join(tmp, "scene.toml"), "w") as f:
        f.write(scene)
    run(tools, "slice-joints", "scene.toml", "-o", "j.h5", cwd=tmp)
    run(tools, "slice-cut", "j.h5", "--prune", "-o", "p.h5", cwd=tmp)
    run(tools, "slice-vertices", "p.h5", "-o", "g.h5", cwd=tmp)
    shutil.copyfile(os.path.join(tmp, "g.h5"), os.path.join(OUT_EXPORT, name))


def run(tools, tool, *args, cwd):
    subprocess.run([os.path.join(tools, tool), "-q", *args], cwd=cwd, check=True)


def craft(src, dst, change):
    shutil.copyfile(src, dst)
    with h5py.File(dst, "r+") as f:
        change(f)


def replace(f, path, data):
    del f[path]
    f[path] = data


def main():
    tools = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build/tools")
    os.makedirs(OUT, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(tmp, "small.toml"), "w") as f:
            f.write(SCENE)
        # Relative names, so that the provenance attributes hold no machine's paths.
        run(tools, "slice-joints", "small.toml", "-o", "joints.h5", cwd=tmp)
        run(tools, "slice-cut", "joints.h5", "-o", "blocks.h5", cwd=tmp)
        run(tools, "slice-cut", "joints.h5", "--prune", "-o", "pruned.h5", cwd=tmp)
        run(tools, "slice-vertices", "pruned.h5", "-o", "geom.h5", cwd=tmp)
        for name in ["joints.h5", "blocks.h5", "pruned.h5", "geom.h5"]:
            shutil.copyfile(os.path.join(tmp, name), os.path.join(OUT, name))

    j = os.path.join(OUT, "joints.h5")
    g = os.path.join(OUT, "geom.h5")
    out = lambda name: os.path.join(OUT, name)
    # Element types: float32 normals (converts to double), int64 kinds (too wide for uint8).
    craft(j, out("joints-float32.h5"),
          lambda f: replace(f, "joints/normal", f["joints/normal"][()].astype(np.float32)))
    craft(j, out("joints-kind-int64.h5"),
          lambda f: replace(f, "joints/kind", f["joints/kind"][()].astype(np.int64)))
    # Shapes: normals as (n, 2), a 1-D d read as 2-D.
    craft(j, out("joints-normal-2cols.h5"),
          lambda f: replace(f, "joints/normal", f["joints/normal"][:, :2]))
    # h5py's variable-length strings (refused: one string layout).
    def vlen_kind(f):
        del f.attrs["kind"]
        f.attrs["kind"] = "joints"  # h5py writes str as a variable-length string
    craft(j, out("joints-vlen-kind.h5"), vlen_kind)
    # Chunked, compressed storage (valid HDF5, another code path in the library).
    def chunked(f):
        for name in ["normal", "centre"]:
            data = f["joints/" + name][()]
            del f["joints/" + name]
            f.create_dataset("joints/" + name, data=data, chunks=True, compression="gzip")
    craft(j, out("joints-gzip.h5"), chunked)
    # /geometry: a face index out of its block, and a missing dataset.
    def bad_face_vertex(f):
        fv = f["geometry/face_vertices"][()]
        fv[0] = 1000
        replace(f, "geometry/face_vertices", fv)
    craft(g, out("geom-face-vertex-out.h5"), bad_face_vertex)
    craft(g, out("geom-no-volume.h5"), lambda f: f.__delitem__("geometry/volume"))
    # Only the root attributes of a joints file.
    def header_only(f):
        for name in list(f.keys()):
            del f[name]
    craft(j, out("header-only.h5"), header_only)
    os.makedirs(OUT_EXPORT, exist_ok=True)
    shutil.copyfile(g, os.path.join(OUT_EXPORT, "geom.h5"))
    with tempfile.TemporaryDirectory() as tmp:
        geometry_of(tools, SCENE_NAMES, tmp, "geom-names-rock.h5")
        geometry_of(tools, SECTION, tmp, "geom-section.h5")
    # A scene name that is no UTF-8 (a damaged file; a scene file cannot give one).
    def bad_utf8_name(f):
        del f.attrs["name"]
        f.attrs.create("name", np.bytes_(b"bad \xff\xfe utf-8 \xed\xa0\x80"))
    craft(g, os.path.join(OUT_EXPORT, "geom-name-not-utf8.h5"), bad_utf8_name)
    for out_dir in [OUT, OUT_EXPORT]:
        total = sum(os.path.getsize(os.path.join(out_dir, n)) for n in os.listdir(out_dir))
        print(f"{len(os.listdir(out_dir))} files, {total} bytes in {out_dir}")


if __name__ == "__main__":
    main()
