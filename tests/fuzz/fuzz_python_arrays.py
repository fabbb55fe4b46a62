#!/usr/bin/env python3
"""Random hostile arrays and arguments through the Python module's array
conversions: every entry point that takes an image or a matrix.

Each input is an array of a random dtype (including object, bool, float16,
complex, big-endian), 0 to 5 dimensions, sides of 0 to 4096 built as
broadcast or strided views (so even huge shapes cost no memory: only
arrays of up to 4M elements are ever written out), C or Fortran order, read-only or not, plus random argument values. The module
must answer each with a result or a Python exception (chromatag.Error,
TypeError, ValueError, MemoryError, OverflowError); a crash of the
interpreter is the failure. The cases before the random ones are the seeds:
the ones that once broke it.

usage: fuzz_python_arrays.py SECONDS [SEED]
"""
import math
import random
import sys
import time
import warnings

import numpy as np

import chromatag

ACCEPTED = (chromatag.Error, TypeError, ValueError, MemoryError, OverflowError)

DTYPES = [np.uint8, np.int8, np.uint16, np.int32, np.int64, np.float16, np.float32,
          np.float64, np.complex64, np.bool_, object, np.dtype('>u2'), np.dtype('>f8')]

SEEDS = [
    lambda: np.broadcast_to(np.zeros((1, 1, 3), np.uint8), (50000, 50000, 3)),
    lambda: np.broadcast_to(np.zeros((1, 1, 3), np.uint8), (2147483653, 1, 3)),
    lambda: np.zeros((0, 0, 3), np.uint8),
    lambda: np.zeros((10, 10, 3), np.uint8)[::-1, ::2],
    lambda: np.zeros((10, 10, 4), np.uint8),
    lambda: np.asfortranarray(np.zeros((20, 30, 3), np.uint8)),
    lambda: np.zeros((5, 0, 4), np.uint8),
    lambda: np.array(b'not an image'),
    lambda: np.zeros((3, 3), object),
    # 2**31 elements: as doubles, 16 GB that a conversion would write out.
    lambda: np.broadcast_to(np.zeros((1,), np.uint8), (4096, 4096, 128)),
]


def random_array(rng):
    try:
        return make_array(rng)
    except (ValueError, MemoryError):  # numpy's own refusals: a shape too large.
        return np.zeros((1,), np.uint8)


def make_array(rng):
    dtype = rng.choice(DTYPES)
    ndim = rng.randint(0, 5)
    shape = []
    for _ in range(ndim):
        shape.append(rng.choice([0, 1, 2, 3, 4, 7, 64, 4096, 2**31 + rng.randint(0, 9),
                                 rng.randint(0, 300)]))
    # Memory for up to 4M elements: the other sides (and any over 512) are
    # broadcast, since sides under 512 can still multiply to billions.
    small = math.prod(shape) <= 1 << 22
    base_shape = []
    for side in shape:
        keep = side <= 512 and math.prod(base_shape) * side <= 1 << 22
        base_shape.append(side if keep else 1)
    base_shape = tuple(base_shape)
    try:
        base = np.zeros(base_shape, dtype=dtype)
    except (ValueError, MemoryError):
        return np.zeros((1,), np.uint8)
    if rng.random() < 0.3 and base.size:
        base = (np.arange(base.size) % 256).astype(dtype).reshape(base_shape)
    array = np.broadcast_to(base, tuple(shape)) if shape else base
    if ndim and rng.random() < 0.3 and small:
        array = np.ascontiguousarray(array)
        slices = tuple(slice(None, None, rng.choice([1, 2, -1])) for _ in shape)
        array = array[slices]
    if rng.random() < 0.2 and small:
        array = np.asfortranarray(array)
    if rng.random() < 0.2 and array.flags.writeable:
        array.flags.writeable = False
    return array


def random_value(rng):
    return rng.choice([None, 0, -1, 1, 2**40, 2**70, -2**70, float('nan'), float('inf'),
                       1e308, 0.5, '40mm', '', 'rgb', 'bgr', 'x\x00y', [], [1, 2],
                       (1.0, 2.0, 3.0, 4.0), (float('nan'),) * 4, np.zeros(4), {}])


KINDS = 8


def one_case(rng, detector, array, kind=None):
    """Calls one entry point (`kind`, or a random one) with `array`; returns
    nothing, raises only accepted errors."""
    kind = rng.randrange(KINDS) if kind is None else kind
    try:
        if kind == 0:
            detector.detect(array)
        elif kind == 1:
            detector.detect(array, order=rng.choice(['rgb', 'bgr', random_value(rng)]),
                            return_rejected=rng.random() < 0.5,
                            estimate_tag_pose=rng.random() < 0.5,
                            camera_params=random_value(rng), tag_size=random_value(rng))
        elif kind == 2:
            chromatag.draw_detections(array, [])
        elif kind == 3:
            chromatag.Detector(camera_matrix=array, dist_coeffs=random_array(rng),
                               tag_size=0.05)
        elif kind == 4:
            chromatag.BoardTag('16h5', rng.randint(-2, 40), random_value(rng) or 0.03, array,
                               random_array(rng) if rng.random() < 0.5 else None)
        elif kind == 5:
            chromatag.detect(array, order=rng.choice(['rgb', 'bgr']), step=random_value(rng))
        elif kind == 6:
            board = chromatag.Board('b', [chromatag.BoardTag('16h5', 0, 0.03, [0.0, 0.0, 0.0])])
            detector.detect_board(array, board)
        else:
            chromatag.render_tag('16h5', rng.randint(-5, 40), cell_px=random_value(rng) or 4)
    except ACCEPTED:
        pass


def main():
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 30.0
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else int(time.time())
    rng = random.Random(seed)
    warnings.simplefilter('ignore')  # numpy's casts, the channel-order hint.
    print(f'fuzz_python_arrays: {seconds:g} s, seed {seed}', flush=True)
    detector = chromatag.Detector()
    runs = 0
    for make in SEEDS:  # Every seed through every entry point.
        for kind in range(KINDS):
            one_case(rng, detector, make(), kind)
            runs += 1
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        one_case(rng, detector, random_array(rng))
        runs += 1
    print(f'fuzz_python_arrays: {runs} runs, no crash', flush=True)


if __name__ == '__main__':
    main()
