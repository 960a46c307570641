"""Extract a dataset of maps on a Dask cluster: ``python3 -m qex.batch IN_DIR|MANIFEST -o OUT_DIR``.

Every map (``*.obj`` under IN_DIR, or one path per line of a MANIFEST file, relative to it) is
extracted by a task on a ``dask.distributed`` cluster: a LocalCluster on this machine by default,
or the cluster whose scheduler ``--scheduler tcp://HOST:PORT`` names (its workers must be able to
``import qex`` and read the maps' paths). A ``X.vval`` beside ``X.obj`` gives the valences.

For each map, the valid mesh goes to ``OUT_DIR/<its path>`` (relative to IN_DIR or the manifest)
and one row to ``OUT_DIR/summary.jsonl``:

    {"map": ..., "status": "valid" | "invalid" | "rejected" | "error", "quads": ...,
     "faces": ..., "vertices": ..., "signed_area": ..., "defects": ..., "violations": ..., "rung": ...,
     "seconds": ..., "output": ..., "error": ...}

``valid``: the checker accepts the mesh (written); ``invalid``: it rejects it (not written, its
defects counted); ``rejected``: the map is bad input (``error`` says why, naming the element);
``error``: the map could not be read, or its task failed. One bad map never stops the batch.
A batch is resumable: rows are appended as maps finish, and a second run skips every map with a
row (but ``error``) whose output, if any, is in place; at the end the summary keeps one row per map.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple

from . import _dask

__all__ = ["run_one", "find_maps", "run_batch", "main"]


Row = Dict[str, Any]  # a row of summary.jsonl


def _row(status: str, error: Optional[str] = None) -> Row:
    return {"status": status, "quads": 0, "faces": 0, "vertices": 0, "signed_area": None, "defects": 0,
            "violations": 0, "rung": None, "seconds": 0.0, "output": None, "error": error}


def run_one(path: str, out_path: str, threads: int = 1) -> Row:
    """Extract one map and write its mesh (a Dask task).

    Parameters
    ----------
    path : str
        The map (OBJ); a ``.vval`` file beside it gives the valences.
    out_path : str
        Where the mesh goes when the checker accepts it (its folders are made).
    threads : int, optional
        Threads of the extraction (default 1: the batch runs one map per worker).

    Returns
    -------
    dict
        The map's row of the summary, without ``map`` and ``input``: ``status``, ``quads``,
        ``faces``, ``vertices``, ``signed_area``, ``defects``, ``violations``, ``rung``,
        ``seconds``, ``output`` and ``error``. It never raises: a failure is a row saying why.
    """
    row = _row("error")
    start = time.perf_counter()
    try:
        import qex

        V, F, UV = qex.read_obj(path, threads=threads)
        valences = None
        vval = os.path.splitext(path)[0] + ".vval"
        if os.path.exists(vval):
            valences = qex.read_vval(vval)  # the library's reader: a bad count or valence names its line
        try:
            r = qex.extract(V, F, UV, valences=valences, threads=threads)
        except ValueError as e:
            row.update(status="rejected", error=str(e))
            return row
        report = r.report
        row.update(status="valid" if r.valid else "invalid", quads=int(len(r.quads)),
                   faces=report["check"]["faces"], vertices=int(len(r.positions)),
                   signed_area=report["input"]["signed_uv_area"], defects=len(r.defects),
                   violations=len(report["check"]["violations"]), rung=report["fallback"]["rung"])
        if r.valid:
            os.makedirs(os.path.dirname(out_path) or ".", exist_ok=True)
            qex.write_obj(out_path, r)
            row["output"] = out_path
    except Exception as e:  # a file that cannot be read, or anything else: this map's row says so
        row.update(status="error", error="%s: %s" % (type(e).__name__, e))
    finally:
        row["seconds"] = round(time.perf_counter() - start, 6)
    return row


def find_maps(source: str) -> List[Tuple[str, str]]:
    """List the maps of a folder or a manifest.

    Parameters
    ----------
    source : str
        A folder, searched recursively for ``*.obj``, or a manifest: one path per line, relative
        to its folder (blank lines and ``#`` comments skipped).

    Returns
    -------
    list of (str, str)
        ``(name, path)`` per map, sorted for a folder, in the manifest's order otherwise; the
        name is the path relative to the folder (or the manifest's folder, else the file name).

    Raises
    ------
    SystemExit
        The manifest lists two maps under the same name.
    """
    source = os.path.abspath(source)
    if os.path.isdir(source):
        maps = []
        for root, dirs, files in os.walk(source):
            dirs.sort()
            for f in sorted(files):
                if f.endswith(".obj"):
                    path = os.path.join(root, f)
                    maps.append((os.path.relpath(path, source), path))
        return maps
    base = os.path.dirname(source)
    maps = []
    with open(source) as manifest:
        for line in manifest:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            path = os.path.normpath(os.path.join(base, line))
            name = os.path.relpath(path, base)
            if name.startswith(".."):
                name = os.path.basename(path)
            maps.append((name, path))
    names = [n for n, _ in maps]
    if len(set(names)) != len(names):
        raise SystemExit("qex.batch: %s lists two maps under the same name" % source)
    return maps


def _read_summary(path: str) -> Dict[str, Row]:
    rows = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                try:
                    row = json.loads(line)
                    rows[row["map"]] = row
                except (ValueError, KeyError, TypeError):
                    continue  # a row cut short when an earlier run was killed
    return rows


def _finished(row: Optional[Row], out_dir: str) -> bool:
    if row is None or row.get("status") == "error":
        return False
    return row.get("output") is None or os.path.exists(os.path.join(out_dir, row["output"]))


class _Progress:
    """A progress bar on stderr (a line per map when stderr is not a terminal)."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.done, self.failed, self.enabled = total, 0, 0, enabled
        self.tty = sys.stderr.isatty()
        self.start = time.perf_counter()

    def update(self, row: Row) -> None:
        self.done += 1
        self.failed += row["status"] != "valid"
        if not self.enabled:
            return
        if self.tty:
            width = 30
            filled = int(width * self.done / max(self.total, 1))
            sys.stderr.write("\r[%s%s] %d/%d maps, %d not valid, %.0f s" % (
                "#" * filled, "." * (width - filled), self.done, self.total, self.failed,
                time.perf_counter() - self.start))
            if self.done == self.total:
                sys.stderr.write("\n")
        else:
            sys.stderr.write("[%d/%d] %s: %s%s\n" % (self.done, self.total, row["map"], row["status"],
                                                      ", %d quads" % row["quads"] if row["quads"] else ""))
        sys.stderr.flush()


def run_batch(
    source: str,
    out_dir: str,
    scheduler: Optional[str] = None,
    workers: Optional[int] = None,
    threads: int = 1,
    memory_limit: str = "auto",
    progress: bool = True,
) -> List[Row]:
    """Extract every map of a folder or manifest on a Dask cluster, skipping the maps done before.

    Parameters
    ----------
    source : str
        A folder of OBJ maps or a manifest, as `find_maps` takes it.
    out_dir : str
        Where the valid meshes and ``summary.jsonl`` go (made if absent).
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://HOST:PORT``). Default: a LocalCluster.
    workers : int, optional
        The LocalCluster's worker processes (default: one per core).
    threads : int, optional
        Threads of each extraction (default 1).
    memory_limit : str, optional
        The LocalCluster's memory limit per worker (default ``"auto"``).
    progress : bool, optional
        Show a progress bar on stderr (default True).

    Returns
    -------
    list of dict
        The summary's rows, one per map in the maps' order (then rows of maps no longer listed),
        as ``summary.jsonl`` holds them.
    """
    maps = find_maps(source)
    os.makedirs(out_dir, exist_ok=True)
    summary = os.path.join(out_dir, "summary.jsonl")
    rows = _read_summary(summary)
    todo = [(n, p) for n, p in maps if not _finished(rows.get(n), out_dir)]
    if progress:
        sys.stderr.write("qex.batch: %d maps, %d done before, %d to run\n" % (len(maps), len(maps) - len(todo),
                                                                             len(todo)))
    if todo:
        with _dask.client(scheduler, workers, memory_limit=memory_limit) as client:
            _run_on(client, todo, out_dir, threads, rows, progress)
    return _rewrite_summary(summary, maps, rows)


def _run_on(client: Any, todo: List[Tuple[str, str]], out_dir: str, threads: int, rows: Dict[str, Row],
            progress: bool) -> None:
    """Runs a task per map on the client, appending each row to summary.jsonl as it comes (so that a
    killed batch resumes) and into `rows`."""
    out_root = os.path.abspath(out_dir)
    futures = {}
    for name, path in todo:
        fut = client.submit(run_one, path, os.path.join(out_root, name), threads, key="qex-" + name, pure=False)
        futures[fut] = (name, path)
    bar = _Progress(len(todo), progress)
    with open(os.path.join(out_dir, "summary.jsonl"), "a") as out:
        for fut in _dask.distributed().as_completed(futures):
            name, path = futures[fut]
            try:
                row = fut.result()
            except Exception as e:  # the task died with its worker, or was lost
                row = _row("error", error="%s: %s" % (type(e).__name__, e))
            if row.get("output"):
                row["output"] = os.path.relpath(row["output"], out_root)
            row = dict({"map": name, "input": path}, **row)
            rows[name] = row
            out.write(json.dumps(row) + "\n")
            out.flush()
            bar.update(row)


def _rewrite_summary(summary: str, maps: List[Tuple[str, str]], rows: Dict[str, Row]) -> List[Row]:
    """One row per map, in the maps' order (rows of maps no longer listed are kept at the end),
    written through a temporary file so that a killed rewrite leaves the appended summary whole."""
    ordered = [rows[n] for n, _ in maps if n in rows]
    listed = {n for n, _ in maps}
    ordered += [r for n, r in rows.items() if n not in listed]
    tmp = summary + ".tmp"
    with open(tmp, "w") as out:
        for row in ordered:
            out.write(json.dumps(row) + "\n")
    os.replace(tmp, summary)
    return ordered


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command line ``python3 -m qex.batch IN_DIR|MANIFEST -o OUT_DIR [options]``.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``); ``--help`` lists them.

    Returns
    -------
    int
        The exit code: 0 when the batch ran, whatever the maps' statuses (the summary has them).
    """
    ap = argparse.ArgumentParser(prog="python3 -m qex.batch",
                                 description="Extract the quad meshes of many maps on a Dask cluster.")
    ap.add_argument("source", help="a folder of OBJ maps (searched recursively) or a manifest (one path per line)")
    ap.add_argument("-o", "--output", required=True, help="output folder: the meshes and summary.jsonl")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://HOST:PORT); "
                                        "default: a LocalCluster on this machine")
    ap.add_argument("--workers", type=int, help="LocalCluster worker processes (default: one per core)")
    ap.add_argument("--threads", type=int, default=1, help="threads of each extraction (default 1)")
    ap.add_argument("--memory-limit", default="auto", help="LocalCluster memory limit per worker (default auto)")
    ap.add_argument("--no-progress", action="store_true", help="print nothing while it runs")
    args = ap.parse_args(argv)
    if not os.path.exists(args.source):
        ap.error("%s does not exist" % args.source)
    rows = run_batch(args.source, args.output, scheduler=args.scheduler, workers=args.workers,
                     threads=args.threads, memory_limit=args.memory_limit, progress=not args.no_progress)
    counts: Dict[str, int] = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    print("qex.batch: %d maps: %s; summary in %s" % (
        len(rows), ", ".join("%d %s" % (c, s) for s, c in sorted(counts.items())),
        os.path.join(args.output, "summary.jsonl")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
