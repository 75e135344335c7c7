"""Shared pieces of the Python tests: where the built programs are, free
ports, and real nodes run as child processes."""

from __future__ import annotations

import os
import re
import select
import socket
import subprocess
import tempfile
import time

BINARY_DIR = os.environ.get("TROUPE_BINARY_DIR", "")
SOURCE_DIR = os.environ.get("TROUPE_SOURCE_DIR", "")
TROUPE_NODE = os.path.join(BINARY_DIR, "bin", "troupe-node")
TROUPE_CLI = os.path.join(BINARY_DIR, "bin", "troupe")
ROOM_NODE = os.path.join(BINARY_DIR, "tests", "python", "room_node")
KINEMATIC_CONFIG = os.path.join(SOURCE_DIR, "examples", "nodes", "kinematic.json")
WANDER = os.path.join(SOURCE_DIR, "examples", "python", "wander.py")
TROUPE_SIM = os.path.join(BINARY_DIR, "bin", "troupe-sim")
ROOM_WORLD = os.path.join(SOURCE_DIR, "examples", "worlds", "room.world")


def spin_until(client, done, timeout: float = 10.0) -> bool:
    """Spins `client` until done() holds; False when `timeout` (s, a bound on
    a failing test) passes first."""
    deadline = time.monotonic() + timeout
    while not done():
        if time.monotonic() > deadline:
            return False
        client.spin_once(0.05)
    return True


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def listening(port: int) -> bool:
    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


class NodeProcess:
    """A node program run as a child process, serving on `port`, stopped with SIGTERM."""

    def __init__(self, args: list[str], port: int):
        self.port = port
        self.args = args
        self.proc: subprocess.Popen | None = None

    def start(self) -> "NodeProcess":
        # Its log goes to a file, read while it runs (what it refused and why)
        # and when something fails: a pipe nobody reads would stall the node
        # once full.
        self.log = tempfile.TemporaryFile()
        self.final_log = ""
        self.proc = subprocess.Popen(self.args, stdout=subprocess.DEVNULL, stderr=self.log)
        deadline = time.monotonic() + 10
        while not listening(self.port):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"{self.args[0]} did not start: {self.stderr()}")
            time.sleep(0.02)
        return self

    def stderr(self) -> str:
        """What the node logged so far (all of it once stopped)."""
        if self.log.closed:
            return self.final_log
        self.log.seek(0)
        return self.log.read().decode(errors="replace")

    def wait_for_log(self, text: str, timeout: float = 10.0) -> bool:
        """Whether the node's log has `text` (it may log it a moment after the
        client saw the effect); `timeout` s bounds a failing test."""
        deadline = time.monotonic() + timeout
        while text not in self.stderr():
            if time.monotonic() > deadline:
                return False
            time.sleep(0.02)
        return True

    def stop(self) -> int:
        if self.proc is None:
            return 0
        self.proc.terminate()
        try:
            rc = self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait()
        self.proc = None
        self.final_log = self.stderr()
        self.log.close()
        return rc

    def __enter__(self) -> "NodeProcess":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()


def kinematic_node(port: int) -> NodeProcess:
    """troupe-node serving the kinematic example (position2d:0, 10 Hz)."""
    return NodeProcess([TROUPE_NODE, KINEMATIC_CONFIG, "--port", str(port)], port)


def room_node(port: int, *extra: str) -> NodeProcess:
    """room_node: the kinematic base and a laser in a 6 m square room with a pillar."""
    return NodeProcess([ROOM_NODE, "--port", str(port), *extra], port)


class SimProcess:
    """troupe-sim run as a child process on a port of its own choosing
    (--port 0: it prints "listening on HOST:PORT"), stopped with SIGTERM."""

    def __init__(self, world: str, *extra: str):
        self.args = [TROUPE_SIM, world, "--port", "0", *extra]
        self.port = 0
        self.proc: subprocess.Popen | None = None

    def start(self) -> "SimProcess":
        # Its log goes to a file, read when something fails: a pipe nobody
        # reads would stall the simulator once full.
        self.log = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(self.args, stdout=subprocess.PIPE, stderr=self.log)
        deadline = time.monotonic() + 30
        line = b""
        while not line.endswith(b"\n"):
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self.proc.stdout], [], [], max(left, 0))
            chunk = os.read(self.proc.stdout.fileno(), 1) if ready else b""
            if not chunk:
                self.stop()
                raise RuntimeError(f"troupe-sim printed no port ({' '.join(self.args)}): {line!r} {self.stderr()}")
            line += chunk
        found = re.match(rb"listening on .*:(\d+)$", line.strip())
        if found is None:
            self.stop()
            raise RuntimeError(f"troupe-sim: unexpected first line {line!r} {self.stderr()}")
        self.port = int(found.group(1))
        return self

    def stop(self) -> int:
        if self.proc is None:
            return 0
        self.proc.terminate()
        try:
            rc = self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait()
        self.proc.stdout.close()
        self.proc = None
        return rc

    def stderr(self) -> str:
        """What troupe-sim logged so far."""
        self.log.seek(0)
        return self.log.read().decode(errors="replace")

    def __enter__(self) -> "SimProcess":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
