"""Float64 functions that give the same bits on every x86-64 processor with AVX2, under one C library.

NumPy picks a ufunc's kernel by the processor it runs on. On one with AVX-512, ``np.exp``, ``np.log``,
``np.log1p``, ``np.arctan2``, ``np.tan`` and ``x ** y`` (``y`` other than -1, 0, 0.5, 1 and 2) take NumPy's own
AVX-512 kernels; on one with AVX2 alone the C library's (libm). Both are accurate to about an ulp, and they differ in
the last bit of some results. A simulator that computes with them then gives another trajectory on another
processor, and a training run may part in turn. An AVX2-only processor can be imitated on an AVX-512 one by
starting Python with ``NPY_DISABLE_CPU_FEATURES`` naming :data:`AVX512_GROUPS` (tests/test_portable_math.py and
benchmarks/kernel_portability.py do).

These functions reach libm on every processor, through NumPy loops that are never vectorised:

- :func:`power` is ``np.float_power``, libm's ``pow`` (NumPy's own ``**`` for an exponent it computes exactly);
- :func:`exp` is the real part of the complex exponential of ``x + 0j``, libm's ``cexp``, which is ``exp(x)``
  times ``cos(0) = 1``;
- :func:`arctan2` is the argument of the complex number ``x + iy``, taken from libm's ``clog``, whose imaginary
  part is ``atan2(y, x)``;
- :func:`log` is the real part of libm's ``clog`` of ``x + 0j``, which computes ``log |x|`` its own way (not bit
  for bit ``log(x)``, but the same on every processor).

libm is the C library's: glibc picks its FMA code for these on every processor with AVX2 (Intel's since 2013, AMD's
since 2015), so the bits are alike there; an older processor, or another C library (macOS's, musl), may round some
results otherwise. So each equals what NumPy computes on an AVX2-only processor (``log`` aside), and costs a few
times as much: use them where a result decides a trajectory, and plain NumPy elsewhere (a picture, a report).
``np.sqrt``, ``np.sin``, ``np.cos``, ``np.hypot``, ``x ** 2`` and the four arithmetic operations give the same bits
whatever kernels NumPy takes already.
"""

from __future__ import annotations

import numpy as np

# NumPy 2's groups of AVX-512 features: with these named in NPY_DISABLE_CPU_FEATURES, NumPy takes the kernels of an
# AVX2-only processor
AVX512_GROUPS = ("X86_V4", "AVX512_ICL", "AVX512_SPR")

# NumPy computes an array to these scalar powers as a reciprocal, ones, a square root, a copy and a square: IEEE
# operations, correctly rounded everywhere
EXACT_EXPONENTS = (-1.0, 0.0, 0.5, 1.0, 2.0)


def power(base: np.ndarray | float, exponent: np.ndarray | float) -> np.ndarray:
    """``base ** exponent`` in float64 (any broadcastable shapes): NumPy's own where it is exact (a scalar exponent
    in :data:`EXACT_EXPONENTS`), else libm's ``pow``."""
    if np.ndim(exponent) == 0 and float(exponent) in EXACT_EXPONENTS:
        return np.asarray(base, dtype=np.float64) ** float(exponent)
    return np.float_power(base, exponent)


def exp(x: np.ndarray | float) -> np.ndarray:
    """``e ** x`` in float64 (any shape), libm's ``exp``."""
    return np.exp(np.asarray(x, dtype=np.float64) + 0j).real


def log(x: np.ndarray | float) -> np.ndarray:
    """The natural logarithm in float64 (any shape; ``-inf`` at 0, ``nan`` below it, as ``np.log``)."""
    values = np.asarray(x, dtype=np.float64)
    with np.errstate(divide="ignore"):
        result = np.log(values + 0j).real
    return np.where(values < 0.0, np.nan, result)


def arctan2(y: np.ndarray | float, x: np.ndarray | float) -> np.ndarray:
    """The angle of (``x``, ``y``) in radians, in [-pi, pi] (broadcastable shapes, float64), libm's ``atan2``."""
    x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    complex_ = np.empty(x.shape, dtype=np.complex128)
    complex_.real, complex_.imag = x, y
    with np.errstate(divide="ignore"):
        return np.log(complex_).imag
