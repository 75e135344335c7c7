"""Proxies of things that move: position2d, actuator."""

from __future__ import annotations

from troupe.wire import ActuatorCommand as _ac
from troupe.wire import Position2dGoto as _goto
from troupe.wire import Position2dSetOdom as _odom
from troupe.wire import Position2dVel as _vel
from troupe.wire import Switch as _switch
from troupe.wire.ActuatorAction import ActuatorAction
from troupe.wire.ActuatorCmdSub import ActuatorCmdSub
from troupe.wire.ActuatorMode import ActuatorMode
from troupe.wire.ActuatorState import ActuatorState
from troupe.wire.Body import Body
from troupe.wire.Interface import Interface
from troupe.wire.Pose2d import CreatePose2d
from troupe.wire.Position2dCmdSub import Position2dCmdSub
from troupe.wire.Position2dGeometry import Position2dGeometry
from troupe.wire.Position2dReqSub import Position2dReqSub
from troupe.wire.Position2dState import Position2dState

from .address import Address
from .client import Client
from .proxy import Pose2, Pose3, Proxy, Vec3, finite, pose2, pose3, vec3


def switch_body(b, on: bool) -> int:
    _switch.SwitchStart(b)
    _switch.SwitchAddOn(b, on)
    return _switch.SwitchEnd(b)


class Position2dProxy(Proxy):
    """A mobile base: odometry in, velocity and goal commands out.

        base = Position2dProxy(client)        # position2d:0
        base.set_velocity(0.3, 0, 0.2)        # m/s, m/s, rad/s
    """

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Position2d, index, robot))
        #: Odometric pose (or map pose for a localizer): m, m, rad.
        self.pose = Pose2()
        #: Velocity in the robot frame: m/s, m/s, rad/s.
        self.velocity = Pose2()
        self.stall = False
        #: Pose covariance (xx, xy, xa, yy, ya, aa: m^2, m*rad, rad^2) when the device sends one.
        self.covariance: tuple[float, ...] | None = None
        #: Why the base cannot move while a driver fault holds it; None when it is fine.
        self.fault: str | None = None
        self._attach()

    @property
    def x(self) -> float:
        return self.pose.x

    @property
    def y(self) -> float:
        return self.pose.y

    @property
    def a(self) -> float:
        return self.pose.a

    def _update(self, msg) -> None:
        s = msg.body_as(Position2dState)
        if s is None:
            return
        if s.Pose() is not None:
            self.pose = pose2(s.Pose())
        if s.Vel() is not None:
            self.velocity = pose2(s.Vel())
        self.stall = bool(s.Stall())
        c = s.Covariance()
        self.covariance = (c.Xx(), c.Xy(), c.Xa(), c.Yy(), c.Ya(), c.Aa()) if c is not None else None
        fault = s.Fault()
        self.fault = fault.decode("utf-8", "replace") if fault else None

    def set_velocity(self, vx: float, vy: float, va: float) -> bool:
        """Commands the velocity: m/s forward, m/s left, rad/s. Raises
        ValueError for NaN or infinity."""
        finite(vx=vx, vy=vy, va=va)
        b = self.client.begin()
        _vel.Position2dVelStart(b)
        _vel.Position2dVelAddVel(b, CreatePose2d(b, vx, vy, va))
        return self._command(Position2dCmdSub.Vel, Body.Position2dVel, _vel.Position2dVelEnd(b))

    def go_to(self, x: float, y: float, a: float, max_vel: Pose2 | None = None) -> bool:
        """Commands driving to a pose in the odometry frame (m, m, rad), within
        max_vel (m/s, m/s, rad/s; None: the driver's limits). Raises
        ValueError for NaN or infinity."""
        finite(x=x, y=y, a=a)
        if max_vel is not None:
            finite(**{f"max_vel.{k}": v for k, v in zip("xya", max_vel)})
        b = self.client.begin()
        _goto.Position2dGotoStart(b)
        if max_vel is not None:
            _goto.Position2dGotoAddMaxVel(b, CreatePose2d(b, *max_vel))
        _goto.Position2dGotoAddPose(b, CreatePose2d(b, x, y, a))
        return self._command(Position2dCmdSub.Goto, Body.Position2dGoto, _goto.Position2dGotoEnd(b))

    def set_motor_power(self, on: bool) -> bool:
        body = switch_body(self.client.begin(), on)
        return self._request(Position2dReqSub.MotorPower, Body.Switch, body).ok

    def set_odometry(self, x: float, y: float, a: float) -> bool:
        """Restarts odometry from a pose: m, m, rad."""
        finite(x=x, y=y, a=a)
        b = self.client.begin()
        _odom.Position2dSetOdomStart(b)
        _odom.Position2dSetOdomAddPose(b, CreatePose2d(b, x, y, a))
        return self._request(Position2dReqSub.SetOdometry, Body.Position2dSetOdom, _odom.Position2dSetOdomEnd(b)).ok

    def reset_odometry(self) -> bool:
        return self._request(Position2dReqSub.ResetOdometry).ok

    def geometry(self) -> tuple[Vec3, Pose3] | None:
        """The base's size (m) and body offset (m, rad), or None (see client.error)."""
        r = self._request(Position2dReqSub.Geometry)
        g = r.message.body_as(Position2dGeometry) if r.ok else None
        if g is None:
            return None
        return vec3(g.Size()) or Vec3(), pose3(g.Pose())


class ActuatorProxy(Proxy):
    """A gripper or kicker."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None):
        super().__init__(client, addr or Address.of(Interface.Actuator, index, robot))
        #: An ActuatorMode value.
        self.mode = ActuatorMode.Idle
        #: Position of the mechanism: m (linear) or rad (rotary).
        self.position = 0.0
        #: Bit i set: break-beam i is interrupted.
        self.beams = 0
        #: Objects held.
        self.stored = 0
        self._attach()

    def _update(self, msg) -> None:
        s = msg.body_as(ActuatorState)
        if s is not None:
            self.mode, self.position, self.beams, self.stored = s.Mode(), s.Position(), s.Beams(), s.Stored()

    def _act(self, action: int, value: float) -> bool:
        finite(value=value)
        b = self.client.begin()
        _ac.ActuatorCommandStart(b)
        _ac.ActuatorCommandAddAction(b, action)
        _ac.ActuatorCommandAddValue(b, value)
        return self._command(ActuatorCmdSub.Action, Body.ActuatorCommand, _ac.ActuatorCommandEnd(b))

    def open(self) -> bool:
        return self._act(ActuatorAction.Open, 0.0)

    def close(self) -> bool:
        return self._act(ActuatorAction.Close, 0.0)

    def stop(self) -> bool:
        return self._act(ActuatorAction.Stop, 0.0)

    def kick(self, speed: float = 0.0) -> bool:
        """Kicks with the given ball speed, m/s (0: the device's default)."""
        return self._act(ActuatorAction.Kick, speed)

    def go_to(self, position: float) -> bool:
        """Moves to a position, m or rad."""
        return self._act(ActuatorAction.Goto, position)
