#!/usr/bin/env bash
# ctest tests of pipelines/render (issue 24, item 6). Nothing is skipped: a missing pvpython,
# Xvfb or tool fails the test.
#   render_test.sh concurrent TOOLS_DIR SOURCE_DIR BUILD_DIR
#     slices data/cube-3sets.toml into blocks.vtu with the real tools, renders it twice at the
#     same time, and checks both runs exit 0, say they coloured by block volume and looked from
#     the South-East, and both pictures are 1000 x 620 PNG images that show blocks (many
#     colours, mostly not background).
#   render_test.sh stability TOOLS_DIR SOURCE_DIR BUILD_DIR
#     slices data/slope.toml, runs slice-stability (free faces +z,+x, a seismic load towards the
#     East: blocks fail on the slope face) and exports stab.vtu; renders it as is and with
#     --view 270,30, and checks: exit 0; the line says it coloured by factor of safety and
#     looked from the exposed blocks' side (the East, azimuth 90, for the first) or from the
#     view asked for; the pictures are 1000 x 620 PNGs, mostly the light grey of blocks that
#     cannot move, with the factor of safety's colours (its red for fos 0 and pale yellow for 1,
#     which the volume colours do not have) and more than one colour of it on the blocks; the
#     two views differ.
#   render_test.sh bad-input TOOLS_DIR SOURCE_DIR BUILD_DIR
#     a missing blocks.vtu, a file that is no VTU, a missing output folder and bad --view
#     values: each exits 1 with exactly one line on stderr that names the file or the value,
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
    for p in a b; do  # a VTU without fos: as before, volume colours from the South-East
      grep -q 'coloured by block volume; seen from the South-East$' "$tmp/$p.err" ||
        fail "$p.png: not volume colours from the South-East: $(cat "$tmp/$p.err")"
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
    fos='coloured by factor of safety \(0\.\.2, 1 in the middle\)'
    grep -qE "$fos: [0-9]+ of [0-9]+ blocks can move, [1-9][0-9]* below 1" "$tmp/exposed.err" ||
      fail "exposed.png: the line does not say fos colours with blocks below 1"
    # The slope face dips East and the +x face is free: the exposed blocks lie East of the rock.
    grep -qE 'seen from azimuth 90, elevation 30: the side of the [0-9]+ exposed blocks$' \
      "$tmp/exposed.err" || fail "exposed.png: not seen from the East, the exposed blocks' side"
    grep -qE 'coloured by factor of safety.*seen from azimuth 270, elevation 30 \(--view\)$' \
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
    ;;
  bad-input)
    echo 'not a VTU' >"$tmp/junk.vtu"
    mkdir "$tmp/pictures"
    expect_bad "$tmp/missing.vtu" "$tmp/missing.vtu" "$tmp/pictures/a.png"
    expect_bad "$tmp/junk.vtu" "$tmp/junk.vtu" "$tmp/pictures/b.png"
    expect_bad "$tmp/no/such/folder" "$tmp/junk.vtu" "$tmp/no/such/folder/c.png"
    expect_bad "--view 10,95" --view 10,95 "$tmp/junk.vtu" "$tmp/pictures/d.png"
    expect_bad "--view east" --view east "$tmp/junk.vtu" "$tmp/pictures/e.png"
    expect_bad "unknown option --colour" --colour red "$tmp/junk.vtu" "$tmp/pictures/f.png"
    [ -z "$(ls -A "$tmp/pictures")" ] || fail "files left in pictures/: $(ls -A "$tmp/pictures")"
    ;;
  *)
    echo "render_test: unknown mode $mode" >&2
    exit 2
    ;;
esac
exit "$failed"
