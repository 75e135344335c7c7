"""The Python client's camera against troupe-sim serving the camera example
(paused, stepped by the test): images with their shape and format, PNG
images from the simulator, and PNG files saved by the client (zlib and
struct only). An independent decoder, Pillow (Debian's python3-pil), reads
every file back and its pixels must equal the raw image of the same step."""

import io
import os
import struct
import tempfile
import unittest

import helpers
import troupe
from troupe.wire.ImageCompression import ImageCompression
from troupe.wire.PixelFormat import PixelFormat

try:
    from PIL import Image as PilImage
except ImportError:  # the client needs no imaging package; this test's checker does
    PilImage = None

CAMERA_WORLD = os.path.join(helpers.SOURCE_DIR, "examples", "worlds", "camera.world")


def pil_pixels(png: bytes) -> tuple[str, int, int, bytes]:
    """Mode, size and pixels as the wire holds them (16-bit grey little-endian)."""
    im = PilImage.open(io.BytesIO(png))
    im.load()
    if im.mode.startswith("I"):  # 16-bit grey, which Pillow widens to 32-bit integers
        return "I", im.width, im.height, struct.pack(f"<{im.width * im.height}H", *im.getdata())
    return im.mode, im.width, im.height, im.tobytes()


@unittest.skipIf(PilImage is None, "Pillow (Debian: python3-pil) is not installed: nothing independent "
                                   "to decode the PNG files with")
class Camera(unittest.TestCase):
    def setUp(self):
        self.sim = helpers.SimProcess(CAMERA_WORLD, "--paused", "--no-view").start()
        self.raw_client = troupe.Client("127.0.0.1", self.sim.port, name="py-camera-raw")
        self.png_client = troupe.Client("127.0.0.1", self.sim.port, name="py-camera-png")
        self.assertTrue(self.raw_client.connect() and self.png_client.connect())
        self.raw = troupe.CameraProxy(self.raw_client)
        self.png = troupe.CameraProxy(self.png_client, compression=ImageCompression.Png)
        self.sim_proxy = troupe.SimulationProxy(self.raw_client)
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.raw_client.shutdown()
        self.png_client.shutdown()
        self.sim.stop()
        self.dir.cleanup()

    def step(self):
        """One step; both clients hold its image afterwards."""
        self.assertTrue(self.sim_proxy.step(1), self.raw_client.error)
        self.assertTrue(self.raw_client.sync() and self.png_client.sync())

    def test_images_with_their_shape_and_saved_pngs_decode_to_the_same_pixels(self):
        for fmt, mode in ((PixelFormat.Rgb8, "RGB"), (PixelFormat.Mono8, "L"), (PixelFormat.DepthU16, "I")):
            with self.subTest(format=fmt):
                self.assertIsNotNone(self.raw.configure(format=fmt), self.raw_client.error)
                self.step()
                raw, png = self.raw.image, self.png.image
                self.assertEqual((raw.width, raw.height, raw.format), (160, 120, fmt))
                self.assertEqual(raw.stride, 160 * troupe.camera.BYTES_PER_PIXEL[fmt])
                self.assertEqual(raw.compression, ImageCompression.None_)
                self.assertEqual(len(raw.data), raw.stride * raw.height)
                self.assertEqual(png.compression, ImageCompression.Png)
                self.assertLess(len(png.data), len(raw.data))
                # The client's own encoding of the raw image, and the simulator's PNG as it came.
                for proxy in (self.raw, self.png):
                    path = os.path.join(self.dir.name, "image.png")
                    proxy.save_png(path)
                    with open(path, "rb") as f:
                        got_mode, w, h, pixels = pil_pixels(f.read())
                    self.assertEqual((got_mode, w, h), (mode, 160, 120))
                    self.assertEqual(pixels, raw.data)

    def test_depth_in_metres_has_no_png_form_and_reaches_png_readers_raw(self):
        self.assertIsNotNone(self.raw.configure(format=PixelFormat.DepthF32))
        self.step()
        self.assertEqual(self.png.image.compression, ImageCompression.None_)
        self.assertEqual(self.png.image.data, self.raw.image.data)
        with self.assertRaisesRegex(ValueError, "no lossless PNG form: ask the camera for DepthU16"):
            self.raw.save_png(os.path.join(self.dir.name, "depth.png"))
        self.assertFalse(os.path.exists(os.path.join(self.dir.name, "depth.png")))

    def test_bad_images_and_paths_are_refused(self):
        short = troupe.Image(4, 4, 12, PixelFormat.Rgb8, ImageCompression.None_, bytes(40), 0)
        with self.assertRaisesRegex(ValueError, "needs 48 bytes, it has 40"):
            troupe.encode_png(short)
        self.step()
        with self.assertRaises(FileNotFoundError):
            self.raw.save_png(os.path.join(self.dir.name, "no", "such", "dir.png"))
        with self.assertRaisesRegex(ValueError, "no image from the camera yet"):
            troupe.CameraProxy(self.raw_client, index=3).save_png(os.path.join(self.dir.name, "x.png"))


if __name__ == "__main__":
    unittest.main()
