# The package as a Python user gets it (issue 34): `python3 -m build --no-isolation --wheel` on the
# checkout, the wheel installed into a fresh virtual environment (--system-site-packages for
# Debian's numpy, no network), an extraction and a check run there from outside the checkout,
# and the installed package's types checked as a user's type checker sees them.
#
# ctest (python_wheel) sets QEX_CMAKE_BUILD_DIR to its build tree, so that the wheel reuses the
# compiled module already built there (src/python/cmake_build.py) instead of compiling the core
# again: the test then takes seconds.
import os
import subprocess
import sys
import sysconfig
import zipfile

import pytest

from conftest import ROOT, SAMPLE

WHEEL_FILES = {"qex/" + f for f in ("__init__.py", "_arrays.py", "_dask.py", "extraction.py", "checking.py",
                                     "patch_layout.py", "files.py", "batch.py", "conformance.py", "py.typed",
                                     "_qex.pyi", "_qex" + sysconfig.get_config_var("EXT_SUFFIX"))}

USER_CODE = """
import os, sys
import numpy as np
import qex

here = os.path.dirname(os.path.abspath(qex.__file__))
assert here.startswith(sys.prefix), (here, sys.prefix)  # the venv's copy, not the checkout's
V, F, UV = qex.read_obj(sys.argv[1])
r = qex.extract(V, F, UV, threads=1)
assert r.valid and r.quads.shape == (54, 4), r
verdict = qex.check(V, F, UV, r.positions, r.quads)
assert verdict["valid"], verdict["violations"]
assert qex.verify(V, F, UV, r)["valid"]
qex.write_obj("quads.obj", r)
assert open("quads.obj").read().count("\\nf ") == 54
print("installed qex:", len(r.quads), "quads, check:", verdict["valid"])
"""

TYPED_USER_CODE = """
from typing import Any, Dict

import numpy as np
import numpy.typing as npt
import qex

V, F, UV = qex.read_obj("map.obj")
r: qex.Result = qex.extract(V, F, UV, snap_boundary=True, max_qvertices=1000)
quads: npt.NDArray[np.int32] = r.quads
verdict: Dict[str, Any] = qex.check(V, F, UV, r.positions, quads, uv_tolerance=1e-3)
qex.write_obj("out.obj", r)
"""


def run(command, **kwargs):
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=600, **kwargs)
    assert done.returncode == 0, "%s\n%s\n%s" % (" ".join(map(str, command)), done.stdout, done.stderr)
    return done


@pytest.fixture(scope="module")
def user_env():
    """The environment of a user's shell: no PYTHONPATH to the build tree, no package index."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "MYPYPATH")}
    env.update(PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1", PYTHONNOUSERSITE="1")
    return env


@pytest.fixture(scope="module")
def wheel(tmp_path_factory, user_env):
    if not os.environ.get("QEX_CMAKE_BUILD_DIR"):
        pytest.skip("QEX_CMAKE_BUILD_DIR does not name the build tree (ctest sets it)")
    dist = tmp_path_factory.mktemp("dist")
    run([sys.executable, "-m", "build", "--no-isolation", "--wheel", "--outdir", dist, ROOT], env=user_env)
    wheels = sorted(dist.glob("*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


@pytest.fixture(scope="module")
def mypy_cache(venv, tmp_path_factory, user_env):
    """A cache shared by the mypy runs (numpy's stubs are read once); skips without mypy."""
    if subprocess.run([venv, "-c", "import mypy"], env=user_env).returncode != 0:
        pytest.skip("mypy is not installed (python3-mypy)")
    return tmp_path_factory.mktemp("mypy_cache")


@pytest.fixture(scope="module")
def venv(tmp_path_factory, wheel, user_env):
    where = tmp_path_factory.mktemp("venv") / "venv"
    run([sys.executable, "-m", "venv", "--system-site-packages", where], env=user_env)
    python = where / "bin" / "python"
    run([python, "-m", "pip", "install", "--no-index", "--no-build-isolation", wheel], env=user_env)
    return python


def test_readme_gives_the_commands_tested_here():
    text = (ROOT / "README.md").read_text()
    block = text[text.index("<!-- python-install -->"):].split("```")[1]
    assert "/usr/bin/python3 -m venv --system-site-packages .venv" in block, block
    assert ".venv/bin/pip install --no-build-isolation ." in block, block
    assert "/usr/bin/python3 -m build --no-isolation --wheel" in block, block


def test_wheel_holds_the_package_for_this_interpreter(wheel):
    tag = "cp%d%d" % sys.version_info[:2]
    assert wheel.name.startswith("qex-") and ("-%s-%s-linux_" % (tag, tag)) in wheel.name, wheel.name
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        info = [n for n in names if not n.startswith("qex/")]
        assert {n for n in names if n.startswith("qex/")} == WHEEL_FILES
        assert all(n.startswith("qex-") and ".dist-info/" in n for n in info), info
        meta = z.read(next(n for n in info if n.endswith("/WHEEL"))).decode()
        assert "Root-Is-Purelib: false" in meta, meta


def test_installed_package_extracts_and_checks_outside_the_checkout(venv, tmp_path, user_env):
    done = run([venv, "-c", USER_CODE, SAMPLE], cwd=tmp_path, env=user_env)
    assert "installed qex: 54 quads, check: True" in done.stdout, done.stdout
    # The batch module is there too (its help needs no Dask).
    assert "--scheduler" in run([venv, "-m", "qex.batch", "--help"], cwd=tmp_path, env=user_env).stdout


def test_installed_package_is_typed(venv, mypy_cache, tmp_path, user_env):
    """A user's code type-checks against the installed package (py.typed, the inline types and
    qex/_qex.pyi), with Debian's mypy (python3-mypy) seen through --system-site-packages."""
    (tmp_path / "user.py").write_text(TYPED_USER_CODE)
    cache = mypy_cache
    run([venv, "-m", "mypy", "--strict", "--cache-dir", cache, "user.py"], cwd=tmp_path, env=user_env)
    (tmp_path / "wrong.py").write_text("import qex\nqex.extract([], [], [], snap_boundary='yes')\n")
    done = subprocess.run([str(venv), "-m", "mypy", "--strict", "--cache-dir", str(cache), "wrong.py"], cwd=tmp_path,
                          env=user_env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 1 and "snap_boundary" in done.stdout, done.stdout + done.stderr


def test_installed_package_passes_mypy_strict_and_stubtest(venv, mypy_cache, tmp_path, user_env):
    """The package's own code type-checks strictly against the compiled module's stub, and the stub
    matches the compiled module (mypy's stubtest; property_tests/python/stubtest_allowlist.txt)."""
    cache = mypy_cache
    run([venv, "-m", "mypy", "--strict", "--cache-dir", cache, "-p", "qex"], cwd=tmp_path, env=user_env)
    allowlist = ROOT / "property_tests" / "python" / "stubtest_allowlist.txt"
    run([venv, "-m", "mypy.stubtest", "qex._qex", "--allowlist", allowlist], cwd=tmp_path, env=user_env)
