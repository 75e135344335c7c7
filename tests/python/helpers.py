"""Shared pieces of the Python tests: where the built programs are, free
ports, and real nodes run as child processes."""

from __future__ import annotations

import os
import socket
import subprocess
import time

BINARY_DIR = os.environ.get("TROUPE_BINARY_DIR", "")
SOURCE_DIR = os.environ.get("TROUPE_SOURCE_DIR", "")
TROUPE_NODE = os.path.join(BINARY_DIR, "runtime", "troupe-node")
ROOM_NODE = os.path.join(BINARY_DIR, "tests", "python", "room_node")
KINEMATIC_CONFIG = os.path.join(SOURCE_DIR, "examples", "nodes", "kinematic.json")
WANDER = os.path.join(SOURCE_DIR, "examples", "python", "wander.py")


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
        self.proc = subprocess.Popen(self.args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        deadline = time.monotonic() + 10
        while not listening(self.port):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"{self.args[0]} did not start: {self.proc.stderr.read().decode()}")
            time.sleep(0.02)
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
        self.proc.stderr.close()
        self.proc = None
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
