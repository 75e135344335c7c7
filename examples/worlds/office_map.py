#!/usr/bin/env python3
"""Draws bitmaps/office.png, the floor plan of office.world: 20 m x 15 m at
0.05 m per pixel (400 x 300), dark pixels are walls. Rooms, doorways and a
few boxes of different shapes, so that no two places look alike to a laser.
Standard library only: python3 office_map.py"""
import struct
import zlib

RES = 0.05  # m per pixel
W, H = 400, 300
X0, Y0 = -10.0, -7.5  # world coordinates of the image's bottom-left corner, m

img = [[255] * W for _ in range(H)]


def box(x0, y0, x1, y1):
    """Fills the rectangle [x0, x1] x [y0, y1] (world metres) with wall."""
    c0, c1 = int(round((min(x0, x1) - X0) / RES)), int(round((max(x0, x1) - X0) / RES))
    r0, r1 = int(round((Y0 + H * RES - max(y0, y1)) / RES)), int(round((Y0 + H * RES - min(y0, y1)) / RES))
    for r in range(max(r0, 0), min(r1, H)):
        for c in range(max(c0, 0), min(c1, W)):
            img[r][c] = 0


T = 0.2  # wall thickness, m
# Outer walls.
box(-10, -7.5, 10, -7.5 + T)
box(-10, 7.5 - T, 10, 7.5)
box(-10, -7.5, -10 + T, 7.5)
box(10 - T, -7.5, 10, 7.5)
# The corridor's north wall, with a doorway into each of three rooms.
box(-10, 2.5, -6.0, 2.5 + T)
box(-5.0, 2.5, 1.0, 2.5 + T)
box(2.0, 2.5, 6.0, 2.5 + T)
box(7.0, 2.5, 10, 2.5 + T)
# Walls between the rooms.
box(-3.0, 2.5, -3.0 + T, 7.5)
box(4.0, 2.5, 4.0 + T, 7.5)
# Furniture in the rooms: an L, a table, a cabinet.
box(-8.5, 5.0, -6.5, 5.3)
box(-8.5, 5.0, -8.2, 6.5)
box(6.5, 4.5, 8.0, 5.5)
box(0.0, 6.6, 2.5, 7.3)
# The south hall: a half wall, boxes and a pillar.
box(0.0, -7.5, 0.0 + T, -2.5)
box(-6.5, -4.5, -5.5, -3.5)
box(4.0, -5.5, 5.5, -5.0)
box(3.0, -1.2, 3.4, -0.8)
box(-3.0, -0.5, -1.0, -0.2)
box(7.5, -3.0, 8.5, -1.0)


def png_gray(path, rows):
    raw = b"".join(b"\x00" + bytes(row) for row in rows)

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


png_gray("bitmaps/office.png", img)
