"""`qex conform` end to end: cli_conform_test.py QEX BROKEN_EXTRACTOR WORK_DIR.

1. `qex extract` through `qex conform` on the known and hostile cases of seed 1: every case is
   right but those named in KNOWN_WRONG (cases where qex extract exits 0 with a mesh qex check
   rejects; listed so that the test asserts everything else, and says when one is mended).
2. qex_broken_extractor, each way of breaking its output: every case gets the outcome expected,
   and summary.jsonl, the reproducer folders and the exit code 7 are as documented. A refined
   mesh (the map's UVs x 2, as qex extract refines) is judged at grid scale 2: wrong_count on
   a known case, valid on a user's map, and replay.sh checks it with --grid-scale 2.
3. --shrink gives a smaller failing case, and a reproducer replays with one command.
4. Every flag `qex conform --help` lists is in src/cli/README.md's section on it.
"""

import json
import os
import re
import shutil
import subprocess
import sys

QEX, BROKEN, WORK = sys.argv[1], sys.argv[2], sys.argv[3]

# Seed 1, 40 cases per set. qex extract exits 0 and qex check rejects its mesh: a triangle
# dropped from a closed map. (Noise on the boundary of a disk or an annulus, 1e-8 or 1e-9, was
# too, until boundaries within solver noise of an iso-line were snapped: known/disk/0022.)
KNOWN_WRONG = {}

BROKEN_MODES = {
    "none": "exact", "drop_face": "invalid_exit_0", "rotate_edge": "invalid_exit_0",
    "move_vertex": "invalid_exit_0", "one_triangle": "invalid_exit_0", "no_write": "no_output",
    "empty": "no_output", "crash": "crash", "hang": "timeout", "wrong_map": "invalid_exit_0",
    "refined": "wrong_count",  # valid at grid scale 2, but a known case's count is at scale 1
}


def conform(out, extractor, *args):
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.run([QEX, "conform", "--extractor", extractor, "-o", out, *args],
                       capture_output=True, text=True, timeout=240)
    rows = [json.loads(line) for line in open(os.path.join(out, "summary.jsonl"))]
    return p, rows


def check_qex_extract():
    out = os.path.join(WORK, "qex_extract")
    p, rows = conform(out, "'%s' extract {in} -o {out} -q --threads 1" % QEX,
                      "--cases", "known", "--cases", "hostile", "--count", "40", "--jobs", "2", "--timeout", "60")
    assert len(rows) == 80, len(rows)
    families = {r["family"] for r in rows}
    assert len(families) == 15, families  # 6 known layouts, 9 hostile kinds
    for r in rows:
        assert {"case", "family", "outcome", "right"} <= set(r), r
        if r["case"] in KNOWN_WRONG:
            if r["right"]:
                print("note: the known wrong case %s is right now: %s" % (r["case"], KNOWN_WRONG[r["case"]]))
            continue
        assert r["right"], (r["case"], r["outcome"], r["detail"], r["recipe"])
    wrong = [r for r in rows if not r["right"]]
    assert p.returncode == (7 if wrong else 0), (p.returncode, p.stderr)
    assert "%d not right" % len(wrong) in p.stdout, p.stdout
    assert "known/cube" in p.stdout and "hostile/truncated" in p.stdout, p.stdout  # the table
    for r in wrong:  # every case not right has its reproducer
        folder = r["folder"]
        for f in ("map.obj", "stderr.txt", "case.json", "replay.sh"):
            assert os.path.exists(os.path.join(folder, f)), (folder, f)
    print("qex extract: %d cases, %d right, known wrong: %s" % (len(rows), len(rows) - len(wrong),
                                                                 ", ".join(r["case"] for r in wrong)))


def check_broken_modes():
    for mode, expected in BROKEN_MODES.items():
        out = os.path.join(WORK, "broken_" + mode)
        p, rows = conform(out, "'%s' %s {in} {out}" % (BROKEN, mode), "--cases", "known", "--count", "3",
                          "--jobs", "2", "--timeout", "1")
        got = [r["outcome"] for r in rows]
        assert got == [expected] * 3, (mode, got, [r["detail"] for r in rows])
        assert p.returncode == (0 if expected == "exact" else 7), (mode, p.returncode)
        for r in rows:
            assert r["right"] == (expected == "exact"), (mode, r)
            if not r["right"]:
                assert os.path.isdir(r["folder"]), r
            if expected == "invalid_exit_0":
                assert os.path.exists(os.path.join(r["folder"], "verdict.json")), r
                assert os.path.exists(os.path.join(r["folder"], "verdict.svg")), r
            if expected == "crash":
                assert "SIGSEGV" in r["detail"], r
            # Judged at grid scale 1 but the refined mesh, valid at scale 2 alone.
            assert r["grid_scale"] == (2 if mode == "refined" else 1), (mode, r)
    print("qex_broken_extractor: all %d ways classified" % len(BROKEN_MODES))


