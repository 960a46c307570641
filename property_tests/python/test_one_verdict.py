# One verdict everywhere (issue 31): `qex check`, `qex draw --quads`, the C API's qex_check and
# Python's qex.check judge the same mesh through one code path (qex::check_mesh) with the same
# defaults, so they must agree: on qex's own outputs of the sample map and the paper's maps, and on
# mutants of them (an edge rotated between two quads, a quad dropped).
import collections
import ctypes
import json
import re
import subprocess

import numpy as np
import pytest

from conftest import SAMPLE


def read_quads(path):
    V, F = [], []
    for line in open(path):
        if line.startswith("v "):
            V.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            F.append([int(c.split("/")[0]) - 1 for c in line.split()[1:]])
    return np.array(V, float).reshape(-1, 3), np.array(F, np.int32).reshape(-1, 4)


def write_quads(path, V, F):
    with open(path, "w") as f:
        f.writelines("v %.17g %.17g %.17g\n" % tuple(p) for p in V)
        f.writelines("f %d %d %d %d\n" % tuple(int(i) + 1 for i in q) for q in F)


def rotated_edge(F):
    """(a,b,c,d) + (b,a,e,f) -> (c,d,a,e) + (e,f,b,c): the first interior edge of the mesh."""
    sides = {}
    for f, q in enumerate(F):
        for i in range(4):
            sides[(int(q[i]), int(q[(i + 1) % 4]))] = (f, i)
    for f, q in enumerate(F):
        for i in range(4):
            a, b = int(q[i]), int(q[(i + 1) % 4])
            if (b, a) not in sides:
                continue
            g, j = sides[(b, a)]
            r = [int(x) for x in np.roll(q, -i)]  # a b c d
            s = [int(x) for x in np.roll(F[g], -j)]  # b a e f
            c, d, e, ff = r[2], r[3], s[2], s[3]
            if len({a, b, c, d, e, ff}) < 6:
                continue
            G = F.copy()
            G[f] = [c, d, a, e]
            G[g] = [e, ff, b, c]
            return G
    return None


def kinds(verdict):
    return sorted(collections.Counter(v["kind"] for v in verdict["violations"]).items())


class CApi:
    def __init__(self, path):
        lib = ctypes.CDLL(str(path))
        P = ctypes.POINTER
        lib.qex_check.restype = ctypes.c_void_p
        lib.qex_check.argtypes = [P(ctypes.c_double), ctypes.c_int64, P(ctypes.c_int32), ctypes.c_int64,
                                  P(ctypes.c_double), P(ctypes.c_double), ctypes.c_int64, P(ctypes.c_int32),
                                  ctypes.c_int64, ctypes.c_int]
        lib.qex_check_certificate.restype = ctypes.c_void_p
        lib.qex_check_certificate.argtypes = lib.qex_check.argtypes[:-1] + [ctypes.c_char_p]
        for name in ("qex_verdict_ok", "qex_verdict_valid"):
            getattr(lib, name).argtypes = [ctypes.c_void_p]
        lib.qex_verdict_json.restype = ctypes.c_char_p
        lib.qex_verdict_json.argtypes = [ctypes.c_void_p]
        lib.qex_verdict_free.argtypes = [ctypes.c_void_p]
        self.lib = lib

    def check(self, V, F, UV, QV, QF, grid_scale, certificate=None):
        arrays = [np.ascontiguousarray(a, dtype=t) for a, t in
                  ((V, np.float64), (F, np.int32), (UV, np.float64), (QV, np.float64), (QF, np.int32))]
        ptr = [a.ctypes.data_as(ctypes.POINTER(np.ctypeslib.as_ctypes_type(a.dtype))) for a in arrays]
        args = (ptr[0], len(V), ptr[1], len(F), ptr[2], ptr[3], len(QV), ptr[4], len(QF))
        h = (self.lib.qex_check(*args, grid_scale) if certificate is None else
             self.lib.qex_check_certificate(*args, str(certificate).encode()))
        try:
            assert self.lib.qex_verdict_ok(h) == 1
            verdict = json.loads(self.lib.qex_verdict_json(h).decode())
            assert bool(self.lib.qex_verdict_valid(h)) == verdict["valid"]
            return verdict
        finally:
            self.lib.qex_verdict_free(h)


def maps(shared_dir):
    found = [SAMPLE]
    if shared_dir is not None:
        found += sorted((shared_dir / "paper").glob("*.obj"))
    return found


@pytest.fixture(scope="module")
def shared_or_none(request):
    try:
        return request.getfixturevalue("shared_dir")
    except pytest.skip.Exception:
        return None


