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

# What building needs, and what the tests need on top (the demo installs
# only the first list: its build leaves the tests out).
BUILD_PACKAGES=(cmake ninja-build g++ libflatbuffers-dev flatbuffers-compiler
  libeigen3-dev libpng-dev zlib1g-dev libserial-dev libboost-dev libcli11-dev
  cyclonedds-dev cyclonedds-tools libsodium-dev libopenmpi-dev openmpi-bin)
TEST_PACKAGES=(libgtest-dev pkgconf clang-14 libclang-rt-14-dev
  qemu-system-x86 busybox-static cpio iproute2
  g++-arm-linux-gnueabihf g++-aarch64-linux-gnu g++-powerpc-linux-gnu qemu-user systemd
  autoconf automake libtool make patch xz-utils
  python3 python3-flatbuffers python3-nacl python3-pil chromium
  libfastrtps-dev fastddsgen default-jre-headless tshark
  golang-go golang-github-flynn-noise-dev)

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
  # A Debian mirror caught mid-sync serves an index whose size does not match
  # its Release file ("Mirror sync in progress?"), and apt-get update then
  # fails as a whole. That usually heals within minutes: retry with growing
  # pauses. An index that stays broken (seen for days: bookworm-security's
  # armhf list, which the cross tests' sysroots add) must not stop the
  # install: go on with the indexes that did arrive (apt-get install says
  # clearly if a package is then missing).
  local pause
  for pause in 15 45 120 0; do
    $sudo apt-get -o Acquire::Retries=3 update && break
    [ "$pause" -eq 0 ] && { echo "apt-get update kept failing; trying the install with the indexes there are" >&2; break; }
    echo "apt-get update failed; trying again in $pause s" >&2
    sleep "$pause"
  done
  for pause in 30 90 0; do
    DEBIAN_FRONTEND=noninteractive $sudo apt-get -o Acquire::Retries=3 install -y \
      --no-install-recommends "${missing[@]}" && return 0
    [ "$pause" -eq 0 ] && return 1
    echo "apt-get install failed; refreshing the indexes and trying again in $pause s" >&2
    sleep "$pause"
    $sudo apt-get -o Acquire::Retries=3 update || true
  done
}

# The viewer's page is built with npm (packages from the npm registry, into
# the build tree). A Node.js that is already there (Debian's or another) is
# kept: Debian's npm package would fight another vendor's nodejs.
install_node() {
  command -v npm >/dev/null 2>&1 && command -v node >/dev/null 2>&1 && return 0
  install_packages nodejs npm
}

# build PRESET [CMAKE ARGS...]
build() {
  local preset=$1
  shift
  say "building (preset $preset)"
  cmake --preset "$preset" "$@" >/dev/null
  cmake --build --preset "$preset" -j "$(nproc)"
}

# The demo's build leaves the tests out (BUILD_TESTING=OFF), so it needs
# neither GoogleTest nor anything the tests run; a build folder already
# configured with its tests keeps them.
demo_testing() {
  grep -qs '^BUILD_TESTING:BOOL=ON$' "build/$1/CMakeCache.txt" && echo ON || echo OFF
}

SIM_PID=""
stop_sim() {
  [ -n "$SIM_PID" ] && kill "$SIM_PID" 2>/dev/null && wait "$SIM_PID" 2>/dev/null
  SIM_PID=""
  return 0
}

# The main job: troupe-sim on the bundled swarm world, its 100 robots driven
# over the wire by separate client connections, then a picture of the end.
demo() {
  install_packages "${BUILD_PACKAGES[@]}"
  install_node
  build host-release -DBUILD_TESTING="$(demo_testing host-release)"
  local bin=build/host-release port=6665 out=build/demo
  local troupe="$bin/bin/troupe" host="localhost:$port"
  local world=examples/worlds/swarm100.world
  mkdir -p "$out"
  say "starting troupe-sim on $world (100 robots, 4x real time, no in-process controllers)"
  "$bin/bin/troupe-sim" "$world" --no-ctrl --speed 4 --port "$port" \
    --snapshot "$out/swarm100.png" --log "$out/swarm100.csv" &
  SIM_PID=$!
  trap stop_sim EXIT
  for _ in $(seq 100); do "$troupe" ls "$host" >/dev/null 2>&1 && break; sleep 0.1; done
  if ! kill -0 "$SIM_PID" 2>/dev/null; then
    echo "troupe-sim did not start (its error is above; is port $port in use?)" >&2
    exit 1
  fi
  local devices
  devices=$("$troupe" ls "$host")
  say "troupe ls $host (the first 8 of $(wc -l <<<"$devices") devices)"
  head -n 8 <<<"$devices"
  say "driving every robot over the wire: swarm-clients, one connection per robot, 30 s"
  echo "(watch it in a browser meanwhile: the viewer URL troupe-sim printed above)"
  "$bin/bin/swarm-clients" "$host" --seconds 30
  say "robot b0's odometry, read over the wire"
  "$troupe" echo "$host" b0/position2d:0 --count 1
  say "stopping troupe-sim"
  stop_sim
  say "done"
  cat <<EOT
The robots gathered into clusters (the mean distance above fell), each
driven by its own client connection, exactly as real robots would be.

  $out/swarm100.png    the arena, robots and sonar beams at the end
  $out/swarm100.csv    every robot's pose at every step (time,robot,x,y,a)

To keep playing (the tools are in $bin/bin):

  troupe-sim $world &
      the swarm with its in-process controllers; open the viewer URL it prints
  troupe ls localhost                            every robot's devices
  troupe echo localhost b7/ranger:0              a robot's sonar ring
  troupe teleop localhost b7/position2d:0        drive one with the keyboard
  troupe req localhost simulation:0 getpose b7   its ground truth
  troupe help                                    every command
EOT
}

run_tests() {
  install_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
  install_node
  build host-asan
  say "running every test under AddressSanitizer and UBSan"
  ctest --preset host-asan -j "$(nproc)"
  # What cannot run under the sanitizers: the statically linked program that
  # boots in a VM with a kernel CAN bus and the kernel's virtual camera
  # (vivid). Only their targets are built.
  say "building what the kernel VM tests need (preset host-release)"
  cmake --preset host-release >/dev/null
  cmake --build --preset host-release -j "$(nproc)" --target odrive_vcan_test v4l2_vivid_test
  say "running the kernel CAN bus and V4L2 camera tests in a VM"
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
