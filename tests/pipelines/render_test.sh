#!/usr/bin/env bash
# ctest tests of pipelines/render (issue 24, item 6). Nothing is skipped: a missing pvpython,
# Xvfb or tool fails the test.
#   render_test.sh concurrent TOOLS_DIR SOURCE_DIR BUILD_DIR
#     slices data/cube-3sets.toml into blocks.vtu with the real tools, renders it twice at the
#     same time, and checks both runs exit 0 and both pictures are 1000 x 620 PNG images that
#     show blocks (many colours, mostly not background).
#   render_test.sh bad-input TOOLS_DIR SOURCE_DIR BUILD_DIR
#     a missing blocks.vtu, a file that is no VTU and a missing output folder: each exits 1
#     with exactly one line on stderr that names the file, and leaves no picture.
set -uo pipefail
if (($# != 4)); then
  echo "usage: render_test.sh concurrent|bad-input TOOLS_DIR SOURCE_DIR BUILD_DIR" >&2
  exit 2
fi
mode=$1 tools=$2 source=$3
export SLICE_BUILD_DIR=$4  # where pipelines/setup unpacked pvpython
render=$source/pipelines/render
tmp=$(mktemp -d "${TMPDIR:-/tmp}/rockslice-render.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() { echo "render_test: FAILED: $*" >&2; failed=1; }

# Runs render with the given arguments; checks exit 1, one stderr line naming $1, no picture.
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
  [ ! -e "$2" ] || fail "render $*: left $2 behind"
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
  bad-input)
    echo 'not a VTU' >"$tmp/junk.vtu"
    mkdir "$tmp/pictures"
    expect_bad "$tmp/missing.vtu" "$tmp/missing.vtu" "$tmp/pictures/a.png"
    expect_bad "$tmp/junk.vtu" "$tmp/junk.vtu" "$tmp/pictures/b.png"
    expect_bad "$tmp/no/such/folder" "$tmp/junk.vtu" "$tmp/no/such/folder/c.png"
    [ -z "$(ls -A "$tmp/pictures")" ] || fail "files left in pictures/: $(ls -A "$tmp/pictures")"
    ;;
  *)
    echo "render_test: unknown mode $mode" >&2
    exit 2
    ;;
esac
exit "$failed"
