"""Proxies of world knowledge: localize, map, simulation."""

from __future__ import annotations

from typing import NamedTuple

from troupe.wire import LocalizeSetPose as _setpose
from troupe.wire import MapTileRequest as _tilereq
from troupe.wire import SimModel as _model
from troupe.wire import SimPose as _simpose
from troupe.wire import SimSpeed as _speed
from troupe.wire import SimStep as _step
from troupe.wire.Access import Access
from troupe.wire.Body import Body
from troupe.wire.Cell import Cell
from troupe.wire.Cov2d import Cov2d, CreateCov2d
from troupe.wire.Interface import Interface
from troupe.wire.LocalizeReqSub import LocalizeReqSub
from troupe.wire.LocalizeState import LocalizeState
from troupe.wire.MapInfo import MapInfo
from troupe.wire.MapReqSub import MapReqSub
from troupe.wire.MapTile import MapTile
from troupe.wire.Pose2d import CreatePose2d, Pose2d
from troupe.wire.SimClock import SimClock
from troupe.wire.SimPose import SimPose
from troupe.wire.SimulationReqSub import SimulationReqSub

from .address import Address
from .client import Client
from .proxy import Pose2, Proxy, pose2, scalar_vector


class Hypothesis(NamedTuple):
    #: Map frame: m, m, rad.
    mean: Pose2
    #: xx, xy, xa, yy, ya, aa: m^2, m*rad, rad^2.
    cov: tuple[float, ...]
    #: Share of the belief, 0..1.
    weight: float


