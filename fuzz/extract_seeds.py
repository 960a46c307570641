#!/usr/bin/env python3
"""Writes the fuzz_extract seeds of large fold-overs, folds at singularities and scaled maps
(corpus/fuzz_extract/folds/ and benign/), byte for byte as fuzz/fuzz_extract.cpp reads them.

    fuzz/extract_seeds.py [CORPUS_DIR]   (default: corpus/fuzz_extract beside this folder)

fuzz_input.h reads every integer as a big-endian u32 taken modulo the size of its range, and
unit() as u32 / 2147483647.5 - 1, a number in [-1, 1].
"""
import os
import struct
import sys

LAYOUTS = {"torus": 0, "cube": 1, "icosahedron": 2, "prism8": 3, "disk": 4, "annulus": 5}
MOTIONS = {"translate": 0, "twist": 1, "mirror": 2, "expand": 3}


def u32(v):
    return struct.pack(">I", v)


def unit(x):
    """The u32 that Bytes::unit() reads as x (to within 5e-10)."""
    assert -1.0 <= x <= 1.0
    return u32(round((x + 1.0) * 2147483647.5))


def case(layout, n, k, diagonals, seed, rng, first=(), snap=0, second=(), tail=b""):
    """A generated map, perturbations of the first kind, the snap byte, perturbations of the second
    kind (each already encoded), and the bytes that damage the mesh for the oracle without
    provenance (none: it reads zeros)."""
    out = u32(LAYOUTS[layout]) + u32(n - 1) + u32(k - 1) + u32(diagonals) + u32(seed) + u32(rng)
    out += u32(len(first)) + b"".join(first) + bytes([snap])
    out += u32(len(second)) + b"".join(second) + tail
    return out


# Perturbations of the first kind (perturb), op 0..12.
def rechart(log2_translation):
    return u32(0) + u32(log2_translation)


def shuffle():
    return u32(1)


def noise(log2_inverse):  # uniform noise of magnitude 2^-log2_inverse, 20..50
    return u32(4) + u32(log2_inverse - 20)


# Perturbations of the second kind (perturb_more), op 13..17 (the first of its two codes).
def scale(log2_factor):
    return u32(13) + u32(log2_factor - 1)


def push(corner, cells, dx, dy):  # one vertex through its charts, (dx, dy) * cells
    return u32(14) + u32(corner) + u32(cells - 1) + unit(dx) + unit(dy)


def motion(rings, kind, *params):
    out = u32(rings) + u32(MOTIONS[kind])
    if kind == "translate":
        cells, dx, dy = params
        return out + u32(cells - 1) + unit(dx) + unit(dy)
    return out + unit(params[0])  # twist: angle / 2 pi; mirror: angle / pi; expand: factor / 3


def patch(centre, rings, kind, *params):
    return u32(15) + u32(centre) + motion(rings, kind, *params)


def at_singularity(index, rings, kind, *params, neighbour_in_triangle=None):
    out = u32(16) + u32(index)
    out += bytes([0]) if neighbour_in_triangle is None else bytes([1]) + u32(neighbour_in_triangle)
    return out + motion(rings, kind, *params)


def squeeze(index, x):  # factor 1.5 + 4.5 * (x + 1) / 2
    return u32(17) + u32(index) + unit(x)


SEEDS = {
    # UVs x 2^k of fold-free maps: benign, the generated count times 4^k quads.
    "benign/cube_scaled_x4.bin": case("cube", 2, 3, 1, 7, 1, second=[scale(2)]),
    "benign/torus_noise_then_scaled_x8.bin": case("torus", 1, 3, 2, 5, 2, first=[noise(30)], second=[scale(3)]),
    "benign/annulus_scaled_x2_rechart_snapped.bin": case("annulus", 1, 2, 0, 3, 3, snap=1,
                                                         second=[scale(1), rechart(12), noise(24)]),
    # One vertex pushed three cells across its neighbours, through its charts.
    "folds/torus_push_3_cells.bin": case("torus", 2, 4, 1, 1, 4, second=[push(100, 3, 0.9, -0.5)]),
    "folds/cube_rechart_push_across_seam.bin": case("cube", 2, 4, 1, 9, 5,
                                                    second=[rechart(6), push(301, 4, -0.7, 0.8)]),
    # Patches of up to three rings moved over their neighbours: folds several cells wide.
    "folds/icosahedron_patch_translate.bin": case("icosahedron", 2, 4, 2, 11, 6,
                                                  second=[patch(200, 3, "translate", 4, 0.8, 0.6)]),
    "folds/torus_patch_mirror.bin": case("torus", 3, 5, 1, 2, 7, second=[patch(40, 3, "mirror", 0.25)]),
    "folds/annulus_patch_expand.bin": case("annulus", 2, 4, 2, 8, 8, second=[patch(30, 2, "expand", -0.7)]),
    "folds/disk_rechart_patch_twist_noise.bin": case("disk", 3, 5, 2, 4, 9, first=[rechart(16)],
                                                     second=[patch(50, 3, "twist", 0.6), noise(40)]),
    # Folds with a singularity inside (the patch around it) or beside it (around a neighbour).
    "folds/cube_twist_around_corner.bin": case("cube", 2, 4, 1, 3, 10,
                                               second=[at_singularity(0, 3, "twist", 0.45)]),
    "folds/cube_mirror_beside_corner.bin": case("cube", 2, 4, 0, 3, 11,
                                                second=[at_singularity(5, 2, "mirror", -0.3, neighbour_in_triangle=7)]),
    "folds/icosahedron_translate_over_valence5.bin": case("icosahedron", 1, 4, 1, 6, 12,
                                                         second=[at_singularity(3, 2, "translate", 2, -0.9, 0.4)]),
    "folds/prism8_squeeze_cap_centre.bin": case("prism8", 2, 4, 0, 1, 13, second=[squeeze(16, 0.6)]),
    # Scaled before and after folding.
    "folds/torus_scaled_x4_then_patch_translate.bin": case("torus", 2, 3, 1, 12, 14,
                                                           second=[scale(2), patch(60, 3, "translate", 4, -1.0, 0.7)]),
    "folds/cube_twist_at_corner_then_scaled_x2.bin": case("cube", 1, 4, 2, 13, 15,
                                                          second=[at_singularity(2, 3, "twist", -0.8), scale(1)]),
}


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "corpus", "fuzz_extract")
    for name, data in SEEDS.items():
        path = os.path.join(root, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)
        print(f"{path}: {len(data)} bytes")


if __name__ == "__main__":
    main()
