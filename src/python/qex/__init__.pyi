# Type stubs of the qex package (see the docstrings in __init__.py).
from os import PathLike
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__all__ = ["Result", "extract", "verify", "check", "read_obj", "write_obj"]

class Result:
    quads: npt.NDArray[np.int32]  # (k, 4)
    positions: npt.NDArray[np.float64]  # (p, 3)
    face_uvs: npt.NDArray[np.int64]  # (k, 4, 2)
    provenance: Dict[str, npt.NDArray[Any]]
    valid: bool
    report: Dict[str, Any]
    defects: List[Dict[str, Any]]

def extract(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    UV: npt.ArrayLike,
    *,
    valences: Optional[npt.ArrayLike] = ...,
    feature_edges: Optional[npt.ArrayLike] = ...,
    threads: int = ...,
    max_qvertices: int = ...,
    max_trace_steps: int = ...,
    recover_lost_edges: bool = ...,
    merge_vertices: bool = ...,
    canonical_order: bool = ...,
    snap_boundary: bool = ...,
    repair_fold_overs: bool = ...,
    fallback_ladder: bool = ...,
    best_effort: bool = ...,
) -> Result: ...
def verify(V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, result: Result, *, threads: int = ...) -> Dict[str, Any]: ...
def check(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    UV: npt.ArrayLike,
    QV: npt.ArrayLike,
    QF: npt.ArrayLike,
    *,
    uv_tolerance: float = ...,
    distance_tolerance: float = ...,
    locate: bool = ...,
    threads: int = ...,
) -> Dict[str, Any]: ...
def read_obj(
    path: Union[str, "PathLike[str]"], *, threads: int = ...
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32], npt.NDArray[np.float64]]: ...
def write_obj(path: Union[str, "PathLike[str]"], result: Result) -> None: ...
