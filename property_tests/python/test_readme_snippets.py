# The READMEs' snippets run as they are written: the ctypes one (src/capi/README.md) against
# libqex_c (no pybind11), the Python one (README.md) against the package.
import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT


def snippet(marker, readme="README.md"):
    text = (ROOT / readme).read_text()
    m = re.search(r"<!-- %s -->\s*```python\n(.*?)```" % re.escape(marker), text, re.S)
    assert m, "%s has no python block after <!-- %s -->" % (readme, marker)
    return m.group(1)


def run(code, **env):
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, **env))


def test_ctypes_snippet(c_library):
    done = run(snippet("ctypes-snippet", "src/capi/README.md"), QEX_C_LIBRARY=str(c_library))
    assert done.returncode == 0, done.stderr
    assert "4 quads, valid: True" in done.stdout, done.stdout


def test_python_snippet():
    pytest.importorskip("qex")
    done = run(snippet("python-snippet"))
    assert done.returncode == 0, done.stderr
    assert "54 quads" in done.stdout, done.stdout


def test_docstring_examples():
    """The examples in the package's docstrings (paths relative to the checkout). doctest finds a
    function's examples only in the module that defines it: each module of qex is tested."""
    qex = pytest.importorskip("qex")
    code = """import doctest, importlib, pkgutil, qex, sys
modules = [qex] + [importlib.import_module("qex." + m.name) for m in pkgutil.iter_modules(qex.__path__)
                   if m.name != "_qex"]
results = [doctest.testmod(m) for m in modules]
print(results)
failed, attempted = sum(r.failed for r in results), sum(r.attempted for r in results)
# The package's own example and extract's (qex.extraction) must both have run.
sys.exit(1 if failed or not 0 < results[0].attempted < attempted else 0)
"""
    done = run(code)
    assert done.returncode == 0, done.stdout + done.stderr
