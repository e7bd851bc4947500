"""Matrices as numpy arrays and as the scene format's row-major lists."""
import numpy as np


def to_numpy(matrix):
    """A mathutils 4x4 Matrix as a float64 (4, 4) array, rows as in Blender."""
    return np.array([list(row) for row in matrix], dtype=np.float64)


def to_row_major_list(matrix):
    """16 numbers, row by row, as the scene format's `matrix_world`."""
    return [float(v) for row in matrix for v in row]


def transform_points(points, matrix):
    """(N, 3) points through a 4x4 affine matrix: float32 points relative to the matrix's
    translation, and that translation (float64 (3,)), which the scene entry gives back as its
    matrix_world (`placed_at`). Purl composes the two in double: far from the world origin
    float32 keeps only millimetres (at 1e4 m, two yarn radii)."""
    m = to_numpy(matrix) if not isinstance(matrix, np.ndarray) else matrix
    return (points.astype(np.float64) @ m[:3, :3].T).astype(np.float32), m[:3, 3].copy()


def placed_at(origin):
    """The scene format's matrix_world that moves points given relative to `origin` into place."""
    m = np.identity(4)
    m[:3, 3] = origin
    return to_row_major_list(m)


def uniform_scale(matrix):
    """Cube root of |det| of the linear part: how a radius scales (as Cycles does for curves)."""
    m = to_numpy(matrix) if not isinstance(matrix, np.ndarray) else matrix
    return float(abs(np.linalg.det(m[:3, :3])) ** (1.0 / 3.0))


def split_scale(matrix):
    """(rotation+translation matrix as a row-major list, per-axis scale (3,)).

    Lights and cameras are placed by a rigid transform; their sizes take the scale instead."""
    m = to_numpy(matrix) if not isinstance(matrix, np.ndarray) else matrix.copy()
    scale = np.linalg.norm(m[:3, :3], axis=0)
    rigid = m.copy()
    rigid[:3, :3] = m[:3, :3] / np.where(scale > 0.0, scale, 1.0)
    return [float(v) for v in rigid.reshape(-1)], scale
