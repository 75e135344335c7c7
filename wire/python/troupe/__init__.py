"""Troupe's Python client.

    import troupe
    client = troupe.Client("localhost")            # port 6665
    client.connect()
    base = troupe.Position2dProxy(client)           # position2d:0
    laser = troupe.RangerProxy(client)              # ranger:0
    base.set_velocity(0.3, 0, 0.2)                  # m/s, m/s, rad/s
    while client.spin_once(0.1):
        print(base.x, min(laser.ranges, default=None))

The message classes under troupe.wire are generated at build time by
`flatc --python` from wire/schemas/*.fbs; this package adds framing, a
verifier (the Python FlatBuffers runtime has none), the client and one proxy
per interface, shaped like the C++ client (wire/client/).

Secure sessions (Noise IK, wire/README.md) need PyNaCl: troupe.noise is
imported only by a client given an identity, so a plain client runs without it.

    client = troupe.Client("robot7.local", identity="laptop", node_key="robot7.pub")
"""

from .camera import CameraProxy, CameraSettings, Image, encode_png, save_png
from .address import (DEFAULT_PORT, Address, DeviceSpec, format_address, interface_from_name, interface_name,
                      parse_device, parse_host, robot_number)
from .client import Client, DeviceEntry, Reply
from .frame import FrameReader
from .keys import KeyFileError
from .message import PROTOCOL_VERSION, Header, Message, MessageWriter, decode, kind_name, now_us
from .proxies_motion import ActuatorProxy, Position2dProxy
from .proxies_sensors import (Blob, BlobfinderProxy, BumperProxy, Detection, FiducialProxy, ImuProxy, PowerProxy,
                              RangerProxy)
from .proxies_world import GridMap, Hypothesis, LocalizeProxy, MapProxy, SimulationProxy
from .proxy import Pose2, Pose3, Proxy, Vec3
from .verify import Limits, Verifier, VerifyError

__all__ = [
    "DEFAULT_PORT", "PROTOCOL_VERSION", "ActuatorProxy", "Address", "Blob", "BlobfinderProxy", "BumperProxy",
    "CameraProxy", "CameraSettings", "Client", "Detection", "DeviceEntry", "DeviceSpec", "FiducialProxy", "FrameReader", "GridMap", "Header",
    "Hypothesis", "Image", "ImuProxy", "KeyFileError", "Limits", "LocalizeProxy", "MapProxy", "Message", "MessageWriter",
    "Pose2", "Pose3", "Position2dProxy", "PowerProxy", "Proxy", "RangerProxy", "Reply", "SimulationProxy", "Vec3",
    "Verifier", "VerifyError", "decode", "encode_png", "format_address", "interface_from_name", "interface_name", "kind_name",
    "now_us", "parse_device", "parse_host", "robot_number", "save_png",
]