def test_every_front_end_gives_the_same_verdict(cli, c_library, tmp_path, shared_or_none):
    qex = pytest.importorskip("qex")
    capi = CApi(c_library)
    judged = collections.Counter()
    for map_path in maps(shared_or_none):
        name = map_path.stem
        out, report = tmp_path / (name + ".obj"), tmp_path / (name + ".json")
        done = subprocess.run([str(cli), "extract", str(map_path), "-o", str(out), "--report", str(report), "-q"],
                              capture_output=True, text=True)
        if done.returncode != 0:
            continue
        scale = json.load(open(report)).get("fallback", {}).get("grid_scale", 1)
        V, F, UV = qex.read_obj(str(map_path))
        QV, QF = read_quads(out)
        meshes = {"own": (out, QF)}
        for label, G in (("rotated", rotated_edge(QF)), ("dropped", np.delete(QF, len(QF) // 2, axis=0))):
            if G is not None:
                path = tmp_path / ("%s_%s.obj" % (name, label))
                write_quads(path, QV, G)
                meshes[label] = (path, G)
        for label, (path, G) in meshes.items():
            where = "%s (%s)" % (name, label)
            done = subprocess.run([str(cli), "check", "--param", str(map_path), str(path), "--grid-scale", str(scale),
                                   "--json"], capture_output=True, text=True)
            assert done.returncode in (0, 6), where + ": " + done.stderr
            by_cli = json.loads(done.stdout)
            assert (done.returncode == 0) == by_cli["valid"], where
            svg = tmp_path / "draw.svg"
            done = subprocess.run([str(cli), "draw", str(map_path), "--quads", str(path), "-o", str(svg),
                                   "--grid-scale", str(scale)], capture_output=True, text=True)
            assert done.returncode == 0, where + ": " + done.stderr
            drawn = re.search(r": (VALID|INVALID) \(qex check\)", svg.read_text())
            assert drawn, where + ": no verdict in the drawing's title"
            by_python = qex.check(V, F, UV, QV, G, grid_scale=scale)
            by_c = capi.check(V, F, UV, QV, G, scale)
            assert by_python["valid"] == by_cli["valid"] == by_c["valid"], where
            assert drawn.group(1) == ("VALID" if by_cli["valid"] else "INVALID"), where
            assert kinds(by_python) == kinds(by_cli) == kinds(by_c), where
            if label == "own":
                assert by_cli["valid"], where + ": " + str(kinds(by_cli))
            else:
                judged[by_cli["valid"]] += 1
    assert judged[False] >= 1, "no mutant was rejected"


def test_python_c_and_cli_agree_on_a_certificate(cli, c_library, tmp_path, shared_or_none):
    """qex.write_certificate writes the file `qex extract --certificate` writes; qex.check(certificate=),
    the C API's qex_check_certificate, `qex draw --quads --certificate` and `qex check --certificate`
    give the same verdict on the
    mesh, its rotated-edge mutant, and a tampered certificate, which all reject with
    CertificateMismatch."""
    qex = pytest.importorskip("qex")
    capi = CApi(c_library)
    if shared_or_none is None:
        pytest.skip("the shared maps are absent")
    map_path = shared_or_none / "paper" / "duck_miq_8_param.obj"
    V, F, UV = qex.read_obj(str(map_path))
    r = qex.extract(V, F, UV)
    assert r.valid
    mesh, by_python_cert, by_cli_cert = tmp_path / "duck.obj", tmp_path / "py.cert.obj", tmp_path / "cli.cert.obj"
    qex.write_obj(mesh, r)
    qex.write_certificate(by_python_cert, V, F, UV, r)
    done = subprocess.run([str(cli), "extract", str(map_path), "-o", str(tmp_path / "cli.obj"), "--certificate",
                           str(by_cli_cert), "-q"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert by_python_cert.read_bytes() == by_cli_cert.read_bytes()
    QV, QF = read_quads(mesh)
    tampered = tmp_path / "tampered.cert.obj"
    lines = by_python_cert.read_text().splitlines(keepends=True)
    first_vt = next(i for i, line in enumerate(lines) if line.startswith("vt "))
    u, v = (float(x) for x in lines[first_vt].split()[1:3])
    lines[first_vt] = "vt %.17g %.17g\n" % (u + 0.5, v)
    tampered.write_text("".join(lines))
    rotated = rotated_edge(QF)
    cases = [("own", QF, by_python_cert, True), ("tampered", QF, tampered, False)]
    if rotated is not None:
        cases.append(("rotated", rotated, by_python_cert, False))
    for label, G, cert, expect in cases:
        path = tmp_path / (label + ".obj")
        write_quads(path, QV, G)
        done = subprocess.run([str(cli), "check", "--param", str(map_path), str(path), "--certificate", str(cert),
                               "--json"], capture_output=True, text=True)
        assert done.returncode in (0, 6), label + ": " + done.stderr
        by_cli = json.loads(done.stdout)
        by_python = qex.check(V, F, UV, QV, G, certificate=cert)
        by_c = capi.check(V, F, UV, QV, G, 1, certificate=cert)
        svg = tmp_path / (label + ".svg")
        done = subprocess.run([str(cli), "draw", str(map_path), "--quads", str(path), "--certificate", str(cert),
                               "-o", str(svg)], capture_output=True, text=True)
        assert done.returncode == 0, label + ": " + done.stderr
        drawn = re.search(r": (VALID|INVALID) \(qex check\)", svg.read_text())
        assert drawn and drawn.group(1) == ("VALID" if expect else "INVALID"), label
        assert by_python["valid"] == by_cli["valid"] == by_c["valid"] == expect, label
        assert kinds(by_python) == kinds(by_cli) == kinds(by_c), label
        if label == "tampered":
            assert any(k == "CertificateMismatch" for k, _ in kinds(by_python)), label
    with pytest.raises(ValueError):
        qex.check(V, F, UV, QV, QF, certificate=by_python_cert, grid_scale=2)
