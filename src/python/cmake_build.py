"""The setuptools commands that build the package qex with the project's CMake (pyproject.toml).

``pip install .`` and ``python3 -m build --wheel`` run setuptools in the checkout (the folder of
pyproject.toml), with these commands in place of setuptools' own:

``build_ext``
    Builds the compiled module ``qex._qex`` (the CMake target ``qex_python``) for the interpreter
    that runs the build, and copies it into the wheel. By default it configures a CMake build tree
    of its own, ``build/python-wheel/cmake``: Release, the module and the libraries it links, no
    CLI, C API, tests, fuzzers or install rules; a second build configures it again for the
    interpreter running it (a fraction of a second) and recompiles only what changed.
    ``QEX_CMAKE_BUILD_DIR=DIR`` names instead a build tree configured from this checkout with the
    Python module on (the README's ``build``, for example): then only
    ``cmake --build DIR --target qex_python`` runs, nothing when the module is up to date.
    ``CMAKE_ARGS`` adds options to the configuration (``-DCMAKE_CXX_COMPILER_LAUNCHER=ccache``);
    ``CMAKE_GENERATOR`` and ``CMAKE_BUILD_PARALLEL_LEVEL`` are CMake's own variables.
``bdist_wheel``
    Tags the wheel for this interpreter and platform (``cp311-cp311-linux_x86_64``): it holds a
    compiled module, so it is not a pure-Python wheel.
``build``, ``egg_info``
    Keep setuptools' own files under ``build/python-wheel`` (``DIR/python-wheel`` with
    ``QEX_CMAKE_BUILD_DIR``), out of the source folders; ``build`` empties the package's folder
    there first, so that no file since removed from src/python/qex/ reaches the wheel.
``sdist``
    Adds the C++ sources (CMakeLists.txt, include/, src/) that the compiled module is built from.

This file is not part of the package: pyproject.toml names its classes, which setuptools finds
in src/python/ (the package-dir).
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension
from setuptools.command.build import build as _build
from setuptools.command.build_ext import build_ext as _build_ext
from setuptools.command.egg_info import egg_info as _egg_info
from setuptools.command.sdist import sdist as _sdist
from setuptools.errors import SetupError
try:  # setuptools >= 70.1 has its own; Debian 12's setuptools 66 takes wheel's
    from setuptools.command.bdist_wheel import bdist_wheel as _bdist_wheel
except ImportError:
    from wheel.bdist_wheel import bdist_wheel as _bdist_wheel

# The checkout: this file is src/python/cmake_build.py.
SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODULE = "qex._qex"
TARGET = "qex_python"
# The configuration of the wheel's own build tree: the module and what it links, nothing else.
CMAKE_OPTIONS = [
    "-DCMAKE_BUILD_TYPE=Release",
    "-DQEX_BUILD_PYTHON=ON",
    "-DQEX_BUILD_CLI=OFF",
    "-DQEX_BUILD_C_API=OFF",
    "-DQEX_BUILD_TESTS=OFF",
    "-DQEX_BUILD_FUZZERS=OFF",
    "-DQEX_BUILD_BENCH=OFF",
    "-DQEX_INSTALL=OFF",
]


def _given_build_dir():
    """The build tree QEX_CMAKE_BUILD_DIR names (absolute), or None."""
    given = os.environ.get("QEX_CMAKE_BUILD_DIR")
    return os.path.abspath(given) if given else None


def _build_base():
    """Where setuptools writes its files (the wheel's tree, the metadata, the CMake build tree)."""
    given = _given_build_dir()
    return os.path.join(given if given else os.path.join(SOURCE_DIR, "build"), "python-wheel")


def _declare_module(distribution):
    """Declares the compiled module, so that setuptools runs build_ext and tags the wheel for the
    platform (pyproject.toml cannot list extension modules in setuptools 66, Debian 12's)."""
    if not distribution.ext_modules:
        distribution.ext_modules = [Extension(MODULE, sources=[])]


def _cmake_project_version():
    with open(os.path.join(SOURCE_DIR, "CMakeLists.txt")) as f:
        m = re.search(r"project\(\s*qex\s+VERSION\s+([0-9.]+)", f.read())
    if not m:
        raise SetupError("CMakeLists.txt: no project(qex VERSION ...)")
    return m.group(1)


def _cache_value(build_dir, name):
    """A variable of DIR/CMakeCache.txt, or None."""
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
            for line in f:
                key, _, value = line.rstrip("\n").partition("=")
                if key.split(":")[0] == name:
                    return value
    except OSError:
        pass
    return None


def _run(command, what):
    print("qex: " + " ".join(shlex.quote(c) for c in command), flush=True)
    try:
        subprocess.run(command, check=True)
    except FileNotFoundError:
        raise SetupError("qex: %s needs cmake (install-deps.sh installs it)" % what) from None
    except subprocess.CalledProcessError as e:
        raise SetupError("qex: %s failed (exit code %d); the output above says why. The compiled module "
                         "needs python3-dev, pybind11-dev and the libraries install-deps.sh installs"
                         % (what, e.returncode)) from None


class BuildExt(_build_ext):
    """Builds the compiled module qex._qex with the project's CMake (the module docstring says how)."""

    def run(self):
        version = _cmake_project_version()
        if version != self.distribution.get_version():
            raise SetupError("qex: pyproject.toml says version %s, CMakeLists.txt %s: make them agree"
                             % (self.distribution.get_version(), version))
        for ext in self.extensions:
            self.build_extension(ext)

    def build_extension(self, ext):
        given = _given_build_dir()
        build_dir = given or os.path.join(_build_base(), "cmake")
        if given:
            home = _cache_value(build_dir, "CMAKE_HOME_DIRECTORY")
            if home is None or os.path.realpath(home) != os.path.realpath(SOURCE_DIR):
                raise SetupError("qex: QEX_CMAKE_BUILD_DIR=%s is not a CMake build tree of %s"
                                 % (build_dir, SOURCE_DIR))
        else:
            # Configured at every build (a fraction of a second once the tree exists): the
            # interpreter and CMAKE_ARGS may have changed since the last one.
            command = ["cmake", "-S", SOURCE_DIR, "-B", build_dir] + CMAKE_OPTIONS
            command.append("-DPython_EXECUTABLE=" + sys.executable)
            fresh = _cache_value(build_dir, "CMAKE_HOME_DIRECTORY") is None
            if fresh and not os.environ.get("CMAKE_GENERATOR") and shutil.which("ninja"):
                command += ["-G", "Ninja"]
            command += shlex.split(os.environ.get("CMAKE_ARGS", ""))
            _run(command, "configuring the CMake build tree " + build_dir)
        what = "building the module (CMake target %s)" % TARGET
        if given:
            what += " in QEX_CMAKE_BUILD_DIR (configured with QEX_BUILD_PYTHON on, without sanitizers?)"
        _run(["cmake", "--build", build_dir, "--target", TARGET], what)
        # CMake names the module for the interpreter it found, setuptools for the one running.
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        folder = os.path.join(build_dir, "python", "qex")
        built = os.path.join(folder, "_qex" + suffix)
        if not os.path.isfile(built):
            found = sorted(f for f in os.listdir(folder) if f.startswith("_qex.")) if os.path.isdir(folder) else []
            raise SetupError("qex: %s holds %s, not the module for this interpreter (%s, %s): configure it with "
                             "-DPython_EXECUTABLE=%s" % (folder, ", ".join(found) or "no module", sys.executable, suffix,
                                                         sys.executable))
        destination = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(destination), exist_ok=True)
        self.copy_file(built, destination)


