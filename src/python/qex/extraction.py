"""`extract` and the `Result` it returns: the quad mesh of a map, its report and the checker's verdict."""

from __future__ import annotations  # qex._qex's types are in its stub (_qex.pyi) only

import json
from typing import Any, Dict, List, Optional

import numpy as np
import numpy.typing as npt

from . import _arrays, _qex

__all__ = ["Result", "extract"]


class Result:
    """The quad mesh of a map, as `extract` returns it.

    Attributes
    ----------
    quads : ndarray of int32, shape (k, 4)
        The quads, indices into `positions`, counter-clockwise. Faces with other than four
        corners (only in a mesh the checker rejects) are left out; ``report["faces"]["non_quad"]``
        counts them.
    positions : ndarray of float64, shape (p, 3)
        The vertices.
    face_uvs : ndarray of int64, shape (k, 4, 2)
        Per quad corner, the integer local UV: a counter-clockwise unit square.
    provenance : dict of ndarrays, each of length p
        Where each vertex lies on the input: ``kind`` (int8: 0 vertex, 1 edge, 2 face),
        ``element`` (input vertex or triangle), ``local_edge``, ``barycentric`` (p, 3), ``grid``
        (p, 2) its integer grid point, ``chart_triangle`` and ``merged``.
    valid : bool
        The checker's verdict: True when the mesh is a valid quad mesh of the map.
    report : dict
        The report, with the content of ``qex extract --report``: counts per stage, fallback,
        repair, defects, explanations, timings and the checker's verdict under ``"check"``.
    defects : list of dict
        ``report["defects"]``: what failed, near which input triangle and grid point.
    """

    quads: npt.NDArray[np.int32]
    positions: npt.NDArray[np.float64]
    face_uvs: npt.NDArray[np.int64]
    provenance: Dict[str, npt.NDArray[Any]]
    valid: bool
    report: Dict[str, Any]
    defects: List[Dict[str, Any]]
    _mesh: _qex.QuadMesh
    __slots__ = ("quads", "positions", "face_uvs", "provenance", "valid", "report", "defects", "_mesh")

    def __init__(self, raw: _qex._Extracted) -> None:
        """Wraps what the compiled `qex._qex.extract` returns; `extract` makes Results."""
        self.quads = raw["quads"]
        self.positions = raw["positions"]
        self.face_uvs = raw["face_uvs"]
        self.provenance = raw["provenance"]
        self.valid = bool(raw["valid"])
        self.report = json.loads(raw["report_json"])
        self.defects = self.report["defects"]
        self._mesh = raw["mesh"]

    def __repr__(self) -> str:
        return "qex.Result(%d quads, %d vertices, valid=%s)" % (len(self.quads), len(self.positions), self.valid)


def result_of(result: Result) -> Result:
    """`result` itself; ValueError when it is not a Result (its compiled mesh is what the library takes)."""
    if not isinstance(result, Result):
        raise ValueError("result must be a qex.Result (what qex.extract returns)")
    return result


def _given(**options: Optional[Any]) -> Dict[str, Any]:
    """The options the caller set: None keeps the library's default, so it is not passed on."""
    return {k: v for k, v in options.items() if v is not None}


def extract(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    UV: npt.ArrayLike,
    *,
    valences: Optional[npt.ArrayLike] = None,
    feature_edges: Optional[npt.ArrayLike] = None,
    threads: int = 0,
    max_qvertices: Optional[int] = None,
    max_trace_steps: Optional[int] = None,
    recover_lost_edges: Optional[bool] = None,
    merge_vertices: Optional[bool] = None,
    canonical_order: Optional[bool] = None,
    snap_boundary: Optional[bool] = None,
    repair_fold_overs: Optional[bool] = None,
    fallback_ladder: Optional[bool] = None,
    best_effort: Optional[bool] = None,
    fill_holes: Optional[bool] = None,
) -> Result:
    """Extract the quad mesh of a triangle mesh carrying an integer-grid map.

    Parameters
    ----------
    V : array_like, shape (n, 3)
        Vertex positions (converted to float64).
    F : array_like of int, shape (m, 3)
        Triangles, indices into `V`, counter-clockwise on the surface.
    UV : array_like, shape (m, 3, 2) or (3m, 2)
        The map: the parameter coordinates of corner k of triangle f, ``UV[f, k]`` or ``UV[3f + k]``.
    valences : array_like of int, shape (n,), optional
        The cross field's valence per vertex (4 regular); default: counted from the map.
    feature_edges : array_like of int, shape (e, 2), optional
        Vertex pairs of edges to snap onto their closest integer iso-line.
    threads : int, optional
        Threads of the library's loops: 0 (default) every core, 1 serial; the output is the same.
    max_qvertices, max_trace_steps : int, optional
        Most grid points the map may hold (default 10,000,000; beyond: ``MapTooLarge``), most
        triangles one trace may cross (default 100,000).
    recover_lost_edges, merge_vertices, canonical_order, snap_boundary : bool, optional
    repair_fold_overs, fallback_ladder, best_effort, fill_holes : bool, optional
        Switches of ``qex::Options`` (include/qex/extract.h), defaults in this order: True, True,
        True, False; True, True, False, True. src/python/README.md ("qex.extract") says what each
        does. None, for any option, keeps the library's default.

    Returns
    -------
    Result
        ``quads``, ``positions``, ``face_uvs``, ``provenance``, ``valid``, ``report`` (the CLI's
        JSON report as a dict) and ``defects``. When ``valid`` is False, the checker's violations
        are in ``report["check"]["violations"]``. The GIL is released while the library works.

    Raises
    ------
    ValueError
        Arrays of the wrong shape or dtype, or input the library rejects (empty, index out of range,
        NaN or Inf, non-manifold or misoriented, isolated vertex, inconsistent map, ...): the
        message names the vertex or triangle.
    TypeError
        An unknown option, or an option of the wrong type.

    Examples
    --------
    >>> import numpy as np, qex
    >>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]], float)
    >>> F = np.array([[0, 1, 2], [0, 2, 3]])
    >>> r = qex.extract(V, F, V[F][:, :, :2])
    >>> r.quads.shape, r.valid
    ((4, 4), True)
    """
    options = _given(max_qvertices=max_qvertices, max_trace_steps=max_trace_steps,
                     recover_lost_edges=recover_lost_edges, merge_vertices=merge_vertices,
                     canonical_order=canonical_order, snap_boundary=snap_boundary,
                     repair_fold_overs=repair_fold_overs, fallback_ladder=fallback_ladder,
                     best_effort=best_effort, fill_holes=fill_holes)
    V, F, UV = _arrays.triangle_map(V, F, UV)
    valences_ = None if valences is None else _arrays.integer("valences", valences, (None,))
    features = None if feature_edges is None else _arrays.integer("feature_edges", feature_edges, (None, 2))
    return Result(_qex.extract(V, F, UV, valences_, features, _arrays.threads(threads), options))
