"""Proxies of sensors: ranger, power, bumper, blobfinder, fiducial, imu."""

from __future__ import annotations

from typing import NamedTuple

from troupe.wire.BlobList import BlobList
from troupe.wire.Body import Body
from troupe.wire.BumperGeometry import BumperGeometry
from troupe.wire.BumperReqSub import BumperReqSub
from troupe.wire.BumperState import BumperState
from troupe.wire.FiducialGeometry import FiducialGeometry
from troupe.wire.FiducialKind import FiducialKind
from troupe.wire.FiducialList import FiducialList
from troupe.wire.FiducialReqSub import FiducialReqSub
from troupe.wire.ImuState import ImuState
from troupe.wire.Interface import Interface
from troupe.wire.Pose2d import Pose2d
from troupe.wire.PowerState import PowerState
from troupe.wire.RangerConfig import RangerConfig
from troupe.wire.RangerGeometry import RangerGeometry
from troupe.wire.RangerReqSub import RangerReqSub
from troupe.wire.RangerScan import RangerScan

from .address import Address
from .client import Client
from .proxies_motion import switch_body
from .proxy import Pose2, Pose3, Proxy, Vec3, pose2, pose3, scalar_vector, vec3


class RangerGeometryInfo(NamedTuple):
    #: Sensor pose on the robot: m, rad.
    pose: Pose3
    #: Sensor size: m.
    size: Vec3
    #: Pose of each transducer on the robot (sonar rings): m, rad.
    elements: list[Pose3]


class RangerSettings(NamedTuple):
    """A ranger's configuration: rad, rad, rad, m, m, m, Hz."""
    min_angle: float
    max_angle: float
    angular_res: float
    min_range: float
    max_range: float
    range_res: float
    frequency: float


class RangerProxy(Proxy):
    """Sonar rings, IR arrays and scanning lasers."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Ranger, index, robot))
        #: Ranges of the latest scan, m. A value >= max_range means no return.
        self.ranges: list[float] = []
        #: Per-beam return strength, device units (empty when not sent).
        self.intensities: bytes = b""
        #: Scanning sensors: bearing of ranges[0] in the sensor frame, rad.
        self.min_angle = 0.0
        #: Scanning sensors: angle between consecutive beams, rad.
        self.angular_res = 0.0
        #: Longest range the sensor reports, m.
        self.max_range = 0.0
        self._attach()

    @property
    def count(self) -> int:
        return len(self.ranges)

    def range(self, i: int) -> float:
        """Range of beam i, m."""
        return self.ranges[i]

    def bearing(self, i: int) -> float:
        """Scanning sensors: bearing of beam i in the sensor frame, rad."""
        return self.min_angle + i * self.angular_res

    def _update(self, msg) -> None:
        s = msg.body_as(RangerScan)
        if s is None:
            return
        scale = s.Scale()
        self.ranges = [r * scale for r in scalar_vector(s, "troupe.wire.RangerScan", "ranges", "H")]
        self.intensities = bytes(scalar_vector(s, "troupe.wire.RangerScan", "intensities", "B"))
        self.min_angle, self.angular_res, self.max_range = s.MinAngle(), s.AngularRes(), s.MaxRange()

    def geometry(self) -> RangerGeometryInfo | None:
        """The sensor's pose and size and each transducer's pose, or None."""
        r = self._request(RangerReqSub.Geometry)
        g = r.message.body_as(RangerGeometry) if r.ok else None
        if g is None:
            return None
        elements = [pose3(g.Elements(i)) for i in range(g.ElementsLength())]
        return RangerGeometryInfo(pose3(g.Pose()), vec3(g.Size()) or Vec3(), elements)

    def config(self) -> RangerSettings | None:
        """The configuration in force, or None."""
        r = self._request(RangerReqSub.GetConfig)
        c = r.message.body_as(RangerConfig) if r.ok else None
        if c is None:
            return None
        return RangerSettings(c.MinAngle(), c.MaxAngle(), c.AngularRes(), c.MinRange(), c.MaxRange(), c.RangeRes(),
                              c.Frequency())

    def set_power(self, on: bool) -> bool:
        body = switch_body(self.client.begin(), on)
        return self._request(RangerReqSub.Power, Body.Switch, body).ok


class PowerProxy(Proxy):
    """Batteries and supplies. Each value is None when the device does not measure it."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Power, index, robot))
        self.volts: float | None = None  # V
        self.percent: float | None = None  # % of full charge
        self.joules: float | None = None  # J remaining
        self.watts: float | None = None  # W drawn (positive) or charged
        self.charging: bool | None = None
        self._attach()

    def _update(self, msg) -> None:
        s = msg.body_as(PowerState)
        if s is None:
            return
        self.volts, self.percent, self.joules, self.watts = s.Volts(), s.Percent(), s.Joules(), s.Watts()
        c = s.Charging()
        self.charging = None if c is None else bool(c)


