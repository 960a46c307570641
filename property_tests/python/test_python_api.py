# The Python package against the CLI and the library: arrays in and out, the report, every bad
# input, the oracle `check` on corrupted meshes, files, and threads.
import json
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import qex
from conftest import SAMPLE

PAPER = ["duck_miq_4", "duck_miq_8", "duck_miq_16", "duck_miq_28", "duck_qc_8"]


def square():
    V = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    return V, F, V[F][:, :, :2].copy()


def read_quads(path):
    """(positions, faces) of a quad OBJ as qex writes it."""
    V, Q = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                V.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                Q.append([int(c.split("/")[0]) - 1 for c in line.split()[1:]])
    return np.array(V), np.array(Q)


def without_times(report):
    report = dict(report)
    report.pop("seconds")
    report.pop("stage_seconds")
    return report


def against_cli(cli, tmp_path, map_path):
    out, rep = tmp_path / "cli.obj", tmp_path / "cli.json"
    # The CLI runs while Python extracts (the GIL is released).
    proc = subprocess.Popen([str(cli), "extract", str(map_path), "-o", str(out), "--report", str(rep), "-q"])
    V, F, UV = qex.read_obj(map_path)
    r = qex.extract(V, F, UV)
    assert proc.wait() == 0
    assert r.valid
    QV, QF = read_quads(out)
    np.testing.assert_array_equal(r.positions, QV)  # shortest round-trip text: bitwise equal
    np.testing.assert_array_equal(r.quads, QF)
    # The CLI's report adds the mesh's quality figures, which `qex.check` measures too.
    by_cli = json.loads(rep.read_text())
    assert "quality" not in r.report
    assert by_cli.pop("quality") == qex.check(V, F, UV, r.positions, r.quads)["quality"]
    assert without_times(r.report) == without_times(by_cli)
    assert r.defects == r.report["defects"]
    mine = tmp_path / "py.obj"
    qex.write_obj(mine, r)
    assert mine.read_bytes() == out.read_bytes()
    return V, F, UV, r


def test_sample_same_as_cli(cli, tmp_path):
    V, F, UV, r = against_cli(cli, tmp_path, SAMPLE)
    assert r.quads.shape == (54, 4) and r.quads.dtype == np.int32
    assert r.positions.shape == (56, 3) and r.positions.dtype == np.float64
    assert r.face_uvs.shape == (54, 4, 2)
    # Each quad's local UVs are a counter-clockwise unit square.
    d = np.diff(np.concatenate([r.face_uvs, r.face_uvs[:, :1]], axis=1), axis=1)
    assert (np.abs(d).sum(axis=2) == 1).all()
    p = r.provenance
    assert all(len(p[k]) == 56 for k in p)
    assert p["barycentric"].shape == (56, 3) and p["grid"].shape == (56, 2)
    assert qex.verify(V, F, UV, r)["valid"]


@pytest.mark.parametrize("name", PAPER)
def test_paper_map_same_as_cli(cli, shared_dir, tmp_path, name):
    against_cli(cli, tmp_path, shared_dir / "paper" / (name + "_param.obj"))


def test_layouts_and_dtypes_give_the_same_mesh():
    V, F, UV = qex.read_obj(SAMPLE)
    want = qex.extract(V, F, UV)
    variants = [
        (V, F, UV.reshape(-1, 2)),  # (3m, 2)
        (np.asfortranarray(V), np.asfortranarray(F), UV),  # column-major
        (np.repeat(V, 2, axis=0)[::2], F[:, ::-1][:, ::-1], UV[::-1][::-1]),  # strided views
        (V.tolist(), F.tolist(), UV.tolist()),  # nested lists
        (V, F.astype(np.uint16), UV),
        (V, F.astype(np.int64), UV.astype(np.longdouble)),
    ]
    for Vx, Fx, UVx in variants:
        got = qex.extract(Vx, Fx, UVx)
        np.testing.assert_array_equal(got.quads, want.quads)
        np.testing.assert_array_equal(got.positions, want.positions)
    assert qex.extract(V, F, UV, threads=1, canonical_order=True).valid


