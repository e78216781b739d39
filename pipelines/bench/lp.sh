#!/bin/sh
# The LP benchmark: runs slice-bench-lp from an existing build and plots its CSV.
#   pipelines/bench/lp.sh BUILD_DIR [slice-bench-lp options, e.g. --count 200 --ipopt-count 20]
# Writes pipelines/bench/results/lp.csv and lp.png. Builds nothing: build the tool first
#   cmake --build BUILD_DIR --target slice-bench-lp
set -eu
if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [slice-bench-lp options]" >&2
  exit 1
fi
build=$1
shift
here=$(cd "$(dirname "$0")" && pwd)
tool="$build/tools/slice-bench-lp"
if [ ! -x "$tool" ]; then
  echo "$0: $tool not found; build it with: cmake --build $build --target slice-bench-lp" >&2
  exit 1
fi
mkdir -p "$here/results"
"$tool" -o "$here/results/lp.csv.partial" "$@"
mv "$here/results/lp.csv.partial" "$here/results/lp.csv"
# Debian's python3 has matplotlib; the python3 first on PATH may not.
/usr/bin/python3 "$here/plot_lp.py" "$here/results/lp.csv" "$here/results/lp.png"
echo "$0: wrote $here/results/lp.csv and lp.png" >&2
