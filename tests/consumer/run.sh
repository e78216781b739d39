#!/usr/bin/env bash
# ctest "the installed package builds a consumer project": installs the build into a temporary
# prefix, then configures, builds and runs tests/consumer against it with find_package(rockslice).
# Any step that fails fails the test; nothing is skipped.
# Usage: run.sh BUILD_DIR CONSUMER_SOURCE_DIR [cmake arguments for the consumer...]
set -euo pipefail
if (($# < 2)); then
  echo "usage: run.sh BUILD_DIR CONSUMER_SOURCE_DIR [cmake arguments...]" >&2
  exit 2
fi
build=$1 source=$2
shift 2

tmp=$(mktemp -d "${TMPDIR:-/tmp}/rockslice-consumer.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix"
cmake -S "$source" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$prefix" "$@" 2>&1 | tee "$tmp/configure.log"
# The package must come from this prefix, not from some other install on the machine.
found=$(sed -n 's/^rockslice_DIR:PATH=//p' "$tmp/build/CMakeCache.txt")
if [[ $found != "$prefix"/* ]]; then
  echo "run.sh: find_package(rockslice) used '$found', not the install in $prefix" >&2
  exit 1
fi
# The package's config must not warn (a warning in a consumer's configure is a bug of ours).
if grep -n "CMake Warning" "$tmp/configure.log" >&2; then
  echo "run.sh: configuring the consumer gave warnings (above)" >&2
  exit 1
fi
cmake --build "$tmp/build"
"$tmp/build/consumer"
