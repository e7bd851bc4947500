"""BCC files written for tests (no bpy: the Python suite uses it too)."""
import struct

import numpy as np


def write_bcc(path, kind, curves, up=2):
    """A BCC file of [(points (n, 3), closed)] curves of type `kind` (C0, PL, BS, BZ); up 1 = Y, 2 = Z."""
    total = sum(len(points) for points, _ in curves)
    with open(path, "wb") as f:
        f.write(b"BCC\x44" + kind.encode() + bytes([3, up]) + struct.pack("<QQ", len(curves), total) + bytes(40))
        for points, closed in curves:
            f.write(struct.pack("<i", -len(points) if closed else len(points)))
            f.write(np.asarray(points, dtype="<f4").tobytes())
    return str(path)
