"""The build step of `pip install .` (pyproject.toml): the project's own CMake build, configured in build-pip/
without tests and benchmarks, makes only the extension tether._tether and the libraries it links, for the Python
that runs pip; setuptools then installs it with the package's Python files (python/tether/)."""
import os
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))
os.makedirs(os.path.join(ROOT, "build-pip"), exist_ok=True)  # setuptools' files go there too, out of the sources


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = os.path.join(ROOT, "build-pip")
        subprocess.run(["cmake", "-S", ROOT, "-B", build_dir, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython_EXECUTABLE={sys.executable}", "-DTETHER_BUILD_TESTS=OFF",
                        "-DTETHER_BUILD_BENCHMARKS=OFF"], check=True)
        subprocess.run(["cmake", "--build", build_dir, "--target", "_tether", "-j", str(os.cpu_count() or 1)],
                       check=True)
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        self.copy_file(os.path.join(build_dir, "python", "tether", os.path.basename(target)), target)


setup(packages=["tether"], package_dir={"": "python"},
      options={"build": {"build_base": os.path.join("build-pip", "setuptools")},  # build/ is CMake's
               "egg_info": {"egg_base": "build-pip"}},
      ext_modules=[Extension("tether._tether", sources=[])], cmdclass={"build_ext": CMakeBuild})
