#!/usr/bin/env python3
"""`qex check --report R.json --svg R.svg` end to end: the verdict written as JSON (the very
document `--json` prints) and drawn on the map. On qex's own (valid) output of a map: exit code 0,
no violations, every cell of the map required by the coverage check, no violation marked. On a
copy with one quad dropped and the edge between two other quads rotated: exit code 6, the three
cells no face covers named (GridCellNotCovered, with their corner vertices and their chart
triangle), every violation with a place, and the SVG well-formed XML with a numbered mark on the
map for every violation that has a place there. A report that cannot be written: exit code 2.
The verdict carries the mesh's quality figures ("quality"), and the words one line of them: on the
copy, one quad fewer, more irregular vertices, and the dropped quad's hole farther from the map.

usage: cli_check_report_test.py QEX MAP WORKDIR
"""
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

qex, map_path, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
SVG = "{http://www.w3.org/2000/svg}"


def run(*args, expect=0):
    r = subprocess.run([qex, *args], capture_output=True, text=True)
    assert r.returncode == expect, f"qex {' '.join(args)}: exit code {r.returncode}, expected {expect}\n{r.stderr}"
    return r


def check(mesh, name, expect):
    """Runs qex check with --report and --svg; returns the report, the parsed SVG and the marks' labels."""
    report, svg = os.path.join(work, name + ".json"), os.path.join(work, name + ".svg")
    for f in (report, svg):
        if os.path.exists(f):
            os.remove(f)
    run("check", "--param", map_path, mesh, "--report", report, "--svg", svg, expect=expect)
    verdict = json.load(open(report))
    # The file holds what --json prints.
    printed = json.loads(run("check", "--param", map_path, mesh, "--json", expect=expect).stdout)
    assert verdict == printed, f"{name}: --report and --json differ"
    root = ET.parse(svg).getroot()  # well-formed XML, or this raises
    assert root.tag == SVG + "svg", f"{name}: the root element is {root.tag}"
    labels = []
    for g in root.iter(SVG + "g"):
        if g.get("class") == "violation-mark":
            labels += [n.strip() for t in g.iter(SVG + "text") for n in (t.text or "").split(",")]
    return verdict, root, labels


def faces_of(path):
    lines = open(path).read().split("\n")
    idx = [i for i, l in enumerate(lines) if l.startswith("f ")]
    faces = [[int(w.split("/")[0]) - 1 for w in lines[i].split()[1:]] for i in idx]
    return lines, idx, faces


# The valid mesh: nothing to mark.
mesh = os.path.join(work, "mesh.obj")
run("extract", map_path, "-o", mesh, "-q")
verdict, root, labels = check(mesh, "valid", 0)
assert verdict["valid"] and verdict["violations"] == [], verdict["violations"]
coverage = verdict["located"]["coverage"]
assert coverage["required_cells"] == verdict["faces"], f"{coverage} for {verdict['faces']} faces"
assert coverage["uncovered_cells"] == 0 and coverage["uncovered_grid_points"] == 0, coverage
assert labels == [], f"marks on a valid mesh: {labels}"
assert len(list(root.iter(SVG + "polygon"))) > 0, "no map drawn"
quality = verdict["quality"]
assert quality["computed"] and quality["quads"] == verdict["faces"] and quality["other_faces"] == 0, quality
jacobian = quality["scaled_jacobian"]
assert 0 < jacobian["min"] <= jacobian["p5"] <= jacobian["mean"] <= 1, jacobian
assert quality["vertices"] == verdict["vertices"] and 0 < quality["irregular_vertex_share"] < 1, quality
assert quality["distance"]["input_to_mesh"] < 0.05 and quality["distance"]["mesh_to_input"] < 0.05, quality
words = run("check", "--param", map_path, mesh).stdout
line = next((l for l in words.splitlines() if l.startswith("quality: scaled Jacobian min ")), None)
assert line and "irregular vertices" in line and "of the bounding-box diagonal" in line, words

# Drop one quad, and rotate the edge between two others (far from it): their cells have no face.
lines, idx, faces = faces_of(mesh)
dropped = len(faces) // 2
f = 0
while any(v in faces[dropped] for v in faces[f]):
    f += 1
g, k, m = next((g, k, m) for g in range(len(faces)) if g != f and not any(v in faces[dropped] for v in faces[g])
               for k in range(4) for m in range(4)
               if faces[g][m] == faces[f][(k + 1) % 4] and faces[g][(m + 1) % 4] == faces[f][k])
cells = [faces[dropped], faces[f], faces[g]]
a = faces[f][k:] + faces[f][:k]  # (a, b, x, y)
b = faces[g][m:] + faces[g][:m]  # (b, a, z, w)
hexagon = [a[0], b[2], b[3], a[1], a[2], a[3]]
faces[f] = hexagon[1:5]
faces[g] = [hexagon[4], hexagon[5], hexagon[0], hexagon[1]]
for n, i in enumerate(idx):
    lines[i] = "f " + " ".join(str(v + 1) for v in faces[n])
del lines[idx[dropped]]
broken = os.path.join(work, "broken.obj")
open(broken, "w").write("\n".join(lines))

verdict, root, labels = check(broken, "broken", 6)
violations = verdict["violations"]
assert not verdict["valid"] and violations
for x in violations:
    assert x["places"] and x["places"][0]["indices"], f"{x['kind']} has no place: {x['message']}"
named = []
for x in violations:
    if x["kind"] != "GridCellNotCovered":
        continue
    assert x["element_kind"] == "input_triangle" and x["element"] >= 0, x
    kinds = {p["kind"]: p["indices"] for p in x["places"]}
    assert kinds["grid_cell"][0] == x["element"] and len(kinds["grid_cell"]) == 3, x
    named.append(sorted(kinds["vertex"]))
assert sorted(named) == sorted(sorted(c) for c in cells), f"cells named {named}, expected {cells}"
assert verdict["located"]["coverage"]["uncovered_cells"] == 3
broken_quality = verdict["quality"]
assert broken_quality["quads"] == quality["quads"] - 1, broken_quality
assert broken_quality["irregular_vertices"] > quality["irregular_vertices"], broken_quality
assert broken_quality["distance"]["input_to_mesh"] > quality["distance"]["input_to_mesh"], broken_quality
# Every violation with a place on the map (a grid cell or point, or an input triangle) is marked
# there with its number.
on_map = {"grid_cell", "grid_point", "input_triangle"}
for i, x in enumerate(violations, start=1):
    if x["element_kind"] == "input_triangle" or any(p["kind"] in on_map for p in x["places"]):
        assert str(i) in labels, f"violation {i} ({x['kind']}) is not marked on the map: marks {labels}"
assert sum(1 for x in violations if x["kind"] == "GridCellNotCovered") <= len(set(labels))
text = "".join(t.text or "" for t in root.iter(SVG + "text"))
assert "GridCellNotCovered" in text and "INVALID" in text, "the listing or the verdict is missing"

# A report that cannot be written: exit code 2, a message.
r = run("check", "--param", map_path, mesh, "--report", os.path.join(work, "no", "such", "dir", "r.json"), expect=2)
assert "cannot write" in r.stderr, r.stderr
print(f"qex check --report/--svg: {len(violations)} violations, {len(set(labels))} marks on the map")
