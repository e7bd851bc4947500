"""A minimal OpenEXR reader for the tests: channel names, and pixels of uncompressed scanline files
(single-part as Blender 3.4/4.5 write them, multi-part as 5.0 does). Enough to check passes
without OpenImageIO's Python module."""
import struct

import numpy as np

_PIXEL_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}
_MULTIPART = 0x1000


def _read_header(data, pos):
    """(attributes, position after the header's terminating byte)."""
    header = {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        name, kind = data[pos:name_end].decode(), data[name_end + 1:type_end].decode()
        (size,) = struct.unpack_from("<i", data, type_end + 1)
        header[name] = (kind, data[type_end + 5:type_end + 5 + size])
        pos = type_end + 5 + size
    return header, pos + 1


def _read_headers(data):
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file")
    (version,) = struct.unpack_from("<i", data, 4)
    multipart = bool(version & _MULTIPART)
    headers, pos = [], 8
    while True:
        header, pos = _read_header(data, pos)
        headers.append(header)
        if not multipart or data[pos] == 0:
            break
    return headers, (pos + 1 if multipart else pos), multipart


def _channels(value):
    channels, pos = [], 0
    while value[pos] != 0:
        end = value.index(b"\0", pos)
        (pixel_type,) = struct.unpack_from("<i", value, end + 1)
        channels.append((value[pos:end].decode(), pixel_type))
        pos = end + 1 + 16
    return channels


def channel_names(path):
    with open(path, "rb") as f:
        headers, _, _ = _read_headers(f.read())
    return [name for header in headers for name, _ in _channels(header["channels"][1])]


def read_channels(path):
    """{channel: float32 (H, W) array}, rows top to bottom; uncompressed scanline files only."""
    with open(path, "rb") as f:
        data = f.read()
    headers, pos, multipart = _read_headers(data)
    images = {}
    for part, header in enumerate(headers):
        if header["compression"][1][0] != 0:
            raise ValueError("only uncompressed EXR files are read here")
        x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"][1])
        width, height = x1 - x0 + 1, y1 - y0 + 1
        channels = _channels(header["channels"][1])
        offsets = struct.unpack_from("<{}Q".format(height), data, pos)
        pos += 8 * height
        planes = {name: np.empty((height, width), dtype=np.float32) for name, _ in channels}
        for offset in offsets:
            if multipart:
                offset += 4  # each chunk starts with its part number
            y, _size = struct.unpack_from("<ii", data, offset)
            cursor = offset + 8
            for name, pixel_type in channels:
                dtype = _PIXEL_TYPES[pixel_type]
                row = np.frombuffer(data, dtype=dtype, count=width, offset=cursor)
                planes[name][y - y0] = row.astype(np.float32)
                cursor += width * dtype.itemsize
        images.update(planes)
    return images
