#!/usr/bin/env python3
"""Builds troupe-node for every board and target and prints its size.

For each row (a board built with a toolchain, linked against the target's
shared libraries or fully statically: TROUPE_STATIC) the table gives the
stripped file, its text + data (what `size` reports for the loaded image),
the difference to the core on the same target linked the same way, and each
driver's share: the sizes of the symbols in its namespace,
troupe::drivers::<driver>. The robot boards are built with secure sessions
(BOARD_SECURE); the core is not, and its "core secure" rows (TROUPE_SECURE=ON)
give their cost. For each secure row a second table breaks the secure
sessions' bytes down: troupe's own Noise code (troupe::wire::noise and
node_secure.cc) and libsodium, by object file of libsodium.a (from the
linker's map; nothing of libsodium is in the file when it is linked as a
shared library).

    boards/size_report.py                     # every row, build/size-report
    boards/size_report.py --only core         # the rows of one board
    boards/size_report.py --build-root DIR    # build folders under DIR

Builds are incremental: a second run only measures. The host build runs it
as `cmake --build build/dev --target size-report`.
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (board, toolchain or None for the board's own, build type or None for the
# board's own, linked statically, secure: True/False, or None for the
# board's own). The plain core on every target is the reference of the
# others. pioneer-p3dx has no static row: Debian's libserial-dev holds no
# static archive.
ROWS = [
    ("core", "arm-linux-gnueabihf", None, False, None),
    ("core", "aarch64-linux-gnu", None, False, None),
    ("core", "powerpc-linux-gnu", None, False, None),
    ("core", "native", "MinSizeRel", False, None),
    ("core", "arm-linux-gnueabihf", None, False, True),
    ("core", "aarch64-linux-gnu", None, False, True),
    ("core", "powerpc-linux-gnu", None, False, True),
    ("pioneer-p3dx", None, None, False, None),
    ("camera", None, None, False, None),
    ("diffbot-can", None, None, False, None),
    ("ppc-node", None, None, False, None),
    ("desktop", None, None, False, None),
    ("host", None, "Release", False, None),
    ("core", "arm-linux-gnueabihf", None, True, None),
    ("core", "aarch64-linux-gnu", None, True, None),
    ("core", "powerpc-linux-gnu", None, True, None),
    ("core", "arm-linux-gnueabihf", None, True, True),
    ("diffbot-can", None, None, True, None),
    ("ppc-node", None, None, True, None),
]

ARCH_NAMES = {
    "arm-linux-gnueabihf": "armhf",
    "aarch64-linux-gnu": "arm64",
    "powerpc-linux-gnu": "powerpc",
}


def run(args, **kwargs):
    return subprocess.run(args, check=True, text=True, **kwargs)


def build(board, toolchain, build_type, static, secure, root, jobs):
    """Configures and builds troupe-node; returns the build's board.json."""
    name = board if toolchain is None else f"{board}-{ARCH_NAMES.get(toolchain, toolchain)}"
    if secure is not None:
        name += "-secure" if secure else "-plain"
    if static:
        name += "-static"
    folder = os.path.join(root, name)
    args = ["cmake", "-S", SOURCE_DIR, "-B", folder, "-G", "Ninja", f"-DTROUPE_BOARD={board}",
            f"-DTROUPE_STATIC={'ON' if static else 'OFF'}"]
    if secure is not None:
        args.append(f"-DTROUPE_SECURE={'ON' if secure else 'OFF'}")
    # The linker's map: which archive member each kept section came from.
    args.append(f"-DCMAKE_EXE_LINKER_FLAGS=-Wl,-Map={os.path.join(folder, 'troupe-node.map')}")
    if toolchain is not None:
        args.append(f"-DTROUPE_TOOLCHAIN={toolchain}")
    if build_type is not None:
        args.append(f"-DCMAKE_BUILD_TYPE={build_type}")
    run(args, stdout=subprocess.DEVNULL)
    run(["cmake", "--build", folder, "--target", "troupe-node", "-j", str(jobs)], stdout=subprocess.DEVNULL)
    with open(os.path.join(folder, "board.json")) as f:
        return json.load(f)