def bad_inputs():
    V, F, UV = square()
    nan_v = V.copy()
    nan_v[2, 1] = np.nan
    inf_uv = UV.copy()
    inf_uv[1, 2, 0] = np.inf
    fan = np.array([[0, 1, 2], [0, 2, 3], [2, 0, 1]])
    return {
        "V not (n,3)": ((V[:, :2], F, UV), "V must have shape"),
        "V 1-d": ((V.ravel(), F, UV), "V must have shape"),
        "V complex": ((V.astype(complex), F, UV), "real numbers"),
        "V strings": ((V.astype(str), F, UV), "real numbers"),
        "V objects": ((np.array([[None] * 3] * 4), F, UV), "real numbers"),
        "F float": ((V, F.astype(float), UV), "integers"),
        "F (m,4)": ((V, np.hstack([F, F[:, :1]]), UV), "F must have shape"),
        "F too large": ((V, F + 2**40, UV), "32 bits"),
        "F uint64 huge": ((V, np.full((2, 3), 2**64 - 1, np.uint64), UV), "out of range"),
        "UV too few": ((V, F, UV[:1]), "UV must have shape"),
        "UV (m,3,3)": ((V, F, np.zeros((2, 3, 3))), "UV must have shape"),
        "UV (3m,3)": ((V, F, np.zeros((6, 3))), "UV must have shape"),
        "empty": ((np.zeros((0, 3)), np.zeros((0, 3), int), np.zeros((0, 2))), "EmptyMesh"),
        "empty lists": (([], [], []), "must have shape"),
        "NaN position": ((nan_v, F, UV), "NonFiniteValue: vertex 2"),
        "Inf uv": ((V, F, inf_uv), "NonFiniteValue: triangle 1"),
        "index out of range": ((V, F + 1, UV), "IndexOutOfRange"),
        "negative index": ((V, F - 1, UV), "IndexOutOfRange"),
        "isolated vertex": ((np.vstack([V, [5, 5, 5]]), F, UV), "IsolatedVertex: vertex 4"),
        "repeated vertex": ((V, np.array([[0, 1, 1], [0, 2, 3]]), UV), "DegenerateTriangle"),
        "three triangles on an edge": ((V, fan, np.zeros((3, 3, 2))), "triangle"),
        "huge coordinate": ((V * 2.0**60, F, UV), "CoordinateTooLarge"),
    }


@pytest.mark.parametrize("case", list(bad_inputs()))
def test_bad_input_raises_value_error(case):
    args, message = bad_inputs()[case]
    with pytest.raises(ValueError, match=message):
        qex.extract(*args)


def test_random_shapes_dtypes_and_strides_never_crash():
    """Any array for any argument: a result, ValueError or TypeError, never a crash."""
    V, F, UV = square()
    rng = np.random.default_rng(15)
    pool = [V, F, UV, UV.reshape(-1, 2), V[::-1], V.T, F.T, UV.transpose(1, 0, 2), np.asfortranarray(UV),
            np.zeros(()), np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3), np.int32), np.zeros((1, 1, 1, 1)),
            V.astype(np.float32), F.astype(np.int8), F.astype(np.uint64), F.astype(bool), V.astype(complex),
            V.astype(object), V.astype(str), np.array(["2020-01-01"], "datetime64[D]"), np.full((4, 3), np.nan),
            np.full((2, 3), -(2**31)), np.full((2, 3, 2), np.inf), [[0, 1, 2]], [], None, 1, "abc"]
    outcomes = {}
    for _ in range(400):
        args = [pool[i] for i in rng.integers(0, len(pool), 3)]
        try:
            qex.extract(*args)
            outcome = "result"
        except (ValueError, TypeError) as e:
            outcome = type(e).__name__
        outcomes[outcome] = outcomes.get(outcome, 0) + 1
    assert outcomes.get("ValueError", 0) > 100, outcomes
    for bad in [np.zeros(()), np.zeros(0), np.zeros((1, 1, 1, 1)), V.astype(complex), V.astype(object), V.astype(str),
                np.array(["2020-01-01"], "datetime64[D]"), None, "abc"]:
        with pytest.raises((ValueError, TypeError)):
            qex.check(V, F, UV, bad, [[0, 1, 2, 3]])
        with pytest.raises((ValueError, TypeError)):
            qex.check(V, F, UV, V, bad)


