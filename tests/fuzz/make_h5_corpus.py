#!/usr/bin/python3
"""Makes the HDF5 seed corpus of fuzz_h5 (tests/fuzz/corpus/h5/): the files the tools write
from a small scene (joints, blocks, pruned blocks, blocks with /geometry) and a few crafted
variants that the readers must refuse with a message (other element types, shapes, string
layouts, storage). Run by hand after a schema change, with the release tools built:

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
    total = sum(os.path.getsize(os.path.join(OUT, n)) for n in os.listdir(OUT))
    print(f"{len(os.listdir(OUT))} files, {total} bytes in {OUT}")


if __name__ == "__main__":
    main()
