"""A conformance run of a Python extractor on a Dask cluster: ``qex.conform(extractor, out_dir)``.

The cases are the library's (``qex conform``: known, hostile, a folder or list of maps; the same
seed gives the same cases on any machine). Each case is a task on a ``dask.distributed``
cluster (a LocalCluster by default, or the one ``scheduler=`` names); the task writes the case's
map, calls ``extractor(map_path, out_path)`` in the worker, and judges the output with the
library's judge (``qex::check_mesh``). Every case not right gets the reproducer folder the CLI
writes (``OUT_DIR/cases/<case>``), and ``OUT_DIR/summary.jsonl`` has the CLI's rows.

The extractor returns its exit status (``None`` is 0); an exception is a failure (status 1, its
traceback in the case's stderr.txt). A call past ``timeout`` seconds is a timeout (the call is
left running in its worker thread); a worker that dies in the call (a crash of compiled code)
makes the case a crash.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import threading
import time
import traceback
from typing import Any, Callable, Dict, List, Optional, Sequence

from . import _dask, _qex

__all__ = ["conform", "run_case"]

Row = Dict[str, Any]  # a row of summary.jsonl
Extractor = Callable[[str, str], Optional[int]]


def _replay_command(extractor: Extractor) -> str:
    """How replay.sh reruns an importable callable (module and name), else empty."""
    module, name = getattr(extractor, "__module__", None), getattr(extractor, "__qualname__", "")
    if not module or module == "__main__" or not name.isidentifier():
        return ""
    return ("python3 -c 'import sys, %s as m; sys.exit(m.%s(sys.argv[1], sys.argv[2]) or 0)' {in} {out}"
            % (module, name))


def _call(extractor: Extractor, map_path: str, out_path: str, stderr_path: str, timeout: float) -> Dict[str, Any]:
    """Calls the extractor on a thread, up to `timeout` seconds: its status, or a timeout."""
    result: Dict[str, Any] = {"exit_code": 1}

    def target() -> None:
        try:
            code = extractor(map_path, out_path)
            result["exit_code"] = 0 if code is None else int(code)
        except BaseException:  # the extractor's failure, kept for the reproducer
            with open(stderr_path, "a") as err:
                err.write(traceback.format_exc())

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(timeout)
    result["timed_out"] = thread.is_alive()
    return result


def run_case(case: str, extractor: Extractor, out_dir: str, timeout: float, replay: str, checker: str) -> Row:
    """Runs and judges one case (a Dask task); returns its summary row.

    Parameters
    ----------
    case : str
        The case as JSON (what ``_qex.conform_cases`` lists).
    extractor : callable
        ``extractor(map_path, out_path)``, returning the exit status (None: 0).
    out_dir : str
        The run's folder: the case works in ``work/`` there, its reproducer goes to ``cases/``.
    timeout : float
        Seconds before the call counts as a timeout.
    replay : str
        The command line replay.sh reruns the extractor with ({in}, {out}); may be empty.
    checker : str
        The qex program replay.sh judges with.

    Returns
    -------
    dict
        The case's row of ``summary.jsonl``.
    """
    c = json.loads(case)
    work = os.path.join(out_dir, "work", c["name"].replace("/", "_"))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    map_path = c["map_path"] if not c["generated"] else os.path.join(work, "map.obj")
    if c["generated"]:
        with open(map_path, "w") as f:
            f.write(_qex.conform_map_text(case))
    out_path, stderr_path = os.path.join(work, "output.obj"), os.path.join(work, "stderr.txt")
    open(stderr_path, "w").close()
    start = time.perf_counter()
    status = _call(extractor, map_path, out_path, stderr_path, timeout)
    seconds = time.perf_counter() - start
    row: Row = json.loads(_qex.conform_judge(case, map_path, out_path, stderr_path, status["exit_code"], 0,
                                             status["timed_out"], seconds, out_dir, replay, checker))
    if not status["timed_out"]:
        shutil.rmtree(work, ignore_errors=True)
    return row


def _crash_row(case: str, error: BaseException, out_dir: str) -> Row:
    """The row of a case whose worker died in the call: judged as ended by a signal."""
    c = json.loads(case)
    map_path = c["map_path"] or os.path.join(out_dir, "work", c["name"].replace("/", "_"), "map.obj")
    row: Row = json.loads(_qex.conform_judge(case, map_path, "", "", 0, 9, False, 0.0, out_dir, "", "qex"))
    row["detail"] = "the worker died in the call (%s: %s)" % (type(error).__name__, error)
    return row


def _run_on(client: Any, todo: List[str], extractor: Extractor, out_dir: str, timeout: float, replay: str,
            checker: str, progress: bool) -> Dict[int, Row]:
    """Runs a task per case on the client: the rows by the cases' index (they finish in any order)."""
    rows: Dict[int, Row] = {}
    futures = {client.submit(run_case, c, extractor, out_dir, timeout, replay, checker, pure=False): i
               for i, c in enumerate(todo)}
    for fut in _dask.distributed().as_completed(futures):
        i = futures[fut]
        try:
            rows[i] = fut.result()
        except Exception as e:  # the worker died in the call
            rows[i] = _crash_row(todo[i], e, out_dir)
        if progress:
            wrong = sum(not r["right"] for r in rows.values())
            sys.stderr.write("\r[%d/%d] cases, %d not right" % (len(rows), len(todo), wrong))
    return rows


