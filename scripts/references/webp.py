#!/usr/bin/env python3
"""Writes crates/gltf-import/tests/data/palette.webp: a 4 x 2 image of eight known colours (the
rows below), encoded losslessly by libwebp through Pillow (`pip install pillow`), so that
raystage's WebP decoder is checked against another encoder: crates/gltf-import/tests/import.rs
reads the file as an EXT_texture_webp image and expects these very texels."""

import sys

from PIL import Image

PALETTE = [
    [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 255)],
    [(0, 0, 0), (128, 64, 32), (17, 200, 99), (250, 128, 7)],
]


def main(out):
    image = Image.new("RGB", (4, 2))
    for y, row in enumerate(PALETTE):
        for x, colour in enumerate(row):
            image.putpixel((x, y), colour)
    image.save(out, "WEBP", lossless=True, quality=100, method=6)


if __name__ == "__main__":
    main(sys.argv[1])