class LocalizeProxy(Proxy):
    """Pose hypotheses from a localizer, best first."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Localize, index, robot))
        self.hypotheses: list[Hypothesis] = []
        # The localizer says it is lost: the hypotheses are not to be trusted.
        self.lost = False
        self._attach()

    def _update(self, msg) -> None:
        s = msg.body_as(LocalizeState)
        if s is None:
            return
        self.lost = bool(s.Lost())
        self.hypotheses = []
        for i in range(s.HypothesesLength()):
            h = s.Hypotheses(i)
            c = h.Cov(Cov2d())
            self.hypotheses.append(Hypothesis(pose2(h.Mean(Pose2d())), (c.Xx(), c.Xy(), c.Xa(), c.Yy(), c.Ya(), c.Aa()),
                                              h.Weight()))

    def set_pose(self, x: float, y: float, a: float, sx: float, sy: float, sa: float) -> bool:
        """Starts pose tracking from a pose (m, m, rad) with standard deviations (m, m, rad)."""
        b = self.client.begin()
        _setpose.LocalizeSetPoseStart(b)
        _setpose.LocalizeSetPoseAddCov(b, CreateCov2d(b, sx * sx, 0, 0, sy * sy, 0, sa * sa))
        _setpose.LocalizeSetPoseAddMean(b, CreatePose2d(b, x, y, a))
        body = _setpose.LocalizeSetPoseEnd(b)
        return self._request(LocalizeReqSub.SetPose, Body.LocalizeSetPose, body).ok

    def global_localization(self) -> bool:
        """Restarts global localization (the C++ global())."""
        return self._request(LocalizeReqSub.Global).ok


class GridMap(NamedTuple):
    width: int  # cells
    height: int  # cells
    resolution: float  # m per cell
    origin: Pose2  # pose of cell (0,0)'s corner: m, m, rad
    #: Cell values (Cell.Free, Occupied, Unknown), row-major from (0,0).
    cells: bytearray


class MapProxy(Proxy):
    """An occupancy grid, fetched in tiles."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Map, index, robot))
        self._attach(Access.Write)  # requests only: maps do not stream data

    def fetch(self, tile: int = 256) -> GridMap | None:
        """The whole map, in tiles of at most tile x tile cells; None on failure."""
        r = self._request(MapReqSub.Info)
        info = r.message.body_as(MapInfo) if r.ok else None
        if info is None:
            return None
        w, h = info.Width(), info.Height()
        cells = bytearray([Cell.Unknown]) * (w * h)
        tile = max(tile, 1)
        for row in range(0, h, tile):
            for col in range(0, w, tile):
                tw, th = min(tile, w - col), min(tile, h - row)
                b = self.client.begin()
                _tilereq.MapTileRequestStart(b)
                _tilereq.MapTileRequestAddCol(b, col)
                _tilereq.MapTileRequestAddRow(b, row)
                _tilereq.MapTileRequestAddWidth(b, tw)
                _tilereq.MapTileRequestAddHeight(b, th)
                reply = self._request(MapReqSub.Tile, Body.MapTileRequest, _tilereq.MapTileRequestEnd(b), 5.0)
                t = reply.message.body_as(MapTile) if reply.ok else None
                packed = scalar_vector(t, "troupe.wire.MapTile", "cells", "B") if t is not None else ()
                if t is None or t.Width() != tw or t.Height() != th or len(packed) < (tw * th + 3) // 4:
                    self.client.error = f"bad map tile at ({col}, {row})"
                    return None
                for i in range(tw * th):
                    cells[(row + i // tw) * w + col + i % tw] = (packed[i // 4] >> (2 * (i % 4))) & 3
        return GridMap(w, h, info.Resolution(), pose2(info.Origin()), cells)


class SimulationProxy(Proxy):
    """A simulator's controls (troupe-sim serves simulation:0)."""

    def __init__(self, client: Client, index: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Simulation, index, 0))
        #: Simulated time since start, us.
        self.sim_time_us = 0
        self.paused = False
        #: Measured simulated seconds per wall second.
        self.real_time_factor = 0.0
        self._attach()

    def _update(self, msg) -> None:
        c = msg.body_as(SimClock)
        if c is not None:
            self.sim_time_us, self.paused, self.real_time_factor = c.SimTimeUs(), bool(c.Paused()), c.RealTimeFactor()

    def _clock_request(self, sub: int, body_type: int = Body.NONE, body: int = 0, timeout: float = 2.0) -> bool:
        r = self._request(sub, body_type, body, timeout)
        if not r.ok:
            return False
        c = r.message.body_as(SimClock)
        if c is not None:
            self.sim_time_us, self.paused = c.SimTimeUs(), bool(c.Paused())
        return True

    def pause(self) -> bool:
        return self._clock_request(SimulationReqSub.Pause)

    def resume(self) -> bool:
        return self._clock_request(SimulationReqSub.Resume)

    def reset(self) -> bool:
        return self._clock_request(SimulationReqSub.Reset)

    def step(self, steps: int = 1) -> bool:
        """Runs `steps` steps (while paused) and returns after they ran."""
        b = self.client.begin()
        _step.SimStepStart(b)
        _step.SimStepAddSteps(b, steps)
        return self._clock_request(SimulationReqSub.Step, Body.SimStep, _step.SimStepEnd(b), 60.0)

    def set_speed(self, speed: float) -> bool:
        """Multiple of real time; 0: as fast as possible."""
        b = self.client.begin()
        _speed.SimSpeedStart(b)
        _speed.SimSpeedAddSpeed(b, speed)
        return self._request(SimulationReqSub.SetSpeed, Body.SimSpeed, _speed.SimSpeedEnd(b)).ok

    def get_pose(self, model: str) -> Pose2 | None:
        """Ground-truth pose of a model (world frame: m, m, rad), or None."""
        b = self.client.begin()
        name = b.CreateString(model)
        _model.SimModelStart(b)
        _model.SimModelAddName(b, name)
        r = self._request(SimulationReqSub.GetPose, Body.SimModel, _model.SimModelEnd(b))
        p = r.message.body_as(SimPose) if r.ok else None
        return pose2(p.Pose()) if p is not None and p.Pose() is not None else None

    def set_pose(self, model: str, pose: Pose2) -> bool:
        """Teleports a model to a world pose: m, m, rad."""
        b = self.client.begin()
        name = b.CreateString(model)
        _simpose.SimPoseStart(b)
        _simpose.SimPoseAddName(b, name)
        _simpose.SimPoseAddPose(b, CreatePose2d(b, *pose))
        return self._request(SimulationReqSub.SetPose, Body.SimPose, _simpose.SimPoseEnd(b)).ok
