"""Frames of many shapes built with the generated code: strings, vectors of
scalars, of structs and of tables, optional scalars, nested structs, 64-bit
fields. The verifier tests start from these."""

from __future__ import annotations

import troupe
from troupe.wire import DeviceInfo as di
from troupe.wire import DeviceList as dl
from troupe.wire import FiducialList as fl
from troupe.wire import Hello as he
from troupe.wire import Position2dState as ps
from troupe.wire import PowerState as pw
from troupe.wire import RangerScan as rs
from troupe.wire import SimPose as sp
from troupe.wire.Address import CreateAddress
from troupe.wire.Body import Body
from troupe.wire.Cov2d import CreateCov2d
from troupe.wire.Fiducial import CreateFiducial
from troupe.wire.Interface import Interface
from troupe.wire.Kind import Kind
from troupe.wire.Pose2d import CreatePose2d

A = troupe.Address


def hello(name: str = "sample-node") -> bytes:
    w = troupe.MessageWriter()
    b = w.start()
    n = b.CreateString(name)
    he.HelloStart(b)
    he.HelloAddProtocolVersion(b, troupe.PROTOCOL_VERSION)
    he.HelloAddName(b, n)
    he.HelloAddMaxFrameBytes(b, 1 << 20)
    he.HelloAddClockUs(b, 0x123456789ABC)
    return w.finish(A(0, 0, 0), Kind.Hello, 0, 0, 5, Body.Hello, he.HelloEnd(b))


def device_list(count: int = 3, seq: int = 1) -> bytes:
    w = troupe.MessageWriter()
    b = w.start()
    infos = []
    for i in range(count):
        robot, driver = b.CreateString(f"r{i}"), b.CreateString("kinematic")
        di.DeviceInfoStart(b)
        di.DeviceInfoAddAddr(b, CreateAddress(b, i, Interface.Position2d, 0))
        di.DeviceInfoAddRobotName(b, robot)
        di.DeviceInfoAddDriver(b, driver)
        infos.append(di.DeviceInfoEnd(b))
    dl.DeviceListStartDevicesVector(b, count)
    for info in reversed(infos):
        b.PrependUOffsetTRelative(info)
    vec = b.EndVector()
    dl.DeviceListStart(b)
    dl.DeviceListAddDevices(b, vec)
    return w.finish(A(0, 0, 0), Kind.DeviceList, 0, seq, 6, Body.DeviceList, dl.DeviceListEnd(b))


def position2d(x: float = 1.5, fault: str | None = "left axis silent", seq: int = 1) -> bytes:
    w = troupe.MessageWriter()
    b = w.start()
    f = b.CreateString(fault) if fault else None
    ps.Position2dStateStart(b)
    ps.Position2dStateAddPose(b, CreatePose2d(b, x, -2.0, 0.5))
    ps.Position2dStateAddVel(b, CreatePose2d(b, 0.3, 0.0, 0.1))
    ps.Position2dStateAddStall(b, True)
    ps.Position2dStateAddCovariance(b, CreateCov2d(b, 0.01, 0, 0, 0.02, 0, 0.003))
    if f is not None:
        ps.Position2dStateAddFault(b, f)
    return w.finish(A(0, Interface.Position2d, 0), Kind.Data, 1, seq, 1_000_000 + seq, Body.Position2dState,
                    ps.Position2dStateEnd(b))


def ranger(beams: int = 181, base_mm: int = 1000, seq: int = 1) -> bytes:
    w = troupe.MessageWriter()
    b = w.start()
    rs.RangerScanStartIntensitiesVector(b, beams)
    for i in reversed(range(beams)):
        b.PrependUint8(i % 256)
    intensities = b.EndVector()
    rs.RangerScanStartRangesVector(b, beams)
    for i in reversed(range(beams)):
        b.PrependUint16(base_mm + i)
    ranges = b.EndVector()
    rs.RangerScanStart(b)
    rs.RangerScanAddRanges(b, ranges)
    rs.RangerScanAddIntensities(b, intensities)
    rs.RangerScanAddMinAngle(b, -1.5)
    rs.RangerScanAddAngularRes(b, 3.0 / max(beams - 1, 1))
    rs.RangerScanAddMaxRange(b, 8.0)
    return w.finish(A(0, Interface.Ranger, 0), Kind.Data, 1, seq, 2_000_000 + seq, Body.RangerScan,
                    rs.RangerScanEnd(b))


def power() -> bytes:
    w = troupe.MessageWriter()
    b = w.start()
    pw.PowerStateStart(b)
    pw.PowerStateAddVolts(b, 12.5)
    pw.PowerStateAddCharging(b, False)
    return w.finish(A(0, Interface.Power, 0), Kind.Data, 1, 1, 7, Body.PowerState, pw.PowerStateEnd(b))


def fiducials(count: int = 4, kinds: list[int] | None = None) -> bytes:
    """`count` detections; `kinds` (FiducialKind values), when given, their kinds."""
    w = troupe.MessageWriter()
    b = w.start()
    fl.FiducialListStartFiducialsVector(b, count)
    for i in reversed(range(count)):
        CreateFiducial(b, i, 1.0 + i, -0.5, 0.25)
    vec = b.EndVector()
    kind_vec = None
    if kinds is not None:
        fl.FiducialListStartKindsVector(b, len(kinds))
        for k in reversed(kinds):
            b.PrependUint8(k)
        kind_vec = b.EndVector()
    fl.FiducialListStart(b)
    fl.FiducialListAddFiducials(b, vec)
    if kind_vec is not None:
        fl.FiducialListAddKinds(b, kind_vec)
    return w.finish(A(2, Interface.Fiducial, 1), Kind.Data, 1, 3, 9, Body.FiducialList, fl.FiducialListEnd(b))


def sim_pose() -> bytes:
    w = troupe.MessageWriter()
    b = w.start()
    name = b.CreateString("r7")
    sp.SimPoseStart(b)
    sp.SimPoseAddName(b, name)
    sp.SimPoseAddPose(b, CreatePose2d(b, 3.0, 4.0, 1.0))
    return w.finish(A(0, Interface.Simulation, 0), Kind.Ack, 6, 12, 10, Body.SimPose, sp.SimPoseEnd(b))


def all_samples() -> dict[str, bytes]:
    return {"hello": hello(), "device_list": device_list(), "position2d": position2d(), "ranger": ranger(),
            "power": power(), "fiducials": fiducials(), "sim_pose": sim_pose()}
