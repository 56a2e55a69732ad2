"""setuptools glue of `pip install .` (pyproject.toml): builds the extension ringlet._ringlet
with the project's CMake (target ringlet_python, for the Python running pip) and installs it in
the package python/ringlet. Environment: RINGLET_PIP_BUILD_DIR (default build-pip/ in the source
tree), RINGLET_PIP_JOBS (parallel compile jobs, default 2), RINGLET_PIP_CMAKE_ARGS (more CMake
arguments, space-separated, e.g. "-DRINGLET_WARNINGS_AS_ERRORS=ON"; they come last, so
"-DCMAKE_BUILD_TYPE=RelWithDebInfo" overrides the default Release build)."""
import os
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = os.environ.get("RINGLET_PIP_BUILD_DIR", os.path.join(HERE, "build-pip"))
        configure = ["cmake", "-S", HERE, "-B", build_dir,
                     "-DPython_EXECUTABLE=" + sys.executable,
                     "-DRINGLET_BUILD_TESTS=OFF", "-DRINGLET_BUILD_STUDIO=OFF",
                     "-DRINGLET_BUILD_TOOLS=OFF",
                     # An installed module: optimized, without debug information (a -O2 -g
                     # build took 37 min and made a 108-MB extension; issue 25, item 8).
                     "-DCMAKE_BUILD_TYPE=Release"]
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        configure += shlex.split(os.environ.get("RINGLET_PIP_CMAKE_ARGS", ""))
        subprocess.check_call(configure)
        subprocess.check_call(["cmake", "--build", build_dir, "--target", "ringlet_python",
                               "-j", os.environ.get("RINGLET_PIP_JOBS", "2")])
        package = os.path.join(build_dir, "python", "ringlet")
        built = [f for f in os.listdir(package) if f.startswith("_ringlet") and f.endswith(".so")]
        if len(built) != 1:
            raise RuntimeError("expected one _ringlet*.so in %s, found %s" % (package, built))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(package, built[0]), target)


setup(
    packages=["ringlet"],
    package_dir={"ringlet": "python/ringlet"},
    # The type stubs and the PEP 561 marker: IDEs and type checkers see the API's types.
    package_data={"ringlet": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("ringlet._ringlet", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
)
