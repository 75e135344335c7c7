#!/bin/sh
# toolchain_is_fixed.sh SOURCE_DIR BUILD_DIR
# Configures the core for armhf, then asks the same folder for powerpc:
# CMake cannot change a build folder's compiler, so the second configure
# must fail and say so (ctest matches the message).
set -u
src=$1
dir=$2
if ! command -v arm-linux-gnueabihf-g++ >/dev/null 2>&1; then
  echo "skipped: arm-linux-gnueabihf-g++ is not installed"
  exit 77
fi
rm -rf "$dir"
cmake -S "$src" -B "$dir" -G Ninja -DTROUPE_BOARD=core >/dev/null || exit 1
cmake -S "$src" -B "$dir" -DTROUPE_TOOLCHAIN=powerpc-linux-gnu 2>&1
status=$?
rm -rf "$dir"
[ $status -ne 0 ]
