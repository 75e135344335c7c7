#!/usr/bin/env bash
# Troupe's two commands, for a fresh Debian 12 machine (run from the checkout):
#
#   ./run.sh demo    install what is missing, build, run the main job
#   ./run.sh test    install what is missing, build with sanitizers, run every test
#
# Packages come from Debian's archive (apt-get; sudo when not root). Builds
# go to build/<preset>/ (see CMakePresets.json).
set -euo pipefail
cd "$(dirname "$0")"

# What building needs, and what the tests need on top.
BUILD_PACKAGES=(cmake ninja-build g++ libflatbuffers-dev flatbuffers-compiler
  libeigen3-dev libpng-dev zlib1g-dev libserial-dev)
TEST_PACKAGES=(libgtest-dev clang-14 libclang-rt-14-dev
  qemu-system-x86 busybox-static cpio iproute2
  g++-arm-linux-gnueabihf g++-aarch64-linux-gnu g++-powerpc-linux-gnu qemu-user)

say() { printf '\n== %s\n' "$*"; }

install_packages() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  say "installing ${missing[*]}"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
}

build() {
  say "building (preset $1)"
  cmake --preset "$1" >/dev/null
  cmake --build --preset "$1" -j "$(nproc)"
}

NODE_PID=""
stop_node() {
  [ -n "$NODE_PID" ] && kill "$NODE_PID" 2>/dev/null && wait "$NODE_PID" 2>/dev/null
  return 0
}

demo() {
  install_packages "${BUILD_PACKAGES[@]}"
  build host-release
  local bin=build/host-release port=6665
  local troupe="$bin/wire/cli/troupe" host="localhost:$port"
  say "starting troupe-node with examples/nodes/kinematic.json"
  "$bin/runtime/troupe-node" examples/nodes/kinematic.json --port "$port" &
  NODE_PID=$!
  trap stop_node EXIT
  for _ in $(seq 50); do "$troupe" ls "$host" >/dev/null 2>&1 && break; sleep 0.1; done
  if ! kill -0 "$NODE_PID" 2>/dev/null; then
    echo "troupe-node did not start (its error is above; is port $port in use?)" >&2
    exit 1
  fi
  say "troupe ls $host"
  "$troupe" ls "$host"
  say "driving position2d:0 around a 1 m square with goto commands"
  local corner=1
  for goal in "1 0 1.5708" "1 1 3.1416" "0 1 -1.5708" "0 0 0"; do
    # shellcheck disable=SC2086  # goal is three numbers
    "$troupe" cmd "$host" position2d:0 goto $goal
    sleep 7
    printf 'corner %d (goal %s): ' "$corner" "$goal"
    "$troupe" echo "$host" position2d:0 --count 1
    corner=$((corner + 1))
  done
  say "done"
  cat <<EOT
The robot was a kinematic base inside troupe-node, driven over the wire by
the troupe CLI. To keep playing:

  $bin/runtime/troupe-node examples/nodes/kinematic.json &
  $troupe teleop localhost position2d:0      # drive with the keyboard
  $troupe echo localhost position2d:0        # watch its odometry
  $troupe help                               # every command
EOT
}

run_tests() {
  install_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
  build host-asan
  say "running every test under AddressSanitizer and UBSan"
  ctest --preset host-asan -j "$(nproc)"
  # What cannot run under the sanitizers: the statically linked program that
  # boots in a VM with a kernel CAN bus. Only its targets are built.
  say "building what the kernel CAN test needs (preset host-release)"
  cmake --preset host-release >/dev/null
  cmake --build --preset host-release -j "$(nproc)" --target odrive_vcan_test
  say "running the kernel CAN bus test in a VM"
  ctest --test-dir build/host-release -L vcan --output-on-failure
}

case "${1:-}" in
  demo) demo ;;
  test) run_tests ;;
  *)
    echo "usage: ./run.sh demo|test" >&2
    exit 2
    ;;
esac
