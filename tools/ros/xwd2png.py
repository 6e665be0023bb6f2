#!/usr/bin/python3
"""An X window dump (xwd -root) as a PNG: the rviz screenshot in docs/ is taken under Xvfb with
xwd (x11-apps), which writes XWD; this reads 24/32-bit ZPixmap dumps, the format Xvfb gives.

    tools/ros/xwd2png.py IN.xwd OUT.png
"""
import struct
import sys

import numpy as np
import cv2


def read_xwd(path):
    data = open(path, "rb").read()
    fields = struct.unpack(">25I", data[:100])
    header_size, version, pixmap_format, depth, width, height = fields[:6]
    byte_order, bits_per_pixel, bytes_per_line, ncolors = fields[7], fields[11], fields[12], fields[19]
    if version != 7 or pixmap_format != 2 or bits_per_pixel not in (24, 32):
        raise SystemExit(f"{path}: not a 24/32-bit ZPixmap XWD (version {version}, format {pixmap_format}, "
                         f"{bits_per_pixel} bits per pixel)")
    offset = header_size + 12 * ncolors
    rows = np.frombuffer(data, np.uint8, bytes_per_line * height, offset).reshape(height, bytes_per_line)
    channels = bits_per_pixel // 8
    pixels = rows[:, : width * channels].reshape(height, width, channels)
    # LSB first: each pixel's bytes are B, G, R(, pad).
    bgr = pixels[:, :, :3] if byte_order == 0 else pixels[:, :, channels - 1:channels - 4:-1]
    return np.ascontiguousarray(bgr)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    if not cv2.imwrite(sys.argv[2], read_xwd(sys.argv[1])):
        raise SystemExit(f"{sys.argv[2]}: cannot write")
