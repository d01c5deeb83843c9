"""setuptools driving CMake (pyproject.toml): the Python module and libvmas are built by the
project's own CMakeLists.txt in build-python/, then put into the wheel side by side: the module
at the top, the library in vmas.libs/ (the module's RPATH: $ORIGIN/vmas.libs), with the type
stubs. The version is CMake's."""

import glob
import os
import re
import shutil
import subprocess

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def cmake_version():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(vmas VERSION ([0-9.]+)", f.read()).group(1)


class CMakeBuild(build_ext):
    """Builds the module `vmas` with CMake (incrementally: its build folder is kept)."""

    def build_extension(self, ext):
        build = os.path.abspath(os.path.join(self.build_temp, "cmake"))
        subprocess.run(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                        "-DVMAS_BUILD_TESTS=OFF", "-DVMAS_PYTHON=ON", "-DVMAS_PYTHON_WHEEL=ON"],
                       check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["cmake", "--build", build, "--target", "vmas_python", "-j",
                        str(os.cpu_count() or 1)], check=True)
        target = self.get_ext_fullpath(ext.name)
        folder = os.path.dirname(target)
        os.makedirs(os.path.join(folder, "vmas.libs"), exist_ok=True)
        shutil.copyfile(glob.glob(os.path.join(build, "python", "vmas*.so"))[0], target)
        shutil.copyfile(os.path.join(build, "python", "vmas.pyi"),
                        os.path.join(folder, "vmas.pyi"))
        # The library under its soname, which the module asks for.
        library = os.path.realpath(os.path.join(build, "libvmas.so"))
        soname = ".".join(os.path.basename(library).split(".")[:4])  # libvmas.so.MAJOR.MINOR
        shutil.copyfile(library, os.path.join(folder, "vmas.libs", soname))


# No Python packages to discover (src/ is C++); setuptools' own files go to build-python/ too.
os.makedirs(os.path.join(ROOT, "build-python"), exist_ok=True)
setup(version=cmake_version(),
      packages=[],
      py_modules=[],
      ext_modules=[Extension("vmas", sources=[])],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build-python"},
               "egg_info": {"egg_base": "build-python"}},
      zip_safe=False)
