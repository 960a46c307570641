# The layout (qex.layout, on qex._qex.layout and layout_of_arrays, issue 33): numpy arrays of the quad
# layout, from an extracted result or from vertex and face arrays.
import numpy as np
import pytest

from conftest import ROOT

qex = pytest.importorskip("qex")


def test_the_cube_has_six_square_patches():
    V, F, UV = qex.read_obj(ROOT / "corpus" / "fuzz_obj" / "valid" / "cube_n3_k4.obj")
    r = qex.extract(V, F, UV)
    d = qex.layout(r)
    assert d["face_patch"].tolist() == qex._qex.layout(r._mesh)["face_patch"].tolist()
    assert qex.layout((r.positions, r.quads))["patch_sizes"].tolist() == d["patch_sizes"].tolist()
    assert d["valid"], d["error"]
    assert d["patch_sizes"].tolist() == [[3, 3]] * 6
    assert d["face_patch"].shape == (54,) and d["face_patch"].dtype == np.int64
    assert len(d["separatrices"]) == 12 and set(d["separatrix_ends"]) == {"HeadOn"}
    assert all(len(s) == 4 for s in d["separatrices"])
    assert d["adjacency"].shape == (12, 3) and len(d["special_vertices"]) == 8


def test_arrays_in_and_the_reason_of_a_refusal():
    QV = np.array([[x, y, 0.0] for y in range(3) for x in range(3)])
    QF = np.array([[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]])
    d = qex.layout((QV, QF))
    assert d["valid"] and d["patch_sizes"].tolist() == [[2, 2]] and d["separatrices"] == []
    bad = qex.layout((QV, QF[:, :3]))
    assert not bad["valid"] and "3 vertices" in bad["error"]
