"""qex: quad meshes from triangle meshes carrying an integer-grid map (QEx).

The map is given per triangle corner, as quad-meshing parametrizers (MIQ, QuadCover, ...) write
it. Arrays follow numpy's conventions:

>>> import qex
>>> V, F, UV = qex.read_obj("corpus/fuzz_obj/valid/cube_n3_k4.obj")
>>> r = qex.extract(V, F, UV)
>>> r.valid, r.quads.shape
(True, (54, 4))

Functions
---------
extract    the quad mesh of a map, with the report and the checker's verdict
verify     judge an extracted result again (exact checker)
check      judge any quad mesh, given as arrays, against a map (the oracle of other extractors)
layout     the patch layout of a quad mesh: separatrices, patches, their sizes and neighbours
read_obj   read an OBJ map as (V, F, UV)
read_vval  read a VVAL file of valences (one per input vertex)
write_obj  write an extracted mesh as OBJ
write_certificate  write the repaired map an extracted mesh is judged on (check(certificate=...))
conform    judge a Python extractor on known, hostile and your own maps, on Dask (qex conform)

Bad input raises ValueError with the library's message, which names the element at fault. The
library releases the GIL while it works, so extractions in several Python threads run in parallel.
"""

from __future__ import annotations  # qex._qex's types are in its stub (_qex.pyi) only

import json as _json
import os as _os
from typing import Any, Dict, List, Optional, Sequence, Tuple, TypeVar, Union

import numpy as _np
import numpy.typing as npt

from . import _qex
from .conformance import conform

_Path = Union[str, "_os.PathLike[str]"]
_Array = TypeVar("_Array", bound=npt.NDArray[Any])

__all__ = ["Result", "extract", "verify", "check", "layout", "read_obj", "read_vval", "write_obj", "write_certificate",
           "conform"]


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

    quads: npt.NDArray[_np.int32]
    positions: npt.NDArray[_np.float64]
    face_uvs: npt.NDArray[_np.int64]
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
        self.report = _json.loads(raw["report_json"])
        self.defects = self.report["defects"]
        self._mesh = raw["mesh"]

    def __repr__(self) -> str:
        return "qex.Result(%d quads, %d vertices, valid=%s)" % (len(self.quads), len(self.positions), self.valid)


def _real(name: str, a: npt.ArrayLike, shape: Sequence[Optional[int]]) -> npt.NDArray[_np.float64]:
    """`a` as a C-contiguous float64 array of the given shape (None: any length)."""
    x = _np.asarray(a)
    if x.dtype.kind not in "biuf":
        raise ValueError("%s must hold real numbers, not %s" % (name, x.dtype))
    return _shaped(name, _np.ascontiguousarray(x, dtype=_np.float64), shape)


def _integer(name: str, a: npt.ArrayLike, shape: Sequence[Optional[int]]) -> npt.NDArray[_np.int64]:
    """`a` as a C-contiguous int64 array of the given shape; integer dtypes only."""
    x = _np.asarray(a)
    if x.size == 0 and x.dtype.kind == "f":
        x = x.astype(_np.int64)  # np.zeros((0, 3)) is float64: an empty array has no wrong values
    if x.dtype.kind not in "biu":
        raise ValueError("%s must hold integers, not %s" % (name, x.dtype))
    if x.dtype.kind == "u" and x.size and x.max() > _np.iinfo(_np.int64).max:
        raise ValueError("%s: index %d is out of range" % (name, x.max()))
    return _shaped(name, _np.ascontiguousarray(x, dtype=_np.int64), shape)


def _shaped(name: str, a: _Array, shape: Sequence[Optional[int]]) -> _Array:
    """`a` itself when its shape is `shape` (None: any length); ValueError otherwise."""
    if a.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, a.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError("%s must have shape %s, got %s" % (name, want, a.shape))
    return a


def _threads(threads: int) -> int:
    """The thread count as the CLI takes it (0: every core)."""
    if isinstance(threads, bool) or not isinstance(threads, (int, _np.integer)) or not 0 <= threads <= 1024:
        raise ValueError("threads must be an integer from 0 (every core) to 1024, not %r" % (threads,))
    return int(threads)


def _small_int(name: str, x: int, lo: int, hi: int) -> int:
    """An integer from lo to hi (bools refused, as for threads)."""
    if isinstance(x, bool) or not isinstance(x, (int, _np.integer)) or not lo <= x <= hi:
        raise ValueError("%s must be an integer from %d to %d, not %r" % (name, lo, hi, x))
    return int(x)


def _tolerance(name: str, x: float, most: Optional[float] = None) -> float:
    """A tolerance: a finite number from 0 (to `most`, if given); NaN and infinities refused."""
    x = float(x)
    if not (0 <= x < _np.inf and (most is None or x <= most)):  # NaN fails the comparisons
        bound = "" if most is None else " to %g" % most
        raise ValueError("%s must be a finite number from 0%s, not %r" % (name, bound, x))
    return x


