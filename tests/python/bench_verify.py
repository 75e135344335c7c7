#!/usr/bin/env python3
"""What verification costs the Python client: per frame, the verifier alone
and a proxy's decoding, next to reading the same fields with the generated
accessors unverified (the baseline), as medians over repeats, and ratios.
Not a test (it asserts nothing); run it by hand:

    PYTHONPATH=build/host-release/wire/python python3 tests/python/bench_verify.py
"""

from __future__ import annotations

import statistics
import time

import sample_frames as S
import troupe
from troupe.wire.Position2dState import Position2dState
from troupe.wire.RangerScan import RangerScan

REPEATS = 7


def per_frame_us(fn, frame: bytes, n: int) -> float:
    """Median over REPEATS of the time per call, us."""
    times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        for _ in range(n):
            fn(frame)
        times.append((time.perf_counter() - t0) / n * 1e6)
    return statistics.median(times)


def main() -> None:
    verifier = troupe.Verifier()
    client = troupe.Client("127.0.0.1", 1, reconnect=False)  # never connected: its proxies only decode
    base = troupe.Position2dProxy(client)
    laser = troupe.RangerProxy(client)

    def unverified_position(frame: bytes) -> None:
        m = troupe.Message(frame, 4 + int.from_bytes(frame[4:8], "little"))
        s = m.body_as(Position2dState)
        s.Pose().X(), s.Pose().Y(), s.Pose().A(), s.Vel().X(), s.Stall(), s.Fault()

    def unverified_scan(frame: bytes) -> None:
        m = troupe.Message(frame, 4 + int.from_bytes(frame[4:8], "little"))
        s = m.body_as(RangerScan)
        [s.Ranges(i) * s.Scale() for i in range(s.RangesLength())]

    def proxy(p):
        def run(frame: bytes) -> None:
            p._receive(troupe.decode(frame, verifier))
        return run

    cases = [
        ("position2d state", S.position2d(), unverified_position, proxy(base), 20000),
        ("ranger, 16 sonars", S.ranger(beams=16), unverified_scan, proxy(laser), 10000),
        ("ranger, 181-beam laser", S.ranger(beams=181), unverified_scan, proxy(laser), 3000),
        ("ranger, 361-beam laser", S.ranger(beams=361), unverified_scan, proxy(laser), 2000),
        ("device list, 100 devices", S.device_list(count=100), None, None, 300),
    ]
    print(f"Python {'.'.join(map(str, __import__('sys').version_info[:3]))}, medians of {REPEATS} runs, us per frame\n")
    print("| frame | bytes | generated accessors, unverified | verify only | verify + proxy decode | verify / baseline "
          "| (verify + decode) / baseline |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, frame, baseline, decode, n in cases:
        v = per_frame_us(verifier.verify, frame, n)
        if baseline is None:
            print(f"| {name} | {len(frame)} | - | {v:.1f} | - | - | - |")
            continue
        b = per_frame_us(baseline, frame, n)
        d = per_frame_us(decode, frame, n)
        print(f"| {name} | {len(frame)} | {b:.1f} | {v:.1f} | {d:.1f} | {v / b:.2f} | {d / b:.2f} |")


if __name__ == "__main__":
    main()
