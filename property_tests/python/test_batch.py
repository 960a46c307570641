# python3 -m qex.batch on a 2-worker LocalCluster over the shared paper and MIQ maps (and a bad
# map, which must not stop it): the summary against the CLI, row by row, then a resumed run.
# Every map of ../shared/meshes/{paper,miq} (about a minute on two cores); QEX_BATCH_SUBSET=1 takes
# six of them, for a quick run.
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import pytest

from conftest import ROOT

SUBSET = ["paper/duck_miq_4_param.obj", "paper/duck_qc_8_param.obj", "miq/fandisk_miq_10_param.obj",
          "miq/bunny_miq_10_param.obj", "miq/3holes_miq_10_param.obj", "miq/fertility_miq_10_param.obj"]


def maps(shared_dir):
    if os.environ.get("QEX_BATCH_SUBSET"):
        return [str(shared_dir / m) for m in SUBSET if (shared_dir / m).exists()]
    return sorted(str(p) for d in ("paper", "miq") for p in (shared_dir / d).glob("*.obj"))


def run_batch(*args):
    return subprocess.run([sys.executable, "-m", "qex.batch", *map(str, args)], capture_output=True, text=True,
                          timeout=900)


def read_summary(out):
    rows = [json.loads(line) for line in (out / "summary.jsonl").read_text().splitlines()]
    return {r["map"]: r for r in rows}, len(rows)


def cli_row(cli, tmp, path):
    """What the CLI says of one map: exit code, its report, the mesh's bytes."""
    name = os.path.basename(path)
    mesh, report = tmp / (name + ".cli.obj"), tmp / (name + ".cli.json")
    rc = subprocess.run([str(cli), "extract", path, "-o", str(mesh), "--report", str(report), "-q", "--threads", "1"],
                        capture_output=True).returncode
    rep = json.loads(report.read_text()) if report.exists() else None
    return rc, rep, mesh.read_bytes() if mesh.exists() else None


def test_batch_on_local_cluster_matches_cli(cli, shared_dir, tmp_path):
    listed = maps(shared_dir)
    assert listed
    bad = tmp_path / "broken.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1/1 2/1\n")  # a 2-corner face
    bad_map = tmp_path / "nonmanifold.obj"
    bad_map.write_bytes((ROOT / "corpus" / "fuzz_obj" / "malformed" / "nonmanifold.obj").read_bytes())
    manifest = tmp_path / "maps.txt"
    manifest.write_text("# maps of the test\n" + "\n".join(listed + [str(bad), str(bad_map), "missing.obj"]) + "\n")
    out = tmp_path / "out"

    done = run_batch(manifest, "-o", out, "--workers", "2")
    assert done.returncode == 0, done.stderr
    rows, n = read_summary(out)
    assert n == len(listed) + 3

    with ThreadPoolExecutor(2) as pool:
        cli_rows = list(pool.map(lambda p: cli_row(cli, tmp_path, p), listed))
    for path, (rc, rep, mesh) in zip(listed, cli_rows):
        row = rows[os.path.basename(path)]
        assert row["status"] == {0: "valid", 5: "invalid"}[rc], (path, row)
        assert row["signed_area"] == rep["input"]["signed_uv_area"]
        assert row["defects"] == len(rep["defects"])
        assert row["violations"] == len(rep["check"]["violations"])
        assert row["rung"] == rep["fallback"]["rung"]
        assert row["faces"] == rep["check"]["faces"]  # quads: the faces with 4 corners
        if rc == 0:
            assert row["quads"] == row["faces"]
            assert (out / row["output"]).read_bytes() == mesh, path
        else:
            assert row["output"] is None
    assert rows["broken.obj"]["status"] == "error" and "line 6" in rows["broken.obj"]["error"]
    assert rows["nonmanifold.obj"]["status"] == "rejected" and "NonManifold" in rows["nonmanifold.obj"]["error"]
    assert rows["missing.obj"]["status"] == "error"

    # Resumed: finished maps are skipped; a map whose row is gone, or whose output is gone, runs again.
    lines = (out / "summary.jsonl").read_text().splitlines()
    first = json.loads(lines[0])
    (out / "summary.jsonl").write_text("\n".join(lines[1:]) + "\n")
    second = next(json.loads(line) for line in lines if json.loads(line)["status"] == "valid"
                  and json.loads(line)["map"] != first["map"])
    os.remove(out / second["output"])
    again = run_batch(manifest, "-o", out, "--workers", "1")
    assert again.returncode == 0, again.stderr
    # The two missing maps and the two error rows (bad file, missing file) run again.
    assert "%d done before, 4 to run" % (len(listed) - 1) in again.stderr, again.stderr
    rows2, n2 = read_summary(out)
    assert n2 == n
    for name, row in rows.items():
        for key in ("status", "quads", "signed_area", "defects", "output"):
            assert rows2[name][key] == row[key], (name, key)
    assert (out / second["output"]).exists()


def test_batch_on_a_running_scheduler(tmp_path):
    """--scheduler: a cluster started elsewhere (here a LocalCluster of this process) and a folder."""
    from dask.distributed import LocalCluster

    src = tmp_path / "in" / "sub"
    src.mkdir(parents=True)
    (src / "cube.obj").write_bytes((ROOT / "corpus" / "fuzz_obj" / "valid" / "cube_n3_k4.obj").read_bytes())
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        done = run_batch(tmp_path / "in", "-o", tmp_path / "out", "--scheduler", cluster.scheduler_address)
    assert done.returncode == 0, done.stderr
    rows, n = read_summary(tmp_path / "out")
    assert n == 1 and rows["sub/cube.obj"]["status"] == "valid" and rows["sub/cube.obj"]["quads"] == 54
    assert (tmp_path / "out" / "sub" / "cube.obj").exists()