def _map(
    V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike
) -> Tuple[npt.NDArray[_np.float64], npt.NDArray[_np.int64], npt.NDArray[_np.float64]]:
    """The map's arrays as the compiled module takes them: V (n, 3), F (m, 3) and UV (3m, 2)."""
    positions = _real("V", V, (None, 3))
    triangles = _integer("F", F, (None, 3))
    m = triangles.shape[0]
    if _np.ndim(UV) == 3:
        corners = _real("UV", UV, (m, 3, 2)).reshape(-1, 2)
    else:
        corners = _real("UV", UV, (3 * m, 2))
    return positions, triangles, corners


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
        The map: the parameter coordinates of each triangle corner, ``UV[f, k]`` (or
        ``UV[3f + k]``) for corner k of triangle f.
    valences : array_like of int, shape (n,), optional
        The cross field's valence per vertex (4 regular). Default: counted from the map.
    feature_edges : array_like of int, shape (e, 2), optional
        Vertex pairs of edges to snap onto their closest integer iso-line.
    threads : int, optional
        Threads of the library's parallel loops: 0 (default) every core, 1 serial. The output is
        the same for every value.
    max_qvertices : int, optional
        Most grid points the map may hold (default 10,000,000, about the output's vertex count):
        a map beyond it is refused (``MapTooLarge``).
    max_trace_steps : int, optional
        Most triangles one trace may cross before it fails (default 100,000).
    recover_lost_edges : bool, optional
        Recover the q-edges lost at singularities inside fold-overs (default True).
    merge_vertices : bool, optional
        Merge the q-vertex clones that fold-overs create (default True).
    canonical_order : bool, optional
        Sort the output's vertices and faces canonically, so any input order gives the same mesh
        (default True).
    snap_boundary : bool, optional
        Treat every boundary edge as a feature edge (default False), as ``--snap-boundary``.
    repair_fold_overs : bool, optional
        Re-embed the regions of flipped and degenerate triangles before extracting (default True:
        certified). False is ``--no-repair``: the paper's local handling of fold-overs only, fast
        and uncertified (a mesh may have fewer quads than the map's area).
    fallback_ladder : bool, optional
        When the checker rejects the mesh, retry on the rungs of the fallback ladder (default True).
    best_effort : bool, optional
        When no attempt gives a valid mesh, return the one closest to valid (default False): the
        fewest checker violations, ties to the smallest grid scale; ``valid`` stays False and
        ``report["defects"]`` locates each violation, a collapsed handle first.
    fill_holes : bool, optional
        The last resort when no attempt gives a valid mesh (default True): holes that no grid
        cells close are filled with quads joining their rim vertices, kept only if the checker
        then accepts the mesh (``HoleFilled`` among ``report["explanations"]``: those quads follow
        no cells of the map). False: such a map stays invalid.

    The options are the fields of ``qex::Options`` (``include/qex/extract.h``); None, or leaving
    one out, keeps the library's default.

    Returns
    -------
    Result
        ``quads`` (k, 4) int32, ``positions`` (p, 3) float64, ``face_uvs`` (k, 4, 2),
        ``provenance``, ``valid``, ``report`` (the CLI's JSON report as a dict) and ``defects``.

    Raises
    ------
    ValueError
        Arrays of the wrong shape or dtype, or input the library rejects (empty mesh, index out
        of range, NaN or Inf, non-manifold or inconsistently oriented mesh, isolated vertex,
        inconsistent map, ...): the message names the vertex or triangle.
    TypeError
        An unknown option, or an option of the wrong type.

    Notes
    -----
    The GIL is released while the library works. A result with ``valid == False`` carries the
    checker's violations in ``report["check"]["violations"]``.

    Examples
    --------
    >>> import numpy as np, qex
    >>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]], float)
    >>> F = np.array([[0, 1, 2], [0, 2, 3]])
    >>> r = qex.extract(V, F, V[F][:, :, :2])
    >>> r.quads.shape, r.valid
    ((4, 4), True)
    """
    given = {
        "max_qvertices": max_qvertices,
        "max_trace_steps": max_trace_steps,
        "recover_lost_edges": recover_lost_edges,
        "merge_vertices": merge_vertices,
        "canonical_order": canonical_order,
        "snap_boundary": snap_boundary,
        "repair_fold_overs": repair_fold_overs,
        "fallback_ladder": fallback_ladder,
        "best_effort": best_effort,
        "fill_holes": fill_holes,
    }
    options = {k: v for k, v in given.items() if v is not None}
    V, F, UV = _map(V, F, UV)
    valences_ = None if valences is None else _integer("valences", valences, (None,))
    features = None if feature_edges is None else _integer("feature_edges", feature_edges, (None, 2))
    return Result(_qex.extract(V, F, UV, valences_, features, _threads(threads), options))


def verify(V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, result: Result, *, threads: int = 0) -> Dict[str, Any]:
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
    if not isinstance(result, Result):
        raise ValueError("result must be a qex.Result (what qex.extract returns)")
    verdict: Dict[str, Any] = _json.loads(_qex.verify(*_map(V, F, UV), result._mesh, _threads(threads)))
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
    certificate: Optional[_Path] = None,
) -> Dict[str, Any]:
    """Judge any quad mesh, given as arrays, against a map: the oracle for any extractor's output.

    The same code path and defaults as ``qex check --param`` (and ``qex draw --quads``, the C
    API's ``qex_check``): the same mesh gets the same verdict.

    Parameters
    ----------
    V, F, UV : array_like
        The map, as for `extract`.
    QV : array_like, shape (p, 3)
        The quad mesh's vertices.
    QF : array_like of int, shape (k, 4)
        Its faces, indices into `QV`, counter-clockwise.
    uv_tolerance : float, optional
        Largest UV distance (inf-norm) of a vertex to its integer grid point (default 1e-3), at
        most 1.
    distance_tolerance : float, optional
        Largest distance of a vertex to the surface, as a fraction of the bounding-box diagonal
        (default 1e-6).
    locate : bool, optional
        Locate the vertices on the map (default); False checks the topology only.
    digits : int, optional
        The positions may be rounded to this many significant digits (default 6: float
        precision); 0 takes them as exact doubles (``qex check --strict``).
    grid_scale : int, optional
        Judge the mesh against the map with its UVs multiplied by this power of two (1 to 64; a
        mesh qex extracted with refinement, ``report["fallback"]["grid_scale"]``).
    fold_regions : bool, optional
        Judge vertices in the map's fold-over regions on the surface only (default; False:
        ``qex check --no-fold-regions``).
    strict_map : bool, optional
        Decide every check against the raw map, fold-over regions too: what would be undecided
        there is a violation (``qex check --strict-map``).
    threads : int, optional
        Threads of the checker (0: every core).
    certificate : str or os.PathLike, optional
        qex's certificate for this mesh (`write_certificate`, ``qex extract --certificate``): it
        is checked against the map, and the mesh judged on the repaired map it holds, at its grid
        scale (``qex check --certificate``; excludes `grid_scale`). A certificate that does not
        hold gives ``CertificateMismatch`` violations.

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
        Arrays of the wrong shape or dtype, a map that `extract` would reject, a malformed
        certificate, or both `certificate` and a `grid_scale` other than 1.
    OSError
        The certificate cannot be read.
    """
    Vm, Fm, UVm = _map(V, F, UV)
    QVm = _real("QV", QV, (None, 3))
    QFm = _integer("QF", QF, (None, None))
    uv = _tolerance("uv_tolerance", uv_tolerance, 1.0)
    distance = _tolerance("distance_tolerance", distance_tolerance)
    digits_ = _small_int("digits", digits, 0, 17)
    scale = _small_int("grid_scale", grid_scale, 1, 64)
    verdict: Dict[str, Any] = _json.loads(
        _qex.check(Vm, Fm, UVm, QVm, QFm, uv, distance, bool(locate), digits_, scale, bool(fold_regions),
                   bool(strict_map), _threads(threads), "" if certificate is None else _os.fspath(certificate)))
    return verdict


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
    return dict(_qex.layout_of_arrays(_real("QV", QV, (None, 3)), _integer("QF", QF, (None, None))))


def read_obj(
    path: _Path, *, threads: int = 0
) -> Tuple[npt.NDArray[_np.float64], npt.NDArray[_np.int32], npt.NDArray[_np.float64]]:
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
    return _qex.read_obj(_os.fspath(path), _threads(threads))


def read_vval(path: _Path) -> npt.NDArray[_np.int32]:
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
    return _qex.read_vval(_os.fspath(path))


def write_certificate(path: _Path, V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, result: Result) -> None:
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
    if not isinstance(result, Result):
        raise ValueError("result must be a qex.Result (what qex.extract returns)")
    coarsening = result.report.get("fallback", {}).get("coarsening", 1)
    if coarsening > 1:
        raise ValueError(f"no certificate: the mesh was split from the map divided by {coarsening}")
    _qex.write_certificate(*_map(V, F, UV), result._mesh, _os.fspath(path))


def write_obj(path: _Path, result: Result) -> None:
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
    if not isinstance(result, Result):
        raise ValueError("result must be a qex.Result (what qex.extract returns)")
    _qex.write_obj(_os.fspath(path), result._mesh)