def measure(facts):
    """Sizes of the stripped node, bytes, and each driver's symbols."""
    with tempfile.TemporaryDirectory() as tmp:
        stripped = os.path.join(tmp, "troupe-node")
        run([facts["strip"], "-o", stripped, facts["node"]])
        file_bytes = os.path.getsize(stripped)
        lines = run([facts["size"], "-B", stripped], capture_output=True).stdout.splitlines()
        text, data, bss = (int(v) for v in lines[1].split()[:3])
    symbols = run([facts["nm"], "-S", "-C", facts["node"]], capture_output=True).stdout
    drivers = {d: 0 for d in facts["drivers"]}
    pattern = re.compile(r"^[0-9a-f]+ ([0-9a-f]+) [tTdDrRbB] troupe::drivers::(\w+)::")
    for line in symbols.splitlines():
        m = pattern.match(line)
        if m and m.group(2) in drivers:
            drivers[m.group(2)] += int(m.group(1), 16)
    return {"file": file_bytes, "text": text, "data": data, "bss": bss, "drivers": drivers}


# libsodium's object files (libsodium_la-<name>.o in Debian's archive,
# libsodium_la-<name>.o or <name>.o in one built from source), grouped by
# the primitive they implement. The first pattern that matches wins.
SODIUM_GROUPS = [
    ("X25519 (scalarmult, field arithmetic)", r"x25519|curve25519|scalarmult|ed25519"),
    ("ChaCha20-Poly1305 (AEAD, stream, MAC)", r"chacha|poly1305|aead"),
    ("BLAKE2b (generichash)", r"blake2|generichash"),
    ("randombytes", r"randombytes"),
    ("Argon2 (pwhash, picked by sodium_init)", r"argon2|pwhash"),
    ("sodium_init and its implementation pickers (core, runtime CPU detection)", r"(^|-)(core|runtime)\.o"),
    ("Salsa20 (stream, picked by sodium_init)", r"salsa"),
    ("utils (memzero, compare, allocation)", r"utils|verify|codecs"),
]

# Sections that take room in the loaded image (size's text + data).
NOT_LOADED = re.compile(r"^\.(bss|tbss|comment|debug|note\.GNU-stack|ARM\.attributes|gnu\.attributes|group|stab)")
MAP_ENTRY = re.compile(r"^ (\S+)\s+0x([0-9a-f]+)\s+0x([0-9a-f]+) (\S+)$")
MAP_NAME_ONLY = re.compile(r"^ (\S+)$")
MAP_PLACE = re.compile(r"^\s+0x([0-9a-f]+)\s+0x([0-9a-f]+) (\S+)$")


def archive_members(map_path, archive):
    """Bytes of loaded sections per member of `archive` (a file name such as
    libsodium.a) in a GNU ld map: the sections the link kept."""
    members = {}
    in_map = False
    section = None
    with open(map_path) as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("Linker script and memory map"):
                in_map = True
                continue
            if not in_map:
                continue
            m = MAP_ENTRY.match(line)
            if m:
                name, size, source = m.group(1), int(m.group(3), 16), m.group(4)
            else:
                named = MAP_NAME_ONLY.match(line)
                if named:
                    section = named.group(1)
                    continue
                placed = MAP_PLACE.match(line)
                if not placed or section is None:
                    section = None
                    continue
                name, size, source = section, int(placed.group(2), 16), placed.group(3)
            section = None
            if size == 0 or NOT_LOADED.match(name):
                continue
            a = re.match(r"^(.*/)?([^/(]+)\(([^)]+)\)$", source)
            if a and a.group(2) == archive:
                members[a.group(3)] = members.get(a.group(3), 0) + size
    return members