def test_bad_options_and_extras():
    V, F, UV = square()
    with pytest.raises(TypeError, match="no_such_option"):
        qex.extract(V, F, UV, no_such_option=1)
    with pytest.raises(ValueError, match="valences"):
        qex.extract(V, F, UV, valences=np.zeros((4, 2), int))
    with pytest.raises(ValueError, match="ValenceCountMismatch"):
        qex.extract(V, F, UV, valences=[4, 4])
    with pytest.raises(ValueError, match="BadFeatureEdge"):
        qex.extract(V, F, UV, feature_edges=[[1, 3]])
    with pytest.raises(ValueError, match="MapTooLarge"):
        qex.extract(V, F, UV, max_qvertices=1)
    with pytest.raises(ValueError):
        qex.verify(V, F, UV, "not a result")
    with pytest.raises(TypeError, match="max_qvertices"):
        qex.extract(V, F, UV, max_qvertices="many")
    for threads in (-1, 2**40, 1.5, True):
        with pytest.raises(ValueError, match="threads"):
            qex.extract(V, F, UV, threads=threads)
    for tolerance in (-1.0, float("nan")):
        with pytest.raises(ValueError, match="uv_tolerance"):
            qex.check(V, F, UV, V, [[0, 1, 2, 3]], uv_tolerance=tolerance)
    with pytest.raises(TypeError):
        qex.read_obj(None)
    assert qex.extract(V, F, UV, feature_edges=[[0, 1]], valences=[4, 4, 4, 4]).valid


def test_best_effort_returns_the_mesh_closest_to_valid(shared_dir):
    """fertility_miq_5 collapses a handle: named first, no refinement tried; with best_effort the
    refined mesh that loses only that handle comes back, still invalid."""
    V, F, UV = qex.read_obj(shared_dir / "miq" / "fertility_miq_5_param.obj")
    plain = qex.extract(V, F, UV)
    assert not plain.valid
    assert plain.report["defects"][0]["kind"] == "MapCollapsesHandle"
    assert plain.report["fallback"]["refinements_tried"] == 0
    handle = plain.report["collapsed_handles"][0]
    assert handle["vertex"] >= 0 and len(handle["triangles"]) > 200 and abs(handle["signed_uv_area"]) < 0.002
    r = qex.extract(V, F, UV, best_effort=True)
    assert not r.valid
    assert r.report["fallback"]["grid_scale"] in (4, 8)
    assert [v["kind"] for v in r.report["check"]["violations"]] == ["EulerMismatch"]
    assert r.report["explanations"][0]["kind"] == "BestEffortMesh"
    assert r.quads.shape[0] > 0
    with pytest.raises(TypeError, match="best_effort"):
        qex.extract(V, F, UV, best_effort="yes please")


def test_fill_holes_is_the_last_resort_and_can_be_turned_off(shared_dir):
    """decimated-knight_miq_18 leaves a hole round a fold between pinned singularities at every
    scale: filled from its rim (HoleFilled) the mesh is valid; with fill_holes=False it is not."""
    V, F, UV = qex.read_obj(shared_dir / "miq-more" / "decimated-knight_miq_18_param.obj")
    r = qex.extract(V, F, UV)
    assert r.valid
    kinds = [d["kind"] for d in r.report["explanations"]]
    assert "HoleFilled" in kinds and "FoldPinnedBySingularities" in kinds
    off = qex.extract(V, F, UV, fill_holes=False)
    assert not off.valid
    assert "HoleFilled" not in [d["kind"] for d in off.report["explanations"]]
    with pytest.raises(TypeError, match="fill_holes"):
        qex.extract(V, F, UV, fill_holes="sometimes")


