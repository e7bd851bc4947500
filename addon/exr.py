"""Reads the pixels of an uncompressed scanline OpenEXR file into numpy arrays.

Only what the Cycles half of a composite render writes: single-part multilayer files (Blender 3.4,
4.5) and multi-part files (5.0), codec NONE, half or float channels. Enough to composite without
an OpenEXR module, which Blender's Python does not ship.
"""
import struct

import numpy as np

MAGIC = b"\x76\x2f\x31\x01"
MULTIPART_FLAG = 0x1000
PIXEL_DTYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


def _header(data, pos):
    """One header's attributes {name: raw bytes} and the position after its terminating zero."""
    attributes = {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        (size,) = struct.unpack_from("<i", data, type_end + 1)
        start = type_end + 5
        attributes[data[pos:name_end].decode()] = data[start:start + size]
        pos = start + size
    return attributes, pos + 1


def _channel_list(raw):
    """[(name, pixel type)] in file order (OpenEXR keeps them sorted by name)."""
    channels, pos = [], 0
    while raw[pos] != 0:
        end = raw.index(b"\0", pos)
        (pixel_type,) = struct.unpack_from("<i", raw, end + 1)
        channels.append((raw[pos:end].decode(), pixel_type))
        pos = end + 1 + 16  # pixel type, pLinear + 3 reserved bytes, x and y sampling
    return channels


def _headers(data, path):
    """(the parts' headers, the position of the first offset table, whether the file is multi-part)."""
    if data[:4] != MAGIC:
        raise ValueError("{} is not an OpenEXR file".format(path))
    (version,) = struct.unpack_from("<i", data, 4)
    multipart = bool(version & MULTIPART_FLAG)
    headers, pos = [], 8
    while True:
        header, pos = _header(data, pos)
        headers.append(header)
        if not multipart or data[pos] == 0:
            break
    if multipart:
        pos += 1  # the empty header that ends the list
    return headers, pos, multipart


def channel_names(path):
    """Every part's channel names in file order; reads headers only, so any compression is fine."""
    with open(path, "rb") as f:
        headers, _, _ = _headers(f.read(), path)
    return [name for header in headers for name, _ in _channel_list(header["channels"])]


def read_exr(path):
    """{channel name: float32 (H, W)}, rows top to bottom. Raises ValueError for files it cannot read."""
    with open(path, "rb") as f:
        data = f.read()
    headers, pos, multipart = _headers(data, path)
    planes = {}
    for header in headers:
        if header["compression"][0] != 0:
            raise ValueError("{} is compressed; only uncompressed EXR files are read".format(path))
        x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"])
        width, height = x1 - x0 + 1, y1 - y0 + 1
        channels = _channel_list(header["channels"])
        chunk_offsets = struct.unpack_from("<{}Q".format(height), data, pos)  # one scanline per chunk
        pos += 8 * height
        part = {name: np.zeros((height, width), dtype=np.float32) for name, _ in channels}
        for offset in chunk_offsets:
            offset += 4 if multipart else 0  # a multi-part chunk starts with its part number
            (y,) = struct.unpack_from("<i", data, offset)
            cursor = offset + 8  # y and the chunk's byte count
            for name, pixel_type in channels:
                dtype = PIXEL_DTYPES[pixel_type]
                part[name][y - y0] = np.frombuffer(data, dtype=dtype, count=width, offset=cursor)
                cursor += width * dtype.itemsize
        planes.update(part)
    return planes