def secure_breakdown(facts, m, plain):
    """Rows of the secure sessions' bytes of one secure build: libsodium by
    primitive (from the linker map), and the rest of the difference to the
    plain build `plain` (troupe's Noise code, and what it pulls from libc
    and libstdc++)."""
    rows = []
    map_path = os.path.join(os.path.dirname(os.path.dirname(facts["node"])), "troupe-node.map")
    members = archive_members(map_path, "libsodium.a") if os.path.exists(map_path) else {}
    groups = {}
    for member, size in members.items():
        label = next((g for g, p in SODIUM_GROUPS if re.search(p, member)), "other")
        groups.setdefault(label, []).append((member, size))
    total_sodium = 0
    for label, _ in SODIUM_GROUPS + [("other", None)]:
        if label not in groups:
            continue
        size = sum(s for _, s in groups[label])
        total_sodium += size
        names = ", ".join(f"{re.sub(r'^libsodium_la-', '', n)} {s:,}"
                          for n, s in sorted(groups[label], key=lambda x: -x[1]))
        rows.append((f"libsodium: {label}", size, names))
    if not members:
        # Linked against the shared library: none of it is in the node, and
        # all of it is loaded beside it.
        shared = [f for f in os.listdir(facts["sysroot_lib"]) if f.startswith("libsodium.so.")] \
            if facts.get("sysroot_lib") and os.path.isdir(facts["sysroot_lib"]) else []
        if shared:
            path = os.path.join(facts["sysroot_lib"], sorted(shared)[-1])
            lines = run([facts["size"], "-B", path], capture_output=True).stdout.splitlines()
            text, data = (int(v) for v in lines[1].split()[:2])
            rows.append(("libsodium (not in the node)", 0,
                         f"{os.path.basename(path)}, loaded beside it: {text + data:,} bytes of text + data"))
        else:
            rows.append(("libsodium (not in the node)", 0, "a shared library"))
    if plain is not None:
        delta = m["text"] + m["data"] - plain["text"] - plain["data"]
        rows.append(("troupe's Noise code, node_secure.cc, what they take of libc/libstdc++",
                     delta - total_sodium, "the rest of the difference to the plain build"))
    return rows


def target_name(facts):
    if facts["cross"] == "TRUE":
        return facts["deb_arch"]
    return f"native {facts['deb_arch']}"


def is_secure(facts):
    return facts.get("secure") == "ON"


def link_name(facts):
    return "static" if facts.get("static") == "ON" else "dynamic"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-root", default=os.path.join(SOURCE_DIR, "build", "size-report"))
    parser.add_argument("--only", action="append", help="board to report (repeatable)")
    parser.add_argument("--jobs", type=int, default=2, help="parallel compile jobs (default 2)")
    opts = parser.parse_args()

    rows = []
    for board, toolchain, build_type, static, secure in ROWS:
        if opts.only and board not in opts.only:
            continue
        compiler = None if toolchain in (None, "native") else f"{toolchain}-g++"
        if compiler and shutil.which(compiler) is None:
            print(f"size_report: skipping {board} for {toolchain}: {compiler} is not installed", file=sys.stderr)
            continue
        try:
            facts = build(board, toolchain, build_type, static, secure, opts.build_root, opts.jobs)
        except subprocess.CalledProcessError as e:
            print(f"size_report: {board} ({toolchain or 'its toolchain'}) did not build: {e}", file=sys.stderr)
            return 1
        rows.append((facts, measure(facts)))

    # The plain core of the same target, linked the same way, is each row's
    # reference.
    core = {(target_name(f), link_name(f)): m for f, m in rows if f["board"] == "core" and not is_secure(f)}
    print("| board | target | build | link | secure | stripped file, bytes | text + data, bytes | vs core "
          "| drivers (symbols, bytes) |")
    print("|---|---|---|---|---|---:|---:|---:|---|")
    for facts, m in rows:
        target = target_name(facts)
        image = m["text"] + m["data"]
        ref = core.get((target, link_name(facts)))
        delta = "" if ref is None or ref is m else f"{image - ref['text'] - ref['data']:+,}"
        drivers = ", ".join(f"{d} {n:,}" for d, n in m["drivers"].items()) or "none"
        print(f"| {facts['board']} | {target} | {facts['build_type'] or 'none'} | {link_name(facts)} "
              f"| {'yes' if is_secure(facts) else 'no'} | {m['file']:,} | {image:,} | {delta} | {drivers} |")

    # What secure sessions take, in the secure cores (the difference to the
    # plain core of the same target and link is theirs alone).
    for facts, m in rows:
        if facts["board"] != "core" or not is_secure(facts):
            continue
        print(f"\nSecure sessions in core, {target_name(facts)}, {link_name(facts)}:\n")
        print("| part | text + data, bytes | objects (bytes) |")
        print("|---|---:|---|")
        for label, size, detail in secure_breakdown(facts, m, core.get((target_name(facts), link_name(facts)))):
            print(f"| {label} | {size:,} | {detail} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
