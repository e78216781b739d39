#!/usr/bin/env bash
# ctest tests of pipelines/render (issue 24, item 6). Nothing is skipped: a missing pvpython,
# Xvfb or tool fails the test.
#   render_test.sh concurrent TOOLS_DIR SOURCE_DIR BUILD_DIR
#     slices data/cube-3sets.toml into blocks.vtu with the real tools, renders it twice at the
#     same time, and checks both runs exit 0, say they coloured by volume and looked from the
#     South-East, and both pictures are 1000 x 620 PNG images that show blocks (many colours,
#     mostly not background). Then data/rock-slope.toml (the example's scene) with --view free:
#     the slope face dips East, so the camera looks from azimuth 90 + 30 (turned towards the
#     South) at the elevation of the free faces' mean normal, and the volume range is numpy's
#     2nd and 98th percentiles of the VTU's volumes; --view free on cube-3sets (no face off the
#     box, no stability arrays) falls back to the South-East and says why.
#   render_test.sh stability TOOLS_DIR SOURCE_DIR BUILD_DIR
#     slices data/slope.toml, runs slice-stability (free faces +z,+x, a seismic load towards the
#     East: blocks fail on the slope face) and exports stab.vtu; renders it as is and with
#     --view 270,30, and checks: exit 0; the line says it coloured by factor of safety and
#     looked from outside the exposed blocks' free faces (azimuth 120, elevation 45: the slope
#     faces East and up, turned 30 towards the South) or from the view asked for; the pictures
#     are 1000 x 620 PNGs, mostly the light grey of blocks that cannot move, with the factor of
#     safety's colours (its red for fos 0 and pale yellow for 1, which the volume colours do
#     not have) and more than one colour of it on the blocks; the two views differ. Then:
#     --view west looks along the same direction as --view 270,30, top straight down;
#     --color-by volume and --color-by fos --range p5,p95 report numpy's percentiles of the
#     array's finite values; a copy of stab.vtu whose NaN fos are +inf gives the same range;
#     --range 0.5,1.5 is taken as given; data/cube-3sets.toml with slice-stability
#     --free-faces -x (a West face) is seen from azimuth 240 (270 turned towards the South),
#     20 up; data/open-cut.toml's cut (it faces East) from azimuth 120, 45 up.
#   render_test.sh bad-input TOOLS_DIR SOURCE_DIR BUILD_DIR
#     a missing blocks.vtu, a file that is no VTU, a missing output folder, bad --view,
#     --range and --scale values and an unknown --color-by array (the line lists the arrays
#     present): each exits 1 with exactly one line on stderr that names the file or the value,
#     and leaves no picture.
set -uo pipefail
if (($# != 4)); then
  echo "usage: render_test.sh concurrent|stability|bad-input TOOLS_DIR SOURCE_DIR BUILD_DIR" >&2
  exit 2
fi
mode=$1 tools=$2 source=$3
export SLICE_BUILD_DIR=$4  # where pipelines/setup unpacked pvpython
render=$source/pipelines/render
tmp=$(mktemp -d "${TMPDIR:-/tmp}/rockslice-render.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() { echo "render_test: FAILED: $*" >&2; failed=1; }

# Runs render with the given arguments; checks exit 1, one stderr line naming $1, no picture
# (the last argument).
expect_bad() {
  local names=$1 code lines
  shift
  bash "$render" "$@" >"$tmp/out" 2>"$tmp/err"
  code=$?
  lines=$(wc -l <"$tmp/err")
  [ "$code" = 1 ] || fail "render $*: exit $code, expected 1; stderr: $(cat "$tmp/err")"
  [ "$lines" = 1 ] || fail "render $*: $lines lines on stderr, expected 1: $(cat "$tmp/err")"
  grep -q '^render: error: ' "$tmp/err" || fail "render $*: no 'render: error:' line"
  grep -qF -- "$names" "$tmp/err" || fail "render $*: the line does not name $names"
  [ ! -e "${!#}" ] || fail "render $*: left ${!#} behind"
  echo "render_test: render $* -> exit $code: $(cat "$tmp/err")"
}

# Checks render's one line (stderr file $1) against the VTU $2: the range of array $3 is
# numpy's percentiles $4,$5 of its finite values (a vector's lengths; kind $6 = p, or empty)
# or the values $4,$5 (kind v); with $7 $8 given, the camera is at azimuth $7, elevation $8
# and looks along minus that offset; with $9, that picture is a 1000 x 620 PNG.
check_line() {
  /usr/bin/python3 - "$@" <<'EOF' || fail "$1: $(head -c 600 "$1")"
import math, re, struct, sys
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
err, vtu, name, a, b, kind, az, el, png = (sys.argv[1:] + [''] * 9)[:9]
line = open(err).read()
assert line.count('\n') == 1, 'not one line: %r' % line
m = re.search(r'coloured by (\S+) from (\S+) to (\S+) \(', line)
assert m and m.group(1) == name, 'no "coloured by %s from LO to HI": %s' % (name, line)
lo, hi = float(m.group(2)), float(m.group(3))
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(vtu)
r.Update()
v = vtk_to_numpy(r.GetOutput().GetCellData().GetArray(name)).astype(float)
if v.ndim == 2:  # a vector: its length
    v = np.sqrt((v * v).sum(axis=1))
v = v[np.isfinite(v)]
want = np.percentile(v, [float(a), float(b)]) if kind in ('', 'p') else [float(a), float(b)]
assert (math.isclose(lo, want[0], rel_tol=1e-8, abs_tol=1e-12)
        and math.isclose(hi, want[1], rel_tol=1e-8, abs_tol=1e-12)), \
    'range %r..%r, expected %r..%r (%s %s,%s of %d finite values)' % (
        lo, hi, want[0], want[1], kind or 'p', a, b, v.size)
if az:
    s = re.search(r'seen from azimuth (\S+), elevation (\S+) ', line)
    assert s and (float(s.group(1)), float(s.group(2))) == (float(az), float(el)), \
        'not seen from azimuth %s, elevation %s: %s' % (az, el, line)
    look = [float(x) for x in re.search(r'looking along \((.*)\)$', line).group(1).split(',')]
    t, e = math.radians(float(az)), math.radians(float(el))
    step = [math.sin(t) * math.cos(e), math.cos(t) * math.cos(e), math.sin(e)]
    assert all(abs(x + y) < 1e-5 for x, y in zip(look, step)), \
        'looking along %r, not %r' % (look, [-y for y in step])
if png:
    with open(png, 'rb') as f:
        head = f.read(24)
    assert head[:8] == b'\x89PNG\r\n\x1a\n', '%s: not a PNG' % png
    assert struct.unpack('>II', head[16:24]) == (1000, 620), '%s: not 1000 x 620' % png
print('render_test: %s: %s %r..%r as expected (%s %s,%s)%s' % (
    png or vtu, name, lo, hi, kind or 'p', a, b,
    ', azimuth %s, elevation %s' % (az, el) if az else ''))
EOF
}

# Renders (bash pipelines/render "$@"), stderr into $tmp/<picture's name>.err; fails on exit != 0.
draw() {
  local err="$tmp/$(basename -- "${!#}").err"
  bash "$render" "$@" 2>"$err" || fail "render $*: exit $?: $(cat "$err")"
}

case $mode in
  concurrent)
    set -e
    "$tools/slice-joints" -q "$source/data/cube-3sets.toml" -o "$tmp/joints.h5"
    "$tools/slice-cut" -q "$tmp/joints.h5" -o "$tmp/blocks.h5" --prune
    "$tools/slice-vertices" -q "$tmp/blocks.h5" -o "$tmp/geom.h5"
    "$tools/slice-export" -q "$tmp/geom.h5" --format vtu -o "$tmp/blocks.vtu"
    set +e
    bash "$render" "$tmp/blocks.vtu" "$tmp/a.png" 2>"$tmp/a.err" &
    a=$!
    bash "$render" "$tmp/blocks.vtu" "$tmp/b.png" 2>"$tmp/b.err" &
    b=$!
    wait "$a"; code_a=$?
    wait "$b"; code_b=$?
    [ "$code_a" = 0 ] || fail "first render: exit $code_a: $(cat "$tmp/a.err")"
    [ "$code_b" = 0 ] || fail "second render: exit $code_b: $(cat "$tmp/b.err")"
    for p in a b; do  # a VTU without fos: volume colours from the South-East, as before
      grep -qE 'coloured by volume from .*; seen from the South-East; looking along' \
        "$tmp/$p.err" || fail "$p.png: not volume colours from the South-East: $(cat "$tmp/$p.err")"
    done
    for p in a b; do
      /usr/bin/python3 - "$tmp/$p.png" <<'EOF' || fail "$p.png is not the picture expected"
import struct, sys
import matplotlib.image
import numpy as np
path = sys.argv[1]
with open(path, "rb") as f:
    head = f.read(24)
assert head[:8] == b"\x89PNG\r\n\x1a\n", "%s: not a PNG" % path
w, h = struct.unpack(">II", head[16:24])
assert (w, h) == (1000, 620), "%s: %d x %d, expected 1000 x 620" % (path, w, h)
img = matplotlib.image.imread(path)[..., :3]
assert img.shape == (620, 1000, 3), img.shape
colours = len(np.unique((img * 255).round().astype(np.uint8).reshape(-1, 3), axis=0))
drawn = float(np.mean(np.any(img < 0.98, axis=2)))  # not the white background
assert colours > 50 and drawn > 0.2, "%s: %d colours, %.0f %% drawn" % (path, colours, 100 * drawn)
print("render_test: %s: %d x %d PNG, %d colours, %.0f %% of it drawn" % (path, w, h, colours,
                                                                        100 * drawn))
EOF
    done
    # No face off the bounding box, no stability arrays: --view free says so and falls back.
    draw --view free "$tmp/blocks.vtu" "$tmp/nothing.png"
    cat "$tmp/nothing.png.err"
    grep -qE 'seen from the South-East \(--view free: nothing tells where the free faces are: no' \
      "$tmp/nothing.png.err" || fail "nothing.png: --view free did not fall back, saying why"
    # The example's scene and picture: the slope face dips East (63.4 degrees), the gallery's
    # walls face every way: the free faces' mean normal points East and up.
    set -e
    "$tools/slice-joints" -q "$source/data/rock-slope.toml" -o "$tmp/rs-joints.h5"
    "$tools/slice-cut" -q "$tmp/rs-joints.h5" -o "$tmp/rs-blocks.h5" --prune
    "$tools/slice-vertices" -q "$tmp/rs-blocks.h5" -o "$tmp/rs-geom.h5"
    "$tools/slice-export" -q "$tmp/rs-geom.h5" --format vtu -o "$tmp/rock-slope.vtu"
    set +e
    draw --view free "$tmp/rock-slope.vtu" "$tmp/rock-slope.png"
    cat "$tmp/rock-slope.png.err"
    grep -qE 'off the bounding box: their mean outward normal points to azimuth 9[0-9],' \
      "$tmp/rock-slope.png.err" || fail "rock-slope.png: the free faces do not face East"
    seen='s/.*seen from azimuth ([0-9]+), elevation ([0-9]+) .*'
    az=$(sed -nE "$seen/\1/p" "$tmp/rock-slope.png.err")
    el=$(sed -nE "$seen/\2/p" "$tmp/rock-slope.png.err")
    [ -n "$az" ] && ((az >= 120 && az <= 129 && el >= 20 && el <= 45)) ||
      fail "rock-slope.png: azimuth '$az', elevation '$el', expected 120..129 and 20..45"
    check_line "$tmp/rock-slope.png.err" "$tmp/rock-slope.vtu" volume 2 98 p "${az:-0}" \
      "${el:-0}" "$tmp/rock-slope.png"
    grep -q 'log scale' "$tmp/rock-slope.png.err" ||
      fail "rock-slope.png: volume not on a log scale"
    ;;
  stability)
    set -e
    "$tools/slice-joints" -q "$source/data/slope.toml" -o "$tmp/joints.h5"
    "$tools/slice-cut" -q "$tmp/joints.h5" -o "$tmp/blocks.h5" --prune
    "$tools/slice-vertices" -q "$tmp/blocks.h5" -o "$tmp/geom.h5"
    "$tools/slice-stability" -q "$tmp/geom.h5" -o "$tmp/stab.h5" --free-faces +z,+x \
      --seismic 0.3 --seismic-azimuth 90
    "$tools/slice-export" -q "$tmp/stab.h5" --format vtu -o "$tmp/stab.vtu"
    set +e
    bash "$render" "$tmp/stab.vtu" "$tmp/exposed.png" 2>"$tmp/exposed.err" ||
      fail "render stab.vtu: exit $?: $(cat "$tmp/exposed.err")"
    bash "$render" --view 270,30 "$tmp/stab.vtu" "$tmp/west.png" 2>"$tmp/west.err" ||
      fail "render --view 270,30 stab.vtu: exit $?: $(cat "$tmp/west.err")"
    cat "$tmp/exposed.err" "$tmp/west.err"
    fos='coloured by fos from 0 to 2 \(fixed: 1 in the middle, linear scale\)'
    grep -qE "$fos: [0-9]+ of [0-9]+ blocks can move, [1-9][0-9]* below 1" "$tmp/exposed.err" ||
      fail "exposed.png: the line does not say fos colours with blocks below 1"
    # The slope face dips East (45 degrees) and the bench beside it is flat: the exposed blocks'
    # free faces off the box face East and up, steeper than 45.
    seen='seen from azimuth 120, elevation 45 \(a stability VTU\): outside the .* free faces'
    seen+=' off the bounding box of the [0-9]+ exposed blocks: their mean outward normal points'
    seen+=' to azimuth 90, elevation (4[5-9]|[5-7][0-9]), turned 30 towards the South; looking'
    grep -qE "$seen" \
      "$tmp/exposed.err" || fail "exposed.png: not seen from outside the exposed blocks' faces"
    check_line "$tmp/exposed.err" "$tmp/stab.vtu" fos 0 2 v 120 45 "$tmp/exposed.png"
    grep -qE 'coloured by fos.*seen from azimuth 270, elevation 30 \(--view 270,30\); looking' \
      "$tmp/west.err" || fail "west.png: the line does not say fos colours and --view 270,30"
    /usr/bin/python3 - "$tmp/exposed.png" "$tmp/west.png" <<'EOF' || fail "no fos colours"
import struct, sys
import matplotlib.image
import numpy as np
shots = []
for path in sys.argv[1:]:
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", "%s: not a PNG" % path
    w, h = struct.unpack(">II", head[16:24])
    assert (w, h) == (1000, 620), "%s: %d x %d, expected 1000 x 620" % (path, w, h)
    img = matplotlib.image.imread(path)[..., :3].astype(float)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    drawn = np.any(img < 0.98, axis=2)  # not the white background
    spread = img.max(axis=2) - img.min(axis=2)
    # Blocks that cannot move: the NaN colour, light grey (0.82), shaded (the light kit warms it
    # a little: 177, 174, 165).
    grey = drawn & (spread < 0.07)
    # fos 0: ColorBrewer's dark red (0.65, 0, 0.15); fos 1: pale yellow (1, 1, 0.75). Viridis,
    # the volume colours, has neither (its yellow has b < 0.2).
    # Both in the scalar bar (x >= 880; the orientation axes' x arrow is red too).
    red = (r > 0.55) & (g < 0.15) & (b < 0.25)
    pale = (r > 0.93) & (g > 0.93) & (b > 0.6) & (b < 0.85)
    red[:, :880] = pale[:, :880] = False
    # Blocks that can move, on the model: not the scalar bar, not the orientation axes (bottom
    # left).
    hue = drawn & (spread > 0.15)
    hue[:, 880:] = False
    hue[440:, :180] = False
    colours = len(np.unique((img[hue] * 16).astype(int), axis=0))
    print("render_test: %s: %.0f %% drawn, %.0f %% of it grey; %d red and %d pale yellow "
          "pixels; %d pixels of %d fos colours on the blocks"
          % (path, 100 * drawn.mean(), 100 * grey.sum() / drawn.sum(), red.sum(), pale.sum(),
             hue.sum(), colours))
    assert drawn.mean() > 0.1, "%s: nearly empty" % path
    assert grey.sum() > 0.5 * drawn.sum(), "%s: the blocks that cannot move are not grey" % path
    assert red.sum() >= 50 and pale.sum() >= 50, "%s: no fos colour map (red, pale yellow)" % path
    assert hue.sum() >= 200 and colours >= 4, "%s: no blocks coloured by fos" % path
    shots.append(img)
assert np.mean(np.any(np.abs(shots[0] - shots[1]) > 0.1, axis=2)) > 0.1, \
    "--view 270,30 drew the same picture as the exposed side"
EOF
    # A named view is its azimuth at 30 degrees up; top looks straight down. Colours by any
    # array from numpy's percentiles of its finite values; fos +inf (the HDF5's "cannot move";
    # slice-export writes NaN) does not move the range.
    /usr/bin/python3 - "$tmp/stab.vtu" "$tmp/inf.vtu" <<'EOF' || fail "could not write inf.vtu"
import sys
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(sys.argv[1])
r.Update()
g = r.GetOutput()
fos = vtk_to_numpy(g.GetCellData().GetArray('fos'))  # a view: writes go to the array
fos[np.isnan(fos)] = np.inf
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetFileName(sys.argv[2])
w.SetInputData(g)
w.SetDataModeToBinary()  # inline base64: raw appended data stops ParaView 5.11 (docs/dem-exports.md)
assert w.Write() == 1
EOF
    draw --view west "$tmp/stab.vtu" "$tmp/named.png" &
    draw --view top --color-by volume "$tmp/stab.vtu" "$tmp/volume.png" &
    draw --color-by fos --range p5,p95 --view 200,10 "$tmp/stab.vtu" "$tmp/p5.png" &
    wait
    draw --colour-by fos --range p5,p95 --view 200,10 "$tmp/inf.vtu" "$tmp/inf.png" &
    draw --view s --color-by fos --range 0.5,1.5 "$tmp/stab.vtu" "$tmp/values.png" &
    draw --color-by direction "$tmp/stab.vtu" "$tmp/direction.png" &
    wait
    cat "$tmp"/{named,volume,p5,inf,values,direction}.png.err
    check_line "$tmp/named.png.err" "$tmp/stab.vtu" fos 0 2 v 270 30 "$tmp/named.png"
    check_line "$tmp/volume.png.err" "$tmp/stab.vtu" volume 2 98 p 180 90 "$tmp/volume.png"
    check_line "$tmp/p5.png.err" "$tmp/stab.vtu" fos 5 95 p 200 10 "$tmp/p5.png"
    check_line "$tmp/inf.png.err" "$tmp/inf.vtu" fos 5 95 p 200 10 "$tmp/inf.png"
    check_line "$tmp/values.png.err" "$tmp/stab.vtu" fos 0.5 1.5 v 180 30 "$tmp/values.png"
    check_line "$tmp/direction.png.err" "$tmp/stab.vtu" direction 2 98 p
    cmp -s "$tmp/p5.png" "$tmp/inf.png" || fail "fos +inf drew another picture than NaN"
    # A free face known: cube-3sets with only its West side (-x) free; data/open-cut.toml's
    # cut faces East. Both seen from outside, turned 30 towards the South.
    set -e
    "$tools/slice-joints" -q "$source/data/cube-3sets.toml" -o "$tmp/c-joints.h5"
    "$tools/slice-cut" -q "$tmp/c-joints.h5" -o "$tmp/c-blocks.h5" --prune
    "$tools/slice-vertices" -q "$tmp/c-blocks.h5" -o "$tmp/c-geom.h5"
    "$tools/slice-stability" -q "$tmp/c-geom.h5" -o "$tmp/c-stab.h5" --free-faces -x
    "$tools/slice-export" -q "$tmp/c-stab.h5" --format vtu -o "$tmp/west-face.vtu"
    "$tools/slice-joints" -q "$source/data/open-cut.toml" -o "$tmp/o-joints.h5"
    "$tools/slice-cut" -q "$tmp/o-joints.h5" -o "$tmp/o-blocks.h5" --prune
    "$tools/slice-vertices" -q "$tmp/o-blocks.h5" -o "$tmp/o-geom.h5"
    "$tools/slice-export" -q "$tmp/o-geom.h5" --format vtu -o "$tmp/open-cut.vtu"
    set +e
    draw --view free "$tmp/west-face.vtu" "$tmp/west-face.png" &
    draw --view free "$tmp/open-cut.vtu" "$tmp/open-cut.png" &
    wait
    cat "$tmp/west-face.png.err" "$tmp/open-cut.png.err"
    check_line "$tmp/west-face.png.err" "$tmp/west-face.vtu" fos 0 2 v 240 20 \
      "$tmp/west-face.png"
    grep -q 'mean outward normal points to azimuth 270, elevation 0,' "$tmp/west-face.png.err" ||
      fail "west-face.png: the free faces do not face West"
    check_line "$tmp/open-cut.png.err" "$tmp/open-cut.vtu" volume 2 98 p 120 45 \
      "$tmp/open-cut.png"
    ;;
  bad-input)
    echo 'not a VTU' >"$tmp/junk.vtu"
    mkdir "$tmp/pictures"
    expect_bad "$tmp/missing.vtu" "$tmp/missing.vtu" "$tmp/pictures/a.png"
    expect_bad "$tmp/junk.vtu" "$tmp/junk.vtu" "$tmp/pictures/b.png"
    expect_bad "$tmp/no/such/folder" "$tmp/junk.vtu" "$tmp/no/such/folder/c.png"
    expect_bad "--view 10,95" --view 10,95 "$tmp/junk.vtu" "$tmp/pictures/d.png"
    expect_bad "--view eastward" --view eastward "$tmp/junk.vtu" "$tmp/pictures/e.png"
    expect_bad "--view west,91" --view west,91 "$tmp/junk.vtu" "$tmp/pictures/e.png"
    expect_bad "--range p2,98" --range p2,98 "$tmp/junk.vtu" "$tmp/pictures/e.png"
    expect_bad "--range 1,0" --range 1,0 "$tmp/junk.vtu" "$tmp/pictures/e.png"
    expect_bad "--range p0,p101" --range p0,p101 "$tmp/junk.vtu" "$tmp/pictures/e.png"
    expect_bad "--scale lin" --scale lin "$tmp/junk.vtu" "$tmp/pictures/e.png"
    # An array the VTU does not have: the line lists those it has.
    "$tools/slice-joints" -q "$source/data/cube-3sets.toml" -o "$tmp/joints.h5" &&
      "$tools/slice-cut" -q "$tmp/joints.h5" -o "$tmp/blocks.h5" --prune &&
      "$tools/slice-vertices" -q "$tmp/blocks.h5" -o "$tmp/geom.h5" &&
      "$tools/slice-export" -q "$tmp/geom.h5" --format vtu -o "$tmp/blocks.vtu" ||
      fail "could not make blocks.vtu"
    expect_bad 'no cell array "fos"; the cell arrays are block_id, volume, inradius' \
      --color-by fos "$tmp/blocks.vtu" "$tmp/pictures/g.png"
    expect_bad "--scale log: the range of block_id starts at 0" --scale log --color-by block_id \
      "$tmp/blocks.vtu" "$tmp/pictures/h.png"
    expect_bad "unknown option --colour" --colour red "$tmp/junk.vtu" "$tmp/pictures/f.png"
    [ -z "$(ls -A "$tmp/pictures")" ] || fail "files left in pictures/: $(ls -A "$tmp/pictures")"
    ;;
  *)
    echo "render_test: unknown mode $mode" >&2
    exit 2
    ;;
esac
exit "$failed"
