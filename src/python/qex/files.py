"""The files of qex from Python: OBJ maps and meshes, VVAL valences, certificates."""

from __future__ import annotations  # qex._qex's types are in its stub (_qex.pyi) only

import os
from typing import Tuple

import numpy as np
import numpy.typing as npt

from . import _arrays, _qex
from ._arrays import Path
from .extraction import Result, result_of

__all__ = ["read_obj", "read_vval", "write_obj", "write_certificate"]


def read_obj(
    path: Path, *, threads: int = 0
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32], npt.NDArray[np.float64]]:
    """Read an OBJ map (``v``, ``vt`` and ``f a/ta b/tb c/tc`` records).

    Parameters
    ----------
    path : str or os.PathLike
        The OBJ file.
    threads : int, optional
        Threads of the reader (0, the default: every core); the arrays do not depend on it.

    Returns
    -------
    V : ndarray of float64, shape (n, 3)
    F : ndarray of int32, shape (m, 3)
    UV : ndarray of float64, shape (m, 3, 2)
        Per triangle corner.

    Raises
    ------
    OSError
        The file cannot be read.
    ValueError
        A malformed file (the message names the line).
    """
    return _qex.read_obj(os.fspath(path), _arrays.threads(threads))


def read_vval(path: Path) -> npt.NDArray[np.int32]:
    """Read a VVAL file: the valences of the input vertices, as ``qex extract --valences`` takes them.

    Parameters
    ----------
    path : str or os.PathLike
        The VVAL file (a JSON header line, the vertex count, then one valence per line).

    Returns
    -------
    ndarray of int32, shape (n,)
        A valence per input vertex, for `extract`'s ``valences``.

    Raises
    ------
    OSError
        The file cannot be read.
    ValueError
        A malformed file: a count or valence that is not a plausible integer (the message names
        the line).
    """
    return _qex.read_vval(os.fspath(path))


def write_certificate(path: Path, V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, result: Result) -> None:
    """Write the certificate of an extracted mesh: the repaired map it was extracted from.

    ``qex extract --certificate`` writes the same file. `check` (``certificate=``) and
    ``qex check --certificate`` verify it against the map and judge the mesh on it, where the
    repair left no fold-over to be undecided about. Written through ``path + ".tmp"``, renamed.

    Parameters
    ----------
    path : str or os.PathLike
        The certificate file to write (an OBJ map with a header of comments).
    V, F, UV : array_like
        The map the mesh was extracted from, as given to `extract`.
    result : Result
        What `extract` returned for them.

    Raises
    ------
    OSError
        The file cannot be written.
    ValueError
        `result` is not a `Result`, carries no map of these arrays, or was split from the map
        divided by k (``report["fallback"]["coarsening"] > 1``: it was checked at the coarse
        scale, and has no certificate on the given one).
    """
    coarsening = result_of(result).report.get("fallback", {}).get("coarsening", 1)
    if coarsening > 1:
        raise ValueError(f"no certificate: the mesh was split from the map divided by {coarsening}")
    _qex.write_certificate(*_arrays.triangle_map(V, F, UV), result._mesh, os.fspath(path))


def write_obj(path: Path, result: Result) -> None:
    """Write an extracted mesh as OBJ (quads, with their integer local UVs as ``vt``).

    The file is written to ``path + ".tmp"`` and renamed, so no partial file is ever left.

    Parameters
    ----------
    path : str or os.PathLike
        The OBJ file to write.
    result : Result
        What `extract` returned (a mesh the checker rejected too, as it is).

    Raises
    ------
    OSError
        The file cannot be written.
    ValueError
        `result` is not a `Result`.
    """
    mesh = result_of(result)._mesh  # the type of `result` is checked before the path's
    _qex.write_obj(os.fspath(path), mesh)
