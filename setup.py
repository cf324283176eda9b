"""pip install for the Python package varsym (docs/python.md), without network access:

    /usr/bin/python3 -m venv --system-site-packages ~/.venvs/varsym
    ~/.venvs/varsym/bin/pip install --no-build-isolation --no-index .

The extension module varsym._core is built by CMake (target varsym_python) in VARSYM_BUILD_DIR
(default build/pip), against the interpreter that runs pip (its base interpreter, in a venv);
setuptools installs it with the package's Python files from python/varsym.
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = Path(os.environ.get("VARSYM_BUILD_DIR", ROOT / "build" / "pip")).resolve()
        tool = "ON" if os.environ.get("VARSYM_PIP_TOOL") == "1" else "OFF"
        if not (build / "CMakeCache.txt").exists():  # a build directory of its own
            python = getattr(sys, "_base_executable", sys.executable)
            # One file per compiler process (no unity groups): the largest stays under 1.5 GB.
            # clang++ unless CXX is set, as `make` chooses: measured on 2 cores from a fresh
            # clone, 272 s and 1.0 GB at most against GCC 12's 386 s and 1.9 GB.
            compiler = []
            if "CXX" not in os.environ and shutil.which("clang++"):
                compiler = [f"-DCMAKE_CXX_COMPILER={shutil.which('clang++')}"]
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-Wno-dev",
                            "-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={python}",
                            f"-DVARSYM_BUILD_TOOL={tool}", "-DVARSYM_BUILD_TESTS=OFF",
                            "-DVARSYM_BUILD_BENCH=OFF", "-DVARSYM_BUILD_EXAMPLES=OFF",
                            "-DVARSYM_INSTALL=OFF", "-DVARSYM_UNITY_GROUPS=0", *compiler],
                           check=True)
        # varsym._tool too where the build directory has the tool (VARSYM_PIP_TOOL=1 for a new
        # one).
        tool = "VARSYM_BUILD_TOOL:BOOL=ON" in (build / "CMakeCache.txt").read_text()
        targets = ["varsym_python"] + (["varsym_python_tool"] if tool else [])
        subprocess.run(["cmake", "--build", str(build), "--target", *targets, "-j",
                        str(os.cpu_count() or 2)], check=True)
        built = sorted((build / "python" / "varsym").glob("_core*.so"))
        if not built:
            sys.exit(f"varsym: CMake did not build varsym/_core*.so in {build}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)
        # varsym._tool (the command line in-process) where that build made it.
        for tool in (build / "python" / "varsym").glob("_tool*.so"):
            shutil.copy2(tool, target.parent / tool.name)


VERSION = re.search(r"project\(varsym VERSION ([0-9.]+)",
                    (ROOT / "CMakeLists.txt").read_text()).group(1)

setup(
    name="varsym",
    version=VERSION,
    description="Variational symplectic integrators for Lagrangian mechanics",
    packages=["varsym"],
    package_dir={"": "python"},
    ext_modules=[Extension("varsym._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    python_requires=">=3.9",
    install_requires=["numpy"],
    zip_safe=False,
)
