"""The checks of the arguments every public function shares: dtypes, shapes, counts, tolerances.

They raise ValueError with a message naming the argument, before the compiled module sees it.
"""

from __future__ import annotations

import os
from typing import Any, Optional, Sequence, Tuple, TypeVar, Union

import numpy as np
import numpy.typing as npt

Path = Union[str, "os.PathLike[str]"]
_Array = TypeVar("_Array", bound=npt.NDArray[Any])


def real(name: str, a: npt.ArrayLike, shape: Sequence[Optional[int]]) -> npt.NDArray[np.float64]:
    """`a` as a C-contiguous float64 array of the given shape (None: any length)."""
    x = np.asarray(a)
    if x.dtype.kind not in "biuf":
        raise ValueError("%s must hold real numbers, not %s" % (name, x.dtype))
    return shaped(name, np.ascontiguousarray(x, dtype=np.float64), shape)


def integer(name: str, a: npt.ArrayLike, shape: Sequence[Optional[int]]) -> npt.NDArray[np.int64]:
    """`a` as a C-contiguous int64 array of the given shape; integer dtypes only."""
    x = np.asarray(a)
    if x.size == 0 and x.dtype.kind == "f":
        x = x.astype(np.int64)  # np.zeros((0, 3)) is float64: an empty array has no wrong values
    if x.dtype.kind not in "biu":
        raise ValueError("%s must hold integers, not %s" % (name, x.dtype))
    if x.dtype.kind == "u" and x.size and x.max() > np.iinfo(np.int64).max:
        raise ValueError("%s: index %d is out of range" % (name, x.max()))
    return shaped(name, np.ascontiguousarray(x, dtype=np.int64), shape)


def shaped(name: str, a: _Array, shape: Sequence[Optional[int]]) -> _Array:
    """`a` itself when its shape is `shape` (None: any length); ValueError otherwise."""
    if a.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, a.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError("%s must have shape %s, got %s" % (name, want, a.shape))
    return a


def threads(count: int) -> int:
    """The thread count as the CLI takes it (0: every core)."""
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not 0 <= count <= 1024:
        raise ValueError("threads must be an integer from 0 (every core) to 1024, not %r" % (count,))
    return int(count)


def small_int(name: str, x: int, lo: int, hi: int) -> int:
    """An integer from lo to hi (bools refused, as for threads)."""
    if isinstance(x, bool) or not isinstance(x, (int, np.integer)) or not lo <= x <= hi:
        raise ValueError("%s must be an integer from %d to %d, not %r" % (name, lo, hi, x))
    return int(x)


def tolerance(name: str, x: float, most: Optional[float] = None) -> float:
    """A tolerance: a finite number from 0 (to `most`, if given); NaN and infinities refused."""
    x = float(x)
    if not (0 <= x < np.inf and (most is None or x <= most)):  # NaN fails the comparisons
        bound = "" if most is None else " to %g" % most
        raise ValueError("%s must be a finite number from 0%s, not %r" % (name, bound, x))
    return x


def triangle_map(
    V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.float64]]:
    """The map's arrays as the compiled module takes them: V (n, 3), F (m, 3) and UV (3m, 2)."""
    positions = real("V", V, (None, 3))
    triangles = integer("F", F, (None, 3))
    m = triangles.shape[0]
    if np.ndim(UV) == 3:
        corners = real("UV", UV, (m, 3, 2)).reshape(-1, 2)
    else:
        corners = real("UV", UV, (3 * m, 2))
    return positions, triangles, corners
