# qex.conform on a 2-worker LocalCluster: qex's own extraction as a Python callable is right on
# the known and hostile cases of seed 1 (but the named known wrong ones, as cli_conform_test.py
# names them), and broken callables are classified as the CLI classifies them.
import json
import os
import time

import pytest

import qex

distributed = pytest.importorskip("dask.distributed")

# qex.extract exits 0 with a mesh qex check rejects (cli_conform_test.py lists the same).
KNOWN_WRONG = {"hostile/dropped_triangle/0004"}


def make_extractor(mode):
    """qex's extraction through the Python package, broken on purpose in one way."""

    def extractor(map_path, out_path):
        if mode == "raise":
            raise RuntimeError("this extractor refuses")
        if mode == "sleep":
            time.sleep(5)
            return 0
        V, F, UV = qex.read_obj(map_path)  # a malformed map raises: a clean failure
        r = qex.extract(V, F, UV, threads=1)
        if not r.valid:
            return 5
        qex.write_obj(out_path, r)
        if mode == "drop_face":
            lines = open(out_path).read().splitlines(True)
            first = next(i for i, line in enumerate(lines) if line.startswith("f "))
            open(out_path, "w").write("".join(lines[:first] + lines[first + 1:]))
        return 0

    return extractor


@pytest.fixture(scope="module")
def scheduler():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    yield cluster.scheduler_address
    cluster.close()


def test_qex_extract_is_right(tmp_path, scheduler):
    rows = qex.conform(make_extractor("none"), str(tmp_path), count=9, seed=1, scheduler=scheduler, progress=False)
    assert len(rows) == 18
    lines = [json.loads(line) for line in open(tmp_path / "summary.jsonl")]
    assert [r["case"] for r in lines] == [r["case"] for r in rows]
    for r in rows:
        assert {"case", "family", "outcome", "right"} <= set(r)
        assert r["right"] or r["case"] in KNOWN_WRONG, (r["case"], r["outcome"], r["detail"])
    assert {r["outcome"] for r in rows if r["kind"] == "known"} == {"exact"}
    for r in rows:
        if not r["right"]:  # its reproducer, as the CLI writes it
            assert os.path.exists(os.path.join(r["folder"], "replay.sh"))
            assert os.path.exists(os.path.join(r["folder"], "verdict.json"))


@pytest.mark.parametrize("mode,outcome", [("drop_face", "invalid_exit_0"), ("raise", "clean_failure"),
                                          ("sleep", "timeout")])
def test_broken_callables(tmp_path, scheduler, mode, outcome):
    rows = qex.conform(make_extractor(mode), str(tmp_path), cases=["known"], count=2, seed=3, timeout=0.5,
                       scheduler=scheduler, progress=False)
    assert [r["outcome"] for r in rows] == [outcome] * 2, [r["detail"] for r in rows]
    assert not any(r["right"] for r in rows)
    if mode == "raise":
        assert "this extractor refuses" in open(os.path.join(rows[0]["folder"], "stderr.txt")).read()
