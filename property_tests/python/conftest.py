# pytest fixtures of the Python package's tests (ctest runs them with PYTHONPATH=build/python).
# The environment names what the build made: QEX_CLI (the qex tool), QEX_C_LIBRARY (libqex_c.so),
# QEX_SHARED_DIR (the real maps beside the checkout; tests that need them skip when absent).
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "corpus" / "fuzz_obj" / "valid" / "cube_n3_k4.obj"


def _path(var, default=None):
    value = os.environ.get(var, default)
    return pathlib.Path(value) if value else None


@pytest.fixture(scope="session")
def cli():
    path = _path("QEX_CLI")
    if not path or not path.exists():
        pytest.skip("QEX_CLI does not name the qex tool")
    return path


@pytest.fixture(scope="session")
def shared_dir():
    path = _path("QEX_SHARED_DIR", str(ROOT.parent / "shared"))
    if not (path / "meshes").is_dir():
        pytest.skip("%s/meshes is absent (the shared real maps beside the checkout)" % path)
    return path / "meshes"


@pytest.fixture(scope="session")
def c_library():
    path = _path("QEX_C_LIBRARY")
    if not path or not path.exists():
        pytest.skip("QEX_C_LIBRARY does not name libqex_c")
    return path
