#!/usr/bin/env python3
"""`qex batch` against single runs: a list of maps (the corpus's, the shared ones given that
exist, and one malformed map) run with --jobs 2 must give, map for map, the exit code, quad
count, area and defect count of `qex extract` run alone, and the very same mesh file. A failed
map does not stop the rest; the exit code is 7 and the count of failures is printed. A second
run skips every valid output; -q prints nothing on stdout; no progress line off a terminal.

usage: cli_batch_test.py QEX WORKDIR MAP...
"""
import json
import os
import shutil
import subprocess
import sys

qex, work = sys.argv[1], sys.argv[2]
maps = [os.path.abspath(m) for m in sys.argv[3:] if os.path.exists(m)]
bad = [m for m in maps if "malformed" in m]
assert bad, "the list needs one malformed map"
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
listing = os.path.join(work, "maps.txt")
open(listing, "w").write("# maps for the batch test\n" + "\n".join(maps) + "\n")
out = os.path.join(work, "out")
summary = os.path.join(work, "summary.jsonl")

r = subprocess.run([qex, "batch", listing, "-o", out, "--jobs", "2", "--summary", summary], capture_output=True, text=True)
assert r.returncode == 7, f"exit code {r.returncode}, expected 7 (a map fails)\n{r.stderr}"
assert "\r" not in r.stderr, "a progress line off a terminal"
lines = [json.loads(l) for l in open(summary)]
assert [l["map"] for l in lines] == maps, "one summary line per map, in order"

failures = 0
for line in lines:
    m = line["map"]
    single = os.path.join(work, "single_" + os.path.basename(m))
    report = single + ".json"
    s = subprocess.run([qex, "extract", m, "-o", single, "--report", report, "-q"], capture_output=True)
    assert line["exit_code"] == s.returncode, f"{m}: batch exit code {line['exit_code']}, single {s.returncode}"
    assert line["status"] == ("ok" if s.returncode == 0 else "failed"), f"{m}: status {line['status']}"
    failures += s.returncode != 0
    if os.path.exists(report):  # extraction ran (exit code 0, or 5: the checker rejects the mesh)
        rep = json.load(open(report))
        assert line["quads"] == rep["check"]["faces"], f"{m}: {line['quads']} quads, single run {rep['check']['faces']}"
        assert line["area"] == rep["input"]["signed_uv_area"], f"{m}: area differs"
        assert line["defects"] == len(rep["defects"]), f"{m}: defects differ"
    else:
        assert line["quads"] is None, f"{m}: quads without a report"
    if s.returncode == 0:
        assert open(line["output"], "rb").read() == open(single, "rb").read(), f"{m}: the meshes differ"
    else:
        assert not os.path.exists(line["output"]), f"{m}: output of a failed map"
    print(f"{m}: exit code {line['exit_code']}, {line['quads']} quads, as the single run")

assert f"{failures} of {len(maps)} maps failed" in r.stderr, r.stderr

# Resumed: valid outputs skipped (not rewritten), the failed map run again; -q: nothing on stdout.
stamps = {l["output"]: os.stat(l["output"]).st_mtime_ns for l in lines if l["status"] == "ok"}
r = subprocess.run([qex, "batch", listing, "-o", out, "--jobs", "2", "--summary", summary, "-q"],
                   capture_output=True, text=True)
assert r.returncode == 7 and r.stdout == "", f"exit code {r.returncode}, stdout {r.stdout!r}"
again = [json.loads(l) for l in open(summary)]
for before, after in zip(lines, again):
    want = "skipped" if before["status"] == "ok" else "failed"
    assert after["status"] == want, f"{after['map']}: {after['status']} on the second run, expected {want}"
    if want == "skipped":
        assert after["quads"] == before["quads"], f"{after['map']}: the skipped map's summary changed"
        assert os.stat(after["output"]).st_mtime_ns == stamps[after["output"]], f"{after['output']} rewritten"
print(f"qex batch: {len(maps)} maps agree with single runs; the second run skipped {len(stamps)}")
