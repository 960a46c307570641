#!/usr/bin/env python3
"""`qex draw` end to end: the map picture and the mesh picture as SVG and, where rsvg-convert is
installed, as PNG of the right size and not blank; defects circled where the checker finds them
(a mesh with one vertex moved off its grid point) and none on a valid mesh; bad input refused.

A large map (more than 30,000 triangles, optional: skipped where absent) is drawn in outline:
its flipped and degenerate triangles only, and its boundary and seam edges.

usage: cli_draw_test.py QEX MAP WORKDIR SINGULARITIES [LARGE_MAP]
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

qex, map_path, work, singularities = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
large = sys.argv[5] if len(sys.argv) > 5 else None
os.makedirs(work, exist_ok=True)
have_rsvg = shutil.which("rsvg-convert") is not None


def run(*args, expect=0):
    r = subprocess.run([qex, *args], capture_output=True, text=True)
    assert r.returncode == expect, f"qex {' '.join(args)}: exit code {r.returncode}, expected {expect}\n{r.stderr}"
    return r


def png_pixels(path):
    """Width, height and the set of distinct RGB(A) pixels of an 8-bit RGB or RGBA PNG."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, color = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and color in (2, 6), f"unexpected PNG format {depth}/{color}"
            bpp = 3 if color == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):  # undo the PNG row filters
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    pixels = [row[i:i + bpp] for row in rows for i in range(0, stride, bpp)]
    return width, height, pixels


def check_png(svg, min_width, min_height, min_drawn=0.05):
    png = svg[:-4] + ".png"
    if not have_rsvg:
        print(f"rsvg-convert absent: {png} not checked")
        return
    w, h, pixels = png_pixels(png)
    assert w >= min_width and h >= min_height, f"{png}: {w}x{h}, expected at least {min_width}x{min_height}"
    white = b"\xff\xff\xff"
    drawn = sum(1 for p in pixels if p[:3] != white)
    colors = len(set(pixels))
    assert drawn > min_drawn * len(pixels) and colors > 8, f"{png} is nearly blank ({drawn} drawn pixels, {colors} colors)"
    print(f"{png}: {w}x{h}, {drawn} of {len(pixels)} pixels drawn, {colors} colors")


png = ["--png"] if have_rsvg else []
# The map: every triangle drawn, every singularity labelled with its valence.
svg = os.path.join(work, "map.svg")
run("draw", map_path, "-o", svg, *png)
text = open(svg).read()
triangles = sum(1 for line in open(map_path) if line.startswith("f "))
assert text.count("<polygon") == triangles, f"{text.count('<polygon')} polygons for {triangles} triangles"
labels = re.findall(r'font-weight="bold"[^>]*>(\d+)</text>', text)
assert len(labels) == singularities, f"{len(labels)} singularity labels, expected {singularities}"
check_png(svg, 500, 300)

# --around: the chart around one triangle, fewer triangles than the map.
svg = os.path.join(work, "around.svg")
run("draw", map_path, "--around", "5", "--radius", "1", "-o", svg)
text = open(svg).read()
assert "around triangle 5" in text and 0 < text.count("<polygon") < triangles, "--around drew the whole map"
run("draw", map_path, "--around", str(triangles), "-o", svg, expect=1)

# --png without rsvg-convert on the PATH: a clean error, the SVG written, no PNG.
svg = os.path.join(work, "no_rsvg.svg")
r = subprocess.run([os.path.abspath(qex), "draw", map_path, "-o", svg, "--png"], capture_output=True, text=True,
                   env={"PATH": "/nonexistent"})
assert r.returncode == 2 and "librsvg2-bin" in r.stderr, f"exit code {r.returncode}: {r.stderr}"
assert os.path.exists(svg) and not os.path.exists(svg[:-4] + ".png"), "the SVG or a PNG without rsvg-convert"

# The valid mesh: three views, no circle; then one vertex moved: circled in each of the three views.
mesh = os.path.join(work, "mesh.obj")
run("extract", map_path, "-o", mesh, "--report", os.path.join(work, "report.json"), "-q")
svg = os.path.join(work, "mesh.svg")
run("draw", map_path, "--quads", mesh, "--report", os.path.join(work, "report.json"), "-o", svg, *png)
text = open(svg).read()
assert "VALID" in text and "INVALID" not in text and text.count('stroke="#e00000"') == 0, "a valid mesh has marks"
assert text.count("<polygon") > 0
check_png(svg, 1500, 500)
lines = open(mesh).read().split("\n")
first_v = next(i for i, l in enumerate(lines) if l.startswith("v "))
x, y, z = map(float, lines[first_v].split()[1:4])
lines[first_v] = f"v {x + 0.05} {y + 0.05} {z}"
moved = os.path.join(work, "moved.obj")
open(moved, "w").write("\n".join(lines))
svg = os.path.join(work, "moved.svg")
run("draw", map_path, "--quads", moved, "-o", svg, *png)
text = open(svg).read()
circles = text.count('stroke="#e00000"')
assert "INVALID" in text and circles >= 3 and circles % 3 == 0, f"{circles} circles for the moved vertex"
assert re.search(r"1: check (NotOnGridPoint|OffSurface)", text), "the moved vertex's violation is not listed"
check_png(svg, 1500, 500)

# Bad input: an exit code, a message and no picture.
bad = os.path.join(work, "bad.svg")
for args, code in [(["/nonexistent.obj"], 2), ([map_path, "--quads", "/nonexistent.obj"], 2),
                   ([map_path, "--quads", mesh, "--report", map_path], 3)]:
    r = run("draw", *args, "-o", bad, expect=code)
    assert r.stderr and not os.path.exists(bad) and not os.path.exists(bad + ".tmp"), f"draw {args}: {r.stderr}"
# A large map: in outline (flipped and degenerate triangles only, boundary and seam lines).
if large and os.path.exists(large):
    info = json.loads(run("info", large, "--json").stdout)
    assert info["triangles"] > 30000, f"{large} is not large"
    svg = os.path.join(work, "large.svg")
    run("draw", large, "-o", svg, *png)
    text = open(svg).read()
    folded = info["flipped_triangles"] + info["degenerate_triangles"]
    assert text.count("<polygon") == folded, f"{text.count('<polygon')} polygons, {folded} folded triangles"
    assert text.count("<line") > 100 and "outline" in text, "no outline drawn"
    check_png(svg, 800, 300, min_drawn=0.02)  # an outline covers little
elif large:
    print(f"skipped the large map: {large} is absent")
print("qex draw: map, valid mesh and moved vertex drawn as expected")
