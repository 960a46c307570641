"""`layout`: the patch layout of a quad mesh (qex/layout.h), from a Result or from arrays."""

from __future__ import annotations  # qex._qex's types are in its stub (_qex.pyi) only

from typing import Any, Dict, Tuple, Union

import numpy.typing as npt

from . import _arrays, _qex
from .extraction import Result

__all__ = ["layout"]


def layout(mesh: Union[Result, Tuple[npt.ArrayLike, npt.ArrayLike]]) -> Dict[str, Any]:
    """The quad layout of a mesh: the separatrices that join its irregular vertices, boundary and
    feature corners along mesh edges, and the rectangular patches they cut it into.

    Parameters
    ----------
    mesh : Result or tuple of (QV, QF)
        An extracted result, or a quad mesh as arrays: positions (n, 3) and quads (k, 4).

    Returns
    -------
    dict
        ``face_patch`` (k,) the patch of each face; ``patch_sizes`` (P, 2) each patch's integer
        (u, v) size; ``patch_corners`` (P, 4); ``separatrices``, a list of vertex index arrays, and
        ``separatrix_ends``, how each ends; ``adjacency`` (A, 3): patch, patch, shared edges;
        ``special_vertices``; ``valid`` (the independent check accepts the layout), ``error``
        (why not) and ``notes`` (a torus without separatrix says so).

    Raises
    ------
    ValueError
        Arrays of the wrong shape or dtype.
    """
    if isinstance(mesh, Result):
        return dict(_qex.layout(mesh._mesh))
    QV, QF = mesh
    return dict(_qex.layout_of_arrays(_arrays.real("QV", QV, (None, 3)), _arrays.integer("QF", QF, (None, None))))
