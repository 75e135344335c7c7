#!/usr/bin/env python3
"""wander: drives a robot around without hitting anything, steered by its
ranger (Stage's classic wander controller, over the Troupe Python client).

It drives forward while the way ahead is clear, turns away from whatever
comes close, and now and then picks a new random heading drift so that it
explores instead of circling. Randomness comes from one seeded generator.

    wander.py [HOST[:PORT]] [--robot NAME] [--ranger INDEX] [--speed M/S]
              [--duration S] [--seed N]

examples:
    troupe-sim examples/worlds/room.world &  # one robot, its laser is ranger:0
    wander.py localhost                      # position2d:0 and ranger:0
    wander.py localhost:7000 --robot r3 --ranger 1 --duration 60

PYTHONPATH must name the built package: <build>/wire/python.
"""

from __future__ import annotations

import argparse
import math
import random
import sys
import time
from dataclasses import dataclass

import troupe


@dataclass
class WanderParams:
    #: Cruise speed, m/s.
    speed: float = 0.4
    #: Turn rate when avoiding, rad/s.
    turn_rate: float = 1.0
    #: An obstacle nearer than this in the front sector makes the robot turn on the spot, m.
    stop_distance: float = 0.7
    #: Nearer than this, it slows down and bends away, m.
    slow_distance: float = 1.4
    #: Half-width of the front sector, rad.
    front_half_angle: float = math.radians(40)
    #: Largest random heading drift, rad/s, re-drawn every `drift_period` s.
    max_drift: float = 0.3
    drift_period: float = 2.0


class Wander:
    """The controller, free of any connection: feed it scans, get velocities."""

    def __init__(self, params: WanderParams, rng: random.Random):
        self.params = params
        self.rng = rng
        self._drift = 0.0
        self._drift_until = -1.0
        self._turn_sign = 0.0

    def step(self, ranges: list[float], bearings: list[float], now: float) -> tuple[float, float]:
        """The velocity (m/s forward, rad/s) for a scan: ranges (m) at bearings
        (rad, robot frame) taken at time `now` (s)."""
        p = self.params
        if now >= self._drift_until:
            self._drift = self.rng.uniform(-p.max_drift, p.max_drift)
            self._drift_until = now + p.drift_period
        front = [r for r, b in zip(ranges, bearings) if abs(b) <= p.front_half_angle]
        nearest = min(front, default=math.inf)
        # Which side has more room: compare the mean clearance left and right.
        left = [min(r, p.slow_distance * 2) for r, b in zip(ranges, bearings) if b > 0]
        right = [min(r, p.slow_distance * 2) for r, b in zip(ranges, bearings) if b < 0]
        roomier = 1.0 if sum(left) / max(len(left), 1) >= sum(right) / max(len(right), 1) else -1.0
        if nearest < p.stop_distance:
            # Keep turning the way we started until the front is clear, so
            # the robot does not dither in a corner.
            if self._turn_sign == 0.0:
                self._turn_sign = roomier
            return 0.0, self._turn_sign * p.turn_rate
        self._turn_sign = 0.0
        if nearest < p.slow_distance:
            closeness = (p.slow_distance - nearest) / (p.slow_distance - p.stop_distance)
            return p.speed * (1.0 - 0.7 * closeness), roomier * p.turn_rate * closeness
        return p.speed, self._drift


def run(client: troupe.Client, base: troupe.Position2dProxy, ranger: troupe.RangerProxy, wander: Wander,
        duration: float) -> int:
    """Drives until `duration` s have passed (0: forever); returns scans handled."""
    start = time.monotonic()
    scans = 0
    try:
        while duration <= 0 or time.monotonic() - start < duration:
            client.spin_once(0.1)
            if not ranger.fresh():
                continue
            bearings = [ranger.bearing(i) for i in range(ranger.count)]
            vx, va = wander.step(ranger.ranges, bearings, time.monotonic() - start)
            base.set_velocity(vx, 0.0, va)
            scans += 1
    finally:
        base.set_velocity(0.0, 0.0, 0.0)
        client.sync()
    return scans


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description="Drive a robot around obstacles with its ranger.",
                                 epilog="examples:\n  wander.py localhost\n"
                                        "  wander.py localhost:7000 --robot r3 --ranger 1 --duration 60",
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("host", nargs="?", default="localhost", help="HOST[:PORT] of the node or simulator")
    ap.add_argument("--robot", default="", help="robot name or number (default: robot 0)")
    ap.add_argument("--position", type=int, default=0, help="position2d index (default 0)")
    ap.add_argument("--ranger", type=int, default=0, help="ranger index (default 0)")
    ap.add_argument("--speed", type=float, default=WanderParams.speed, help="cruise speed, m/s")
    ap.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds (0: Ctrl-C)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the random heading drift")
    args = ap.parse_args(argv)
    try:
        host, port = troupe.parse_host(args.host)
    except ValueError as e:
        ap.error(str(e))
    client = troupe.Client(host, port, name="wander")
    if not client.connect():
        print(f"wander: {client.error}", file=sys.stderr)
        return 1
    prefix = f"{args.robot}/" if args.robot else ""
    base_addr = client.resolve(f"{prefix}position2d:{args.position}")
    ranger_addr = client.resolve(f"{prefix}ranger:{args.ranger}")
    if base_addr is None or ranger_addr is None:
        print(f"wander: {client.error}", file=sys.stderr)
        return 1
    base = troupe.Position2dProxy(client, addr=base_addr)
    ranger = troupe.RangerProxy(client, addr=ranger_addr)
    if not base.is_open or not ranger.is_open:
        print(f"wander: {client.error}", file=sys.stderr)
        return 1
    wander = Wander(WanderParams(speed=args.speed), random.Random(args.seed))
    try:
        scans = run(client, base, ranger, wander, args.duration)
    except KeyboardInterrupt:
        return 0
    print(f"wander: {scans} scans, stopped at x={base.x:.2f} y={base.y:.2f}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
