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
read_obj   read an OBJ map as (V, F, UV)
write_obj  write an extracted mesh as OBJ

Bad input raises ValueError with the library's message, which names the element at fault. The
library releases the GIL while it works, so extractions in several Python threads run in parallel.
"""

import json as _json
import os as _os

import numpy as _np

from . import _qex

__all__ = ["Result", "extract", "verify", "check", "read_obj", "write_obj"]


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

    __slots__ = ("quads", "positions", "face_uvs", "provenance", "valid", "report", "defects", "_mesh")

    def __init__(self, raw):
        self.quads = raw["quads"]
        self.positions = raw["positions"]
        self.face_uvs = raw["face_uvs"]
        self.provenance = raw["provenance"]
        self.valid = bool(raw["valid"])
        self.report = _json.loads(raw["report_json"])
        self.defects = self.report["defects"]
        self._mesh = raw["mesh"]

    def __repr__(self):
        return "qex.Result(%d quads, %d vertices, valid=%s)" % (len(self.quads), len(self.positions), self.valid)


def _real(name, a, shape):
    """`a` as a C-contiguous float64 array of the given shape (None: any length)."""
    a = _np.asarray(a)
    if a.dtype.kind not in "biuf":
        raise ValueError("%s must hold real numbers, not %s" % (name, a.dtype))
    return _shaped(name, _np.ascontiguousarray(a, dtype=_np.float64), shape)


def _integer(name, a, shape):
    """`a` as a C-contiguous int64 array of the given shape; integer dtypes only."""
    a = _np.asarray(a)
    if a.size == 0 and a.dtype.kind == "f":
        a = a.astype(_np.int64)  # np.zeros((0, 3)) is float64: an empty array has no wrong values
    if a.dtype.kind not in "biu":
        raise ValueError("%s must hold integers, not %s" % (name, a.dtype))
    if a.dtype.kind == "u" and a.size and a.max() > _np.iinfo(_np.int64).max:
        raise ValueError("%s: index %d is out of range" % (name, a.max()))
    return _shaped(name, _np.ascontiguousarray(a, dtype=_np.int64), shape)


def _shaped(name, a, shape):
    if a.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, a.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError("%s must have shape %s, got %s" % (name, want, a.shape))
    return a


def _threads(threads):
    """The thread count as the CLI takes it (0: every core)."""
    if isinstance(threads, bool) or not isinstance(threads, (int, _np.integer)) or not 0 <= threads <= 1024:
        raise ValueError("threads must be an integer from 0 (every core) to 1024, not %r" % (threads,))
    return int(threads)


def _tolerance(name, x, most=None):
    """A tolerance: a finite number from 0 (to `most`, if given); NaN and infinities refused."""
    x = float(x)
    if not (0 <= x < _np.inf and (most is None or x <= most)):  # NaN fails the comparisons
        bound = "" if most is None else " to %g" % most
        raise ValueError("%s must be a finite number from 0%s, not %r" % (name, bound, x))
    return x


def _map(V, F, UV):
    V = _real("V", V, (None, 3))
    F = _integer("F", F, (None, 3))
    UV = _np.asarray(UV)
    if UV.ndim == 3:
        UV = _real("UV", UV, (F.shape[0], 3, 2)).reshape(-1, 2)
    else:
        UV = _real("UV", UV, (3 * F.shape[0], 2))
    return V, F, UV


def extract(V, F, UV, *, valences=None, feature_edges=None, threads=0, **options):
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
    **options
        Any field of ``qex::Options``: ``max_qvertices``, ``max_trace_steps``,
        ``recover_lost_edges``, ``merge_vertices``, ``canonical_order``, ``snap_boundary``,
        ``repair_fold_overs``, ``fallback_ladder``, ``best_effort`` (when no attempt gives a valid
        mesh, return the one closest to valid: the fewest checker violations, ties to the
        smallest grid scale; ``valid`` stays False and ``report["defects"]`` locates each).

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
        An unknown option.

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
    V, F, UV = _map(V, F, UV)
    if valences is not None:
        valences = _integer("valences", valences, (None,))
    if feature_edges is not None:
        feature_edges = _integer("feature_edges", feature_edges, (None, 2))
    return Result(_qex.extract(V, F, UV, valences, feature_edges, _threads(threads), options))


def verify(V, F, UV, result, *, threads=0):
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
    V, F, UV = _map(V, F, UV)
    return _json.loads(_qex.verify(V, F, UV, result._mesh, _threads(threads)))


def check(V, F, UV, QV, QF, *, uv_tolerance=1e-3, distance_tolerance=1e-6, locate=True, threads=0):
    """Judge any quad mesh, given as arrays, against a map: the oracle for any extractor's output.

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
    threads : int, optional
        Threads of the checker (0: every core).

    Returns
    -------
    dict
        The verdict, as ``qex check --json`` prints it: ``valid``, ``violations`` (each with
        ``kind``, ``element``, ``message``), ``undecided``, and the counts.

    Raises
    ------
    ValueError
        Arrays of the wrong shape or dtype, or a map that `extract` would reject.
    """
    V, F, UV = _map(V, F, UV)
    QV = _real("QV", QV, (None, 3))
    QF = _integer("QF", QF, (None, None))
    uv_tolerance = _tolerance("uv_tolerance", uv_tolerance, 1.0)
    distance_tolerance = _tolerance("distance_tolerance", distance_tolerance)
    return _json.loads(_qex.check(V, F, UV, QV, QF, uv_tolerance, distance_tolerance, bool(locate), _threads(threads)))


def read_obj(path, *, threads=0):
    """Read an OBJ map (``v``, ``vt`` and ``f a/ta b/tb c/tc`` records).

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


def write_obj(path, result):
    """Write an extracted mesh as OBJ (quads, with their integer local UVs as ``vt``).

    The file is written to ``path + ".tmp"`` and renamed, so no partial file is ever left.

    Raises
    ------
    OSError
        The file cannot be written.
    """
    if not isinstance(result, Result):
        raise ValueError("result must be a qex.Result (what qex.extract returns)")
    _qex.write_obj(_os.fspath(path), result._mesh)