class BumperDefinition(NamedTuple):
    #: Centre of the segment on the robot: m, m, rad.
    pose: Pose2
    #: m
    length: float
    #: m, 0 for straight
    radius: float


class BumperProxy(Proxy):
    """Contact switches around the body."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Bumper, index, robot))
        #: Bit i set: bumper i is pressed.
        self.bits = 0
        #: How many bumpers the device has.
        self.count = 0
        self._attach()

    def pressed(self, i: int) -> bool:
        return 0 <= i < 32 and bool((self.bits >> i) & 1)

    @property
    def any(self) -> bool:
        return self.bits != 0

    def _update(self, msg) -> None:
        s = msg.body_as(BumperState)
        if s is not None:
            self.bits, self.count = s.Pressed(), s.Count()

    def geometry(self) -> list[BumperDefinition] | None:
        r = self._request(BumperReqSub.Geometry)
        g = r.message.body_as(BumperGeometry) if r.ok else None
        if g is None:
            return None
        out = []
        for i in range(g.BumpersLength()):
            d = g.Bumpers(i)
            out.append(BumperDefinition(pose2(d.Pose(Pose2d())), d.Length(), d.Radius()))
        return out


class Blob(NamedTuple):
    """One blob in image coordinates (x right, y down), px; colour 0x00RRGGBB."""
    color: int
    area: int
    x: int
    y: int
    left: int
    right: int
    top: int
    bottom: int
    #: Distance to the blob's source, mm (0: unknown).
    range_mm: int
    id: int


class BlobfinderProxy(Proxy):
    """Coloured regions found in a camera image."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Blobfinder, index, robot))
        self.blobs: list[Blob] = []
        self.width = 0  # px
        self.height = 0  # px
        self._attach()

    def _update(self, msg) -> None:
        s = msg.body_as(BlobList)
        if s is None:
            return
        self.blobs = []
        for i in range(s.BlobsLength()):
            b = s.Blobs(i)
            self.blobs.append(Blob(b.Color(), b.Area(), b.X(), b.Y(), b.Left(), b.Right(), b.Top(), b.Bottom(),
                                   b.RangeMm(), b.Id()))
        self.width, self.height = s.Width(), s.Height()


class Detection(NamedTuple):
    """One landmark in the sensor frame: id (-1: not identified), m forward, m left, rad, and
    what it is (a FiducialKind value: Generic, Ball, Goal, Post, Line, Robot)."""
    id: int
    x: float
    y: float
    yaw: float
    kind: int = FiducialKind.Generic


class FiducialGeometryInfo(NamedTuple):
    pose: Pose3  # sensor on the robot: m, rad
    size: Vec3  # m
    min_range: float  # m
    max_range: float  # m
    fov: float  # rad


class FiducialProxy(Proxy):
    """Identified landmarks."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Fiducial, index, robot))
        self.fiducials: list[Detection] = []
        self._attach()

    def _update(self, msg) -> None:
        s = msg.body_as(FiducialList)
        if s is None:
            return
        self.fiducials = []
        kinds = s.KindsLength()
        for i in range(s.FiducialsLength()):
            f = s.Fiducials(i)
            kind = s.Kinds(i) if i < kinds else FiducialKind.Generic
            self.fiducials.append(Detection(f.Id(), f.X(), f.Y(), f.Yaw(), kind))

    def geometry(self) -> FiducialGeometryInfo | None:
        r = self._request(FiducialReqSub.Geometry)
        g = r.message.body_as(FiducialGeometry) if r.ok else None
        if g is None:
            return None
        return FiducialGeometryInfo(pose3(g.Pose()), vec3(g.Size()) or Vec3(), g.MinRange(), g.MaxRange(), g.Fov())


class ImuProxy(Proxy):
    """Inertial measurement. Each vector is None when not measured."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Imu, index, robot))
        self.gyro: Vec3 | None = None  # rad/s
        self.accel: Vec3 | None = None  # m/s^2
        self.orientation: Vec3 | None = None  # roll, pitch, yaw: rad
        self._attach()

    def _update(self, msg) -> None:
        s = msg.body_as(ImuState)
        if s is not None:
            self.gyro, self.accel, self.orientation = vec3(s.Gyro()), vec3(s.Accel()), vec3(s.Orientation())
