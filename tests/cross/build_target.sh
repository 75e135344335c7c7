#!/bin/sh
# build_target.sh SOURCE_DIR BUILD_DIR BOARD TOOLCHAIN [static] [secure|plain]
#
# The set-up step of the cross tests: configures, builds and packages one
# board for one target (with the target-side test helpers), incrementally.
# With "static", the node is linked fully statically (TROUPE_STATIC); with
# "secure" or "plain", it is built with or without secure sessions whatever
# the board says (TROUPE_SECURE; the board's BOARD_SECURE otherwise).
# Exits 77, which ctest reports as skipped, when the cross compiler is not
# installed.
set -eu

src=$1
dir=$2
board=$3
toolchain=$4
static=OFF
secure=""
shift 4
for word in "$@"; do
  case "$word" in
    static) static=ON ;;
    secure) secure=-DTROUPE_SECURE=ON ;;
    plain) secure=-DTROUPE_SECURE=OFF ;;
    *) echo "$0: unknown option $word (static, secure, plain)" >&2; exit 2 ;;
  esac
done

if ! command -v "$toolchain-g++" >/dev/null 2>&1; then
  echo "skipped: $toolchain-g++ is not installed (apt-get install g++-$toolchain)"
  exit 77
fi
cmake -S "$src" -B "$dir" -G Ninja -DTROUPE_BOARD="$board" -DTROUPE_TOOLCHAIN="$toolchain" \
  -DTROUPE_TARGET_TEST_TOOLS=ON -DTROUPE_WERROR=ON -DTROUPE_STATIC="$static" $secure >/dev/null
# Two jobs at most: the machine's cores are shared (the build steps of the
# cross tests hold a ctest resource lock, so only one runs at a time).
cmake --build "$dir" -j 2
cmake --build "$dir" --target package >/dev/null
echo "built $board for $toolchain in $dir"