class BdistWheel(_bdist_wheel):
    """bdist_wheel for a wheel holding a compiled module: tagged for this interpreter and platform."""

    def finalize_options(self):
        _declare_module(self.distribution)
        super().finalize_options()


class Build(_build):
    """build, with its files under build/python-wheel (or QEX_CMAKE_BUILD_DIR/python-wheel), the
    package's folder there emptied first: a file since removed from src/python/qex/ stays out."""

    def initialize_options(self):
        super().initialize_options()
        self.build_base = _build_base()

    def run(self):
        shutil.rmtree(os.path.join(self.build_lib, "qex"), ignore_errors=True)
        super().run()


class EggInfo(_egg_info):
    """egg_info, writing qex.egg-info under the build folder rather than into src/python/."""

    def initialize_options(self):
        super().initialize_options()
        _declare_module(self.distribution)

    def finalize_options(self):
        if self.egg_base is None:
            self.egg_base = _build_base()
            os.makedirs(self.egg_base, exist_ok=True)
        super().finalize_options()


class Sdist(_sdist):
    """sdist, with the C++ sources and the CMake files the compiled module is built from (setuptools'
    sdist takes its file list from egg_info, which knows only the package: they join it here)."""

    def make_distribution(self):
        self.filelist.append("CMakeLists.txt")
        for top in ("include", "src"):
            for root, dirs, files in os.walk(os.path.join(SOURCE_DIR, top)):
                dirs[:] = sorted(d for d in dirs if d != "__pycache__")
                for f in sorted(files):
                    self.filelist.append(os.path.relpath(os.path.join(root, f), SOURCE_DIR))
        self.filelist.sort()
        self.filelist.remove_duplicates()
        super().make_distribution()
