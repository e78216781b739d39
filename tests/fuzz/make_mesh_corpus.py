#!/usr/bin/python3
"""Makes the seed corpora of fuzz_obj and fuzz_stl (tests/fuzz/corpus/obj/, corpus/stl/):
small closed meshes the readers accept (a cube, a tetrahedron; OBJ with the usual extras,
ASCII and binary STL) and a few they refuse (an open mesh, an inside-out one, a binary STL
whose triangle count disagrees with its size). Run by hand:

    /usr/bin/python3 tests/fuzz/make_mesh_corpus.py
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

CUBE_V = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
# Quads counter-clockwise seen from outside (0-based).
CUBE_F = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def triangles(faces):
    return [(f[0], f[k], f[k + 1]) for f in faces for k in range(1, len(f) - 1)]


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def obj(vertices, faces, extras=False, negative=False):
    lines = ["# rockslice fuzz seed", "o mesh"] if extras else []
    lines += ["v %g %g %g" % v for v in vertices]
    if extras:
        lines += ["vt 0 0", "vn 0 0 1", "g side", "usemtl rock", "s off"]
    n = len(vertices)
    for f in faces:
        if negative:
            items = [str(k - n) for k in f]
        elif extras:
            items = ["%d/1/1" % (k + 1) for k in f]
        else:
            items = [str(k + 1) for k in f]
        lines.append("f " + " ".join(items))
    return ("\n".join(lines) + "\n").encode()


def ascii_stl(vertices, faces, name="mesh", upper=False):
    out = ["solid " + name]
    for t in triangles(faces):
        p = [vertices[k] for k in t]
        out.append("  facet normal %g %g %g" % normal(*p))
        out.append("    outer loop")
        out += ["      vertex %g %g %g" % x for x in p]
        out.append("    endloop")
        out.append("  endfacet")
    out.append("endsolid " + name)
    text = "\n".join(out) + "\n"
    return (text.upper() if upper else text).encode()


def binary_stl(vertices, faces, count=None, header=b"binary rockslice fuzz seed"):
    tris = triangles(faces)
    data = header.ljust(80, b" ") + struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        p = [vertices[k] for k in t]
        data += struct.pack("<12fH", *normal(*p), *p[0], *p[1], *p[2], 0)
    return data


def main():
    files = {
        "obj/cube.obj": obj(CUBE_V, CUBE_F),
        "obj/tetrahedron.obj": obj(TET_V, TET_F),
        "obj/cube-extras.obj": obj(CUBE_V, CUBE_F, extras=True),
        "obj/cube-negative-indices.obj": obj(CUBE_V, CUBE_F, negative=True),
        "obj/cube-open.obj": obj(CUBE_V, CUBE_F[:-1]),
        "obj/tetrahedron-inside-out.obj": obj(TET_V, [f[::-1] for f in TET_F]),
        "stl/cube-ascii.stl": ascii_stl(CUBE_V, CUBE_F),
        "stl/tetrahedron-ascii-upper.stl": ascii_stl(TET_V, TET_F, upper=True),
        "stl/tetrahedron-binary.stl": binary_stl(TET_V, TET_F),
        "stl/cube-binary-solid-header.stl": binary_stl(CUBE_V, CUBE_F, header=b"solid cube"),
        "stl/cube-binary-wrong-count.stl": binary_stl(CUBE_V, CUBE_F, count=13),
        "stl/tetrahedron-ascii-open.stl": ascii_stl(TET_V, TET_F[:-1]),
    }
    for name, data in files.items():
        with open(os.path.join(HERE, "corpus", name), "wb") as f:
            f.write(data)
    print(f"{len(files)} files, {sum(len(d) for d in files.values())} bytes")


if __name__ == "__main__":
    main()