def conform(
    extractor: Extractor,
    out_dir: str,
    cases: Sequence[str] = ("known", "hostile"),
    count: int = 100,
    seed: int = 1,
    timeout: float = 60.0,
    scheduler: Optional[str] = None,
    workers: Optional[int] = None,
    replay: Optional[str] = None,
    progress: bool = True,
) -> List[Row]:
    """Judge a Python extractor on known, hostile and your own maps, as ``qex conform`` does.

    Parameters
    ----------
    extractor : callable
        ``extractor(map_path, out_path) -> int or None``: reads the map (OBJ), writes the quad
        mesh (OBJ), returns its exit status (None: 0). It must pickle (Dask sends it to workers).
    out_dir : str
        The report's folder: ``summary.jsonl`` and ``cases/`` (a reproducer per case not right).
    cases : sequence of str, optional
        ``"known"``, ``"hostile"``, folders of maps or list files (default: known and hostile).
    count : int, optional
        Cases per generated set (default 100).
    seed : int, optional
        The seed of the generated cases (default 1): the same cases on any machine.
    timeout : float, optional
        Seconds per case (default 60).
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://HOST:PORT``). Default: a LocalCluster.
    workers : int, optional
        The LocalCluster's worker processes (default: one per core).
    replay : str, optional
        The command line replay.sh reruns the extractor with, with ``{in}`` and ``{out}``.
        Default: a ``python3 -c`` call of the extractor when it is importable by name.
    progress : bool, optional
        Show a progress bar and the table on stderr (default True).

    Returns
    -------
    list of dict
        The summary's rows, one per case in the cases' order, as ``summary.jsonl`` holds them.
    """
    out_dir = os.path.abspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    todo = _qex.conform_cases(list(cases), int(count), int(seed))
    replay = _replay_command(extractor) if replay is None else replay
    checker = shutil.which("qex") or "qex"
    with _dask.client(scheduler, workers) as client:
        rows = _run_on(client, todo, extractor, out_dir, timeout, replay, checker, progress)
    ordered = [rows[i] for i in range(len(todo))]
    with open(os.path.join(out_dir, "summary.jsonl"), "w") as out:
        for row in ordered:
            out.write(json.dumps(row) + "\n")
    shutil.rmtree(os.path.join(out_dir, "work"), ignore_errors=True)
    if progress:
        sys.stderr.write("\n" + _qex.conform_table([json.dumps(r) for r in ordered]))
    return ordered
