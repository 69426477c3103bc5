# SPDX-License-Identifier: GPL-3.0-or-later
"""numpy conversions of caller input: positions, faces, index lists."""
import itertools

from ._numpy import np

FLOAT32, FLOAT64 = 0, 1  # cagekit_scalar_type


def positions(values, name="positions"):
    """(C-contiguous float32/float64 (N, 3) array, cagekit_scalar_type)."""
    a = np.asarray(values)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float64)
    if a.size == 0:
        a = a.reshape(0, 3)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError("cagekit: %s must have shape (N, 3), not %s" % (name, a.shape))
    a = np.ascontiguousarray(a)
    return a, (FLOAT32 if a.dtype == np.float32 else FLOAT64)


def control(values, count=None, name="control"):
    """C-contiguous float64 (N, 3) array, N == count when given."""
    a = np.ascontiguousarray(np.asarray(values, dtype=np.float64))
    if a.ndim == 1 and a.size % 3 == 0:
        a = a.reshape(-1, 3)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError("cagekit: %s must have shape (N, 3), not %s" % (name, a.shape))
    if count is not None and a.shape[0] != count:
        raise ValueError("cagekit: %s has %d points, the binding's cage has %d" % (name, a.shape[0], count))
    return a


def indices(values, name="indices"):
    """C-contiguous uint32 1-D array from any integer sequence; negative or >= 2^32 values raise."""
    a = np.asarray(values)
    if a.size == 0:
        return np.zeros(0, dtype=np.uint32)
    if a.dtype.kind not in "iu":
        if a.dtype.kind == "f" and np.all(np.floor(a) == a):
            a = a.astype(np.int64)
        else:
            raise ValueError("cagekit: %s must be integers" % name)
    if a.dtype != np.uint32:
        if a.size and (a.min() < 0 or a.max() >= 2 ** 32):
            raise ValueError("cagekit: %s must be in [0, 2^32)" % name)
        a = a.astype(np.uint32)
    return np.ascontiguousarray(a.reshape(-1))


def faces(values, face_sizes=None):
    """(sizes uint32 array or None, uniform size, flat indices uint32 array, face count).

    values: a (F, k) integer array; a list of index lists (any sizes); a tuple (sizes, indices);
    flat indices with face_sizes given; None for no faces."""
    if face_sizes is not None:
        sizes = indices(face_sizes, "face_sizes")
        flat = indices(values, "faces")
        return sizes, 0, flat, len(sizes)
    if values is None:
        return None, 3, np.zeros(0, dtype=np.uint32), 0
    if isinstance(values, tuple) and len(values) == 2:
        return faces(values[1], face_sizes=values[0])
    if isinstance(values, np.ndarray):
        if values.ndim != 2:
            raise ValueError("cagekit: a face array must have shape (F, k); pass flat indices with face_sizes=")
        return None, int(values.shape[1]), indices(values, "faces"), int(values.shape[0])
    face_list = [f if isinstance(f, np.ndarray) else list(f) for f in values]
    sizes = np.fromiter((len(f) for f in face_list), dtype=np.int64, count=len(face_list))
    flat = np.fromiter(itertools.chain.from_iterable(face_list), dtype=np.int64, count=int(sizes.sum()))
    if len(face_list) and np.all(sizes == sizes[0]):
        return None, int(sizes[0]), indices(flat, "faces"), len(face_list)
    return indices(sizes, "face sizes"), 0, indices(flat, "faces"), len(face_list)


def split_faces(sizes, flat):
    """A list of 1-D arrays of `flat`'s type, one per face (views into `flat`), whatever the face
    sizes: the one type of Mesh.faces and Cage.faces ([] without faces)."""
    if len(sizes) and np.all(sizes == sizes[0]):
        # the rows of one reshape: about 6 times faster than np.split for a large triangle mesh
        return list(flat.reshape(len(sizes), int(sizes[0])))
    return np.split(flat, np.cumsum(sizes[:-1].astype(np.int64))) if len(sizes) else []