def test_hostile_numbers_are_refused_cleanly():
    """Indices, sizes and options at the edges: ValueError (or TypeError for a wrong type), never a
    silent truncation, wrap or crash, from the package and from its compiled half called directly."""
    V, F, UV = square()
    for bad_F in (F.astype(float), np.full((2, 3), np.nan), np.full((2, 3), np.inf), F + 0.5, F * 1e96):
        with pytest.raises(ValueError, match="integers"):
            qex.extract(V, bad_F, UV)
        with pytest.raises(ValueError, match="integers"):
            qex._qex.extract(V, bad_F, UV.reshape(-1, 2), None, None, 0, {})
        with pytest.raises(ValueError, match="integers"):
            qex._qex.check(V, F, UV.reshape(-1, 2), V, bad_F, 1e-3, 1e-6, True, 6, 1, True, False, 0, "")
    with pytest.raises(ValueError, match="integers"):
        qex._qex.extract(V, F, UV.reshape(-1, 2), np.full(4, 4.0), None, 0, {})
    with pytest.raises(ValueError, match="integers"):
        qex._qex.extract(V, F, UV.reshape(-1, 2), None, np.array([[0.0, 1.0]]), 0, {})
    with pytest.raises(ValueError, match="out of range"):
        qex._qex.extract(V, np.full((2, 3), 2**63, np.uint64), UV.reshape(-1, 2), None, None, 0, {})
    for index, message in ((2**31, "32 bits"), (-(2**31) - 1, "32 bits"), (2**63 - 1, "32 bits"),
                           (2**31 - 1, "IndexOutOfRange"), (-(2**31), "IndexOutOfRange")):
        big = F.copy()
        big[1, 2] = index
        with pytest.raises(ValueError, match=message):
            qex.extract(V, big, UV)
    with pytest.raises(ValueError, match="32 bits"):
        qex.extract(V, F, UV, valences=[4, 4, 4, 2**31])
    with pytest.raises(ValueError, match="32 bits"):
        qex.extract(V, F, UV, feature_edges=[[0, 2**32 + 1]])
    for size in (2**63, -(2**63) - 1, 2**64):
        with pytest.raises(ValueError, match="64 bits"):
            qex.extract(V, F, UV, max_qvertices=size)
    for size in (1.0, np.float64(1e96), float("nan")):
        with pytest.raises(TypeError, match="max_qvertices"):
            qex.extract(V, F, UV, max_qvertices=size)
    assert qex.extract(V, F, UV, max_qvertices=2**63 - 1, max_trace_steps=np.int64(2**62)).valid
    for tolerance in (float("inf"), 1.5, 1e308):
        with pytest.raises(ValueError, match="uv_tolerance"):
            qex.check(V, F, UV, V, [[0, 1, 2, 3]], uv_tolerance=tolerance)
        with pytest.raises(ValueError, match="uv_tolerance"):
            qex._qex.check(V, F, UV.reshape(-1, 2), V, np.array([[0, 1, 2, 3]]), tolerance, 1e-6, True, 6, 1, True, False, 0, "")
    for tolerance in (float("inf"), float("nan"), -1.0):
        with pytest.raises(ValueError, match="distance_tolerance"):
            qex.check(V, F, UV, V, [[0, 1, 2, 3]], distance_tolerance=tolerance)
        with pytest.raises(ValueError, match="distance_tolerance"):
            qex._qex.check(V, F, UV.reshape(-1, 2), V, np.array([[0, 1, 2, 3]]), 1e-3, tolerance, True, 6, 1, True, False, 0, "")


def test_check_is_the_oracle_of_arrays():
    V, F, UV = qex.read_obj(SAMPLE)
    r = qex.extract(V, F, UV)
    ok = qex.check(V, F, UV, r.positions, r.quads)
    assert ok["valid"] and ok["violations"] == [] and ok["faces"] == 54

    flipped = r.quads.copy()
    flipped[3] = flipped[3][::-1]
    verdict = qex.check(V, F, UV, r.positions, flipped)
    assert not verdict["valid"]
    assert {"InconsistentOrientation"} <= {v["kind"] for v in verdict["violations"]}

    moved = r.positions.copy()
    moved[7] += [0.01, 0.02, -0.01]
    verdict = qex.check(V, F, UV, moved, r.quads)
    assert not verdict["valid"]
    assert any(v["kind"] == "OffSurface" and v["element"] == 7 for v in verdict["violations"])
    # The quality figures, as `qex check --json` prints them: the moved vertex is measured off
    # the surface; the quads stay the same.
    assert ok["quality"]["computed"] and ok["quality"]["quads"] == 54
    assert ok["quality"]["distance"]["mesh_to_input"] < 1e-9 < verdict["quality"]["distance"]["mesh_to_input"]
    assert verdict["quality"]["quads"] == 54 and 0 < ok["quality"]["scaled_jacobian"]["min"] <= 1

    verdict = qex.check(V, F, UV, r.positions, r.quads[1:])
    assert not verdict["valid"]

    verdict = qex.check(V, F, UV, r.positions, r.quads + 1000)
    assert any(v["kind"] == "BadIndex" for v in verdict["violations"])
    # Topology only, and tolerances.
    assert qex.check(V, F, UV, moved, r.quads, locate=False)["valid"]
    assert qex.check(V, F, UV, moved, r.quads, distance_tolerance=1.0, uv_tolerance=1.0)["valid"] in (True, False)
    # A map that extraction would reject judges nothing.
    with pytest.raises(ValueError, match="IndexOutOfRange"):
        qex.check(V, F + 1000, UV, r.positions, r.quads)
    with pytest.raises(ValueError, match="QF must"):
        qex.check(V, F, UV, r.positions, r.quads.ravel())