def check_refined():
    """A refined mesh: judged at grid scale 2 on known cases and on the same maps as a user's."""
    known = os.path.join(WORK, "broken_refined")  # check_broken_modes' run
    rows = [json.loads(line) for line in open(os.path.join(known, "summary.jsonl"))]
    maps = os.path.join(WORK, "refined_maps")
    shutil.rmtree(maps, ignore_errors=True)
    os.makedirs(maps)
    for i, r in enumerate(rows):
        assert "VALID at grid scale 2" in r["detail"], r
        assert "known %d at grid scale 1" % r["expected_quads"] in r["detail"], r
        assert r["quads"] == 4 * r["expected_quads"], r
        script = open(os.path.join(r["folder"], "replay.sh")).read()
        assert "check --param 'map.obj' 'output.obj' --grid-scale 2\n" in script, script
        verdict = json.load(open(os.path.join(r["folder"], "verdict.json")))
        assert verdict["valid"], verdict  # the verdict at the scale chosen
        shutil.copy(os.path.join(r["folder"], "map.obj"), os.path.join(maps, "map%d.obj" % i))
    replay = subprocess.run(["sh", os.path.join(rows[0]["folder"], "replay.sh")], capture_output=True, text=True)
    assert replay.stdout.splitlines()[-1].startswith("VALID"), replay.stdout  # qex check --grid-scale 2 agrees
    p, user = conform(os.path.join(WORK, "refined_user"), "'%s' refined {in} {out}" % BROKEN, "--cases", maps,
                      "--jobs", "2")
    assert p.returncode == 0 and len(user) == len(rows), (p.returncode, user)
    for r in user:
        assert r["right"] and r["outcome"] == "valid" and r["grid_scale"] == 2, r
        assert r["quads"] >= 4 * r["area"] and "grid scale 2" in r["detail"], r
    print("refined: judged at grid scale 2 (%d known cases wrong_count, %d user maps valid)" % (len(rows), len(user)))


def check_shrink_and_replay():
    out = os.path.join(WORK, "shrink")
    p, rows = conform(out, "'%s' drop_face {in} {out}" % BROKEN, "--cases", "known", "--count", "3",
                      "--jobs", "2", "--shrink", "--seed", "5")
    shrunk = [r for r in rows if r["shrunk"]]
    assert shrunk, rows
    for r in shrunk:
        small = json.load(open(os.path.join(r["folder"] + "_shrunk", "case.json")))["recipe"]
        big = json.load(open(os.path.join(r["folder"], "case.json")))["recipe"]
        size = lambda c: (len(c["steps"]), c["n"], c["k"])
        assert all(a <= b for a, b in zip(size(small), size(big))) and size(small) != size(big), (small, big)
    replay = subprocess.run(["sh", os.path.join(rows[0]["folder"], "replay.sh")], capture_output=True, text=True)
    assert "INVALID" in replay.stdout, replay.stdout  # the extractor rerun, and qex check's verdict
    print("shrink: %d cases shrunk; replay.sh replays" % len(shrunk))


def check_flags_documented():
    help_text = subprocess.run([QEX, "conform", "--help"], capture_output=True, text=True).stdout
    options = [line for line in help_text.splitlines() if re.match(r"\s+(-\w,\s*)?--", line)]  # not the footer
    flags = {re.search(r"--[a-z][a-z-]+", line).group(0) for line in options} - {"--help"}
    readme = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src", "cli", "README.md")).read()
    section = readme[readme.index("## `qex conform`"):]
    section = section[:section.index("\n## ", 1)]
    missing = [f for f in sorted(flags) if "`%s" % f not in section]
    assert len(flags) >= 9 and not missing, (flags, missing)


os.makedirs(WORK, exist_ok=True)
check_flags_documented()
check_qex_extract()
check_broken_modes()
check_refined()
check_shrink_and_replay()
