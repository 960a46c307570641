# Type stubs of the compiled module qex._qex (src/python/qex_module.cpp and the bind_*.cpp beside
# it). Its functions take the arrays the Python half (qex/extraction.py, checking.py, ...) has
# already checked and shaped; users call qex itself.
# `python3 -m mypy.stubtest qex._qex` compares this file with the module (ctest python_types).
from typing import Any, Dict, List, Optional, Tuple, TypedDict

import numpy as np
import numpy.typing as npt

class QuadMesh:
    """The extracted mesh as the library holds it (for verify and write_obj)."""

    @property
    def num_faces(self) -> int: ...
    @property
    def num_vertices(self) -> int: ...

class _Extracted(TypedDict):
    """What `extract` returns (a dict at run time)."""

    quads: npt.NDArray[np.int32]
    positions: npt.NDArray[np.float64]
    face_uvs: npt.NDArray[np.int64]
    provenance: Dict[str, npt.NDArray[Any]]
    valid: bool
    report_json: str
    mesh: QuadMesh

def extract(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    UV: npt.ArrayLike,
    valences: Optional[npt.ArrayLike],
    feature_edges: Optional[npt.ArrayLike],
    threads: int,
    options: Dict[str, Any],
) -> _Extracted: ...
def verify(V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, mesh: QuadMesh, threads: int) -> str: ...
def check(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    UV: npt.ArrayLike,
    QV: npt.ArrayLike,
    QF: npt.ArrayLike,
    uv_tolerance: float,
    distance_tolerance: float,
    locate: bool,
    digits: int,
    grid_scale: int,
    fold_regions: bool,
    strict_map: bool,
    threads: int,
    certificate: str,
) -> str: ...
def read_obj(path: str, threads: int) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32], npt.NDArray[np.float64]]: ...
def read_vval(path: str) -> npt.NDArray[np.int32]: ...
def write_obj(path: str, mesh: QuadMesh) -> None: ...
def write_certificate(V: npt.ArrayLike, F: npt.ArrayLike, UV: npt.ArrayLike, mesh: QuadMesh, path: str) -> None: ...

class _Layout(TypedDict):
    """What `layout` returns (a dict at run time): the quad layout (qex/layout.h)."""

    valid: bool
    error: str
    face_patch: npt.NDArray[np.int64]
    patch_sizes: npt.NDArray[np.int64]
    patch_corners: npt.NDArray[np.int64]
    separatrices: List[npt.NDArray[np.int64]]
    separatrix_ends: List[str]
    adjacency: npt.NDArray[np.int64]
    special_vertices: npt.NDArray[np.int64]
    notes: List[str]

def layout(mesh: QuadMesh) -> _Layout: ...
def layout_of_arrays(QV: npt.ArrayLike, QF: npt.ArrayLike) -> _Layout: ...

# qex.conform (qex/conformance.py): the library's cases, judge and table; cases and rows as JSON.
def conform_cases(sets: List[str], count: int, seed: int) -> List[str]: ...
def conform_map_text(case: str) -> str: ...
def conform_judge(
    case: str,
    map_path: str,
    out_path: str,
    stderr_path: str,
    exit_code: int,
    signal: int,
    timed_out: bool,
    seconds: float,
    out_dir: str,
    replay_command: str,
    checker: str,
) -> str: ...
def conform_table(rows: List[str]) -> str: ...