def test_files(tmp_path):
    with pytest.raises(OSError):
        qex.read_obj(tmp_path / "missing.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(ValueError, match="line"):
        qex.read_obj(bad)
    V, F, UV = square()
    with pytest.raises(OSError):
        qex.write_obj(tmp_path / "no" / "such" / "dir.obj", qex.extract(V, F, UV))


def test_docstrings_and_stubs():
    import qex.batch

    # Every public function documents its parameters numpy-style, and what it returns or raises.
    for f in (qex.extract, qex.verify, qex.check, qex.read_obj, qex.write_obj, qex.batch.run_one,
              qex.batch.find_maps, qex.batch.run_batch, qex.batch.main):
        assert "Parameters\n    ----------" in f.__doc__, f.__name__
        assert "Returns\n    -------" in f.__doc__ or "Raises\n    ------" in f.__doc__, f.__name__
    import pathlib

    package = pathlib.Path(qex.__file__).parent
    assert (package / "py.typed").exists() and (package / "_qex.pyi").exists()
    # The compiled functions' docstrings, numpy-style too (after pybind11's signature line).
    for f in (qex._qex.extract, qex._qex.verify, qex._qex.check, qex._qex.read_obj, qex._qex.write_obj):
        assert "Parameters\n----------" in f.__doc__, f.__name__


def test_threads_run_in_parallel_and_agree():
    V, F, UV = qex.read_obj(SAMPLE)
    # While one thread is inside extract(), the main thread runs Python code: the GIL is
    # released. Held, the main thread could not run from the call's start to its end, and the
    # largest gap between its steps would be the whole call.
    UV24 = UV * 24  # 31104 quads, some 0.1 s to 0.5 s
    window = {}

    def work():
        window["start"] = time.perf_counter()
        qex.extract(V, F, UV24, threads=1)
        window["end"] = time.perf_counter()

    stamps = []
    t = threading.Thread(target=work)
    t.start()
    while t.is_alive():
        stamps.append(time.perf_counter())
    t.join()
    start, end = window["start"], window["end"]
    steps = [start] + [s for s in stamps if start < s < end] + [end]
    gap = max(b - a for a, b in zip(steps, steps[1:]))
    assert gap < 0.5 * (end - start), "the main thread stood still %.3f s of the call's %.3f s" % (gap, end - start)
    # Several threads at once give the same meshes as one.
    UV8 = UV * 8
    want = qex.extract(V, F, UV8, threads=1)
    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(lambda _: qex.extract(V, F, UV8, threads=1), range(8)))
    for r in results:
        np.testing.assert_array_equal(r.quads, want.quads)
        np.testing.assert_array_equal(r.positions, want.positions)


def test_read_vval_is_the_librarys_reader(tmp_path):
    # The valences qex.batch takes beside a map: read by the library, so a hostile count or valence
    # is refused with its line, as `qex extract --valences` refuses it.
    good = tmp_path / "good.vval"
    good.write_text('{"file_format":"VVAL","version":1}\n3\n4\n-0\n5\n')
    val = qex.read_vval(good)
    assert val.dtype == np.int32 and val.tolist() == [4, 0, 5]
    for body, line in [("2\n4\n" + "6" * 96 + "\n", "line 4"), ("2\n4\nnan\n", "line 4"),
                       ("9007199254740993\n4\n4\n", "line 2"), ("2\n4\n4.0\n", "line 4")]:
        bad = tmp_path / "bad.vval"
        bad.write_text('{"file_format":"VVAL","version":1}\n' + body)
        with pytest.raises(ValueError, match=line):
            qex.read_vval(bad)
    with pytest.raises(OSError):
        qex.read_vval(tmp_path / "absent.vval")
