"""The camera proxy, and PNG files of its images with the standard library
alone (zlib and struct): no imaging package is needed to save what a camera
sends."""

from __future__ import annotations

import struct
import zlib
from typing import NamedTuple

from troupe.wire.Body import Body
from troupe.wire.CameraConfig import CameraConfig, CameraConfigAddFormat, CameraConfigAddHeight, \
    CameraConfigAddRate, CameraConfigAddWidth, CameraConfigEnd, CameraConfigStart
from troupe.wire.CameraImage import CameraImage
from troupe.wire.CameraReqSub import CameraReqSub
from troupe.wire.ImageCompression import ImageCompression
from troupe.wire.Interface import Interface
from troupe.wire.PixelFormat import PixelFormat

from .address import Address
from .client import Client
from .proxy import Proxy
from .schema import message_schema

#: Bytes per pixel of each uncompressed format.
BYTES_PER_PIXEL = {PixelFormat.Rgb8: 3, PixelFormat.Mono8: 1, PixelFormat.DepthF32: 4, PixelFormat.DepthU16: 2}


class Image(NamedTuple):
    """One camera image as it came. Raw (compression None): `height` rows of
    `stride` bytes, multi-byte pixels little-endian (wire/schemas/camera.fbs);
    PNG: `data` is the whole file and `stride` is 0."""
    width: int  # px
    height: int  # px
    stride: int  # bytes from one row to the next
    format: int  # a PixelFormat value
    compression: int  # an ImageCompression value
    data: bytes
    stamp_us: int  # when it was taken, sender's clock, us (0: the message's time)


class CameraSettings(NamedTuple):
    width: int  # px
    height: int  # px
    rate: float  # images per second
    format: int  # a PixelFormat value


def encode_png(image: Image) -> bytes:
    """A raw Rgb8, Mono8 or DepthU16 image as a PNG file (DepthU16 as 16-bit
    grey, big-endian as PNG stores it). Rows are stored unfiltered: simple
    rather than small. Raises ValueError for DepthF32 (no lossless PNG form:
    ask the camera for DepthU16) and for data shorter than the shape says."""
    kinds = {PixelFormat.Rgb8: (8, 2), PixelFormat.Mono8: (8, 0), PixelFormat.DepthU16: (16, 0)}
    if image.format not in kinds:
        raise ValueError(f"a format {image.format} image has no lossless PNG form: "
                         "ask the camera for DepthU16 (millimetres) to save depth")
    if image.compression != ImageCompression.None_:
        raise ValueError("encode_png takes raw rows; a PNG image is saved as it came")
    bit_depth, colour_type = kinds[image.format]
    row = image.width * BYTES_PER_PIXEL[image.format]
    need = image.stride * (image.height - 1) + row if image.height else 0
    if image.width == 0 or image.height == 0 or image.stride < row or len(image.data) < need:
        raise ValueError(f"a {image.width}x{image.height} image with stride {image.stride} needs {need} bytes, "
                         f"it has {len(image.data)}")
    rows = bytearray()
    for y in range(image.height):
        pixels = image.data[y * image.stride:y * image.stride + row]
        if bit_depth == 16:  # the wire's little-endian samples, swapped to PNG's big-endian
            swapped = bytearray(pixels)
            swapped[0::2], swapped[1::2] = pixels[1::2], pixels[0::2]
            pixels = swapped
        rows += b"\0" + pixels  # filter type 0: none

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", image.width, image.height, bit_depth, colour_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(rows), 6)) +
            chunk(b"IEND", b""))


def save_png(image: Image, path: str) -> None:
    """Writes `image` to `path` as a PNG file: a PNG image's bytes as they
    came, raw rows through encode_png(). Raises ValueError (see encode_png)
    or OSError (the file cannot be written)."""
    data = image.data if image.compression == ImageCompression.Png else encode_png(image)
    with open(path, "wb") as f:
        f.write(data)


class CameraProxy(Proxy):
    """Images from a camera. `compression=ImageCompression.Png` asks the
    camera for PNG files (a camera that cannot sends raw rows; each image
    says how it is packed)."""

    def __init__(self, client: Client, index: int = 0, robot: int = 0, addr: Address | None = None,
                 compression: int = ImageCompression.None_):
        super().__init__(client, addr or Address.of(Interface.Camera, index, robot))
        self.image: Image | None = None
        self._attach(compression=compression)

    def _update(self, msg) -> None:
        s = msg.body_as(CameraImage)
        if s is None:
            return
        tab = s._tab
        o = tab.Offset(message_schema().field_offset("troupe.wire.CameraImage", "data"))
        data = bytes(tab.Bytes[tab.Vector(o):tab.Vector(o) + tab.VectorLen(o)]) if o else b""
        self.image = Image(s.Width(), s.Height(), s.Stride(), s.Format(), s.Compression(), data, s.StampUs())

    def save_png(self, path: str) -> None:
        """Writes the latest image to `path` as PNG (see save_png()); raises
        ValueError when there is none yet."""
        if self.image is None:
            raise ValueError("no image from the camera yet")
        save_png(self.image, path)

    def configure(self, width: int = 0, height: int = 0, rate: float = 0.0,
                  format: int = PixelFormat.Rgb8) -> CameraSettings | None:
        """Asks for an image size (px), rate (images per second) and format
        (0 keeps a size or rate); returns what the camera took, or None with
        client.error saying why."""
        b = self.client.begin()
        CameraConfigStart(b)
        CameraConfigAddWidth(b, width)
        CameraConfigAddHeight(b, height)
        CameraConfigAddRate(b, rate)
        CameraConfigAddFormat(b, format)
        r = self._request(CameraReqSub.SetConfig, Body.CameraConfig, CameraConfigEnd(b))
        c = r.message.body_as(CameraConfig) if r.ok else None
        return CameraSettings(c.Width(), c.Height(), c.Rate(), c.Format()) if c else None
