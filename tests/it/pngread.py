"""PNG images as (width, height, channels, rows of bytes), for tests that index raw bytes.

The decoding is pngio.read_png's (one PNG decoder in the tests); this only reshapes it.
"""
from pngio import read_png as _read_array


def read_png(path):
    img = _read_array(path)
    height, width, channels = img.shape
    return width, height, channels, [img[y].tobytes() for y in range(height)]


def pixel(img, x, y):
    _, _, ch, rows = img
    return tuple(rows[y][x * ch:(x + 1) * ch])
