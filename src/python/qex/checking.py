"""The checker from Python: `verify` judges an extracted result again, `check` any quad mesh given as arrays."""

from __future__ import annotations  # qex._qex's types are in its stub (_qex.pyi) only

import json
import os
from typing import Any, Dict, Optional

import numpy.typing as npt

from . import _arrays, _qex
from ._arrays import Path
from .extraction import Result, result_of

__all__ = ["verify", "check"]


def verify(
    V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, result: Result, *, threads: int = 0
) -> Dict[str, Any]:
    """Judge an extracted mesh against its map again, with the exact checker.

    Parameters
    ----------
    V, F, UV : array_like
        The map, as given to `extract`.
    result : Result
        What `extract` returned for it.
    threads : int, optional
        Threads of the checker (0: every core); the verdict does not depend on it.

    Returns
    -------
    dict
        The verdict, as ``qex check --json`` prints it: ``valid``, ``violations`` (a list of
        dicts with ``kind``, ``element`` and ``message``), the counts and the input's invariants.
    """
    mesh = result_of(result)._mesh
    verdict: Dict[str, Any] = json.loads(_qex.verify(*_arrays.triangle_map(V, F, UV), mesh, _arrays.threads(threads)))
    return verdict


def check(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    UV: npt.ArrayLike,
    QV: npt.ArrayLike,
    QF: npt.ArrayLike,
    *,
    uv_tolerance: float = 1e-3,
    distance_tolerance: float = 1e-6,
    locate: bool = True,
    digits: int = 6,
    grid_scale: int = 1,
    fold_regions: bool = True,
    strict_map: bool = False,
    threads: int = 0,
    certificate: Optional[Path] = None,
) -> Dict[str, Any]:
    """Judge any quad mesh, given as arrays, against a map: the oracle for any extractor's output.

    The same code path and defaults as ``qex check --param``, ``qex draw --quads`` and the C API's
    ``qex_check``: the same verdict. src/python/README.md has each keyword's CLI flag.

    Parameters
    ----------
    V, F, UV : array_like
        The map, as for `extract`.
    QV, QF : array_like, shapes (p, 3) and (k, 4)
        The quad mesh: its vertices, and its faces as indices into `QV`, counter-clockwise.
    uv_tolerance : float, optional
        Largest UV distance (inf-norm) of a vertex to its grid point (default 1e-3), at most 1.
    distance_tolerance : float, optional
        Largest distance of a vertex to the surface, over the bounding-box diagonal (default 1e-6).
    locate : bool, optional
        Locate the vertices on the map (default); False checks the topology only.
    digits : int, optional
        The positions may be rounded to this many significant digits (default 6: float
        precision); 0 takes them as exact doubles.
    grid_scale : int, optional
        Judge against the map's UVs times this power of two (1 to 64): a refined mesh's
        ``report["fallback"]["grid_scale"]``.
    fold_regions : bool, optional
        Judge vertices in the map's fold-over regions on the surface only (default True).
    strict_map : bool, optional
        Decide every check against the raw map: what would be undecided is a violation.
    threads : int, optional
        Threads of the checker (0: every core).
    certificate : str or os.PathLike, optional
        qex's certificate for this mesh (`write_certificate`): checked against the map, then the
        mesh is judged on the repaired map it holds, at its grid scale (excludes `grid_scale`).
        A certificate that does not hold gives ``CertificateMismatch`` violations.

    Returns
    -------
    dict
        The verdict, as ``qex check --json`` prints it: ``valid``, ``violations`` (each with
        ``kind``, ``element``, ``message``), ``undecided``, the counts, and ``quality``: the
        mesh's scaled Jacobians (``min``, ``p5``, ``mean``), irregular vertices and the distances
        between it and the map (fractions of the map's bounding-box diagonal; qex/quality.h).

    Raises
    ------
    ValueError
        Arrays of the wrong shape or dtype, a map `extract` would reject, a malformed certificate,
        or both `certificate` and a `grid_scale` other than 1.
    OSError
        The certificate cannot be read.
    """
    Vm, Fm, UVm = _arrays.triangle_map(V, F, UV)
    QVm, QFm = _arrays.real("QV", QV, (None, 3)), _arrays.integer("QF", QF, (None, None))
    uv = _arrays.tolerance("uv_tolerance", uv_tolerance, 1.0)
    distance = _arrays.tolerance("distance_tolerance", distance_tolerance)
    digits_, scale = _arrays.small_int("digits", digits, 0, 17), _arrays.small_int("grid_scale", grid_scale, 1, 64)
    path = "" if certificate is None else os.fspath(certificate)  # the compiled module takes "" for none
    verdict: Dict[str, Any] = json.loads(_qex.check(Vm, Fm, UVm, QVm, QFm, uv, distance, bool(locate), digits_,
                                                    scale, bool(fold_regions), bool(strict_map),
                                                    _arrays.threads(threads), path))
    return verdict
