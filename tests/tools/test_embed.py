"""The generated folder as a package for C and C++ builds: CMake's library NAME::NAME, installed
with a package config (find_package) and a pkg-config file; examples/embed/ (a C++ program) built
against generated/furuta by the commands its README shows, run, and compared with the Python
model; add_subdirectory and pkg-config too."""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from gyrochain import build
from conftest import ROOT

pytestmark = pytest.mark.skipif(not (shutil.which("cmake") and shutil.which("c++") and shutil.which("cc")),
                                reason="needs cmake and a C and C++ compiler (apt-get install cmake g++)")

GEN = ROOT / "generated" / "furuta"


def _run(cmd, cwd, env=None):
    res = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0, (cmd, res.stdout[-2000:], res.stderr[-2000:])
    return res.stdout


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """generated/furuta configured, built and installed into a prefix, as examples/embed/README.md says."""
    work = tmp_path_factory.mktemp("embed")
    _run(["cmake", "-S", GEN, "-B", work / "build" / "furuta", "-DCMAKE_BUILD_TYPE=Release"], work)
    _run(["cmake", "--build", work / "build" / "furuta"], work)
    _run(["cmake", "--install", work / "build" / "furuta", "--prefix", work / "build" / "prefix"], work)
    return work


def test_the_readmes_commands_build_and_run_the_cpp_program(installed):
    work = installed
    prefix = work / "build" / "prefix"
    libdir = next(p for p in (prefix / "lib", prefix / "lib64", *prefix.glob("lib/*")) if (p / "cmake" / "furuta").is_dir())
    for f in ("furutaConfig.cmake", "furutaConfigVersion.cmake", "furutaTargets.cmake"):
        assert (libdir / "cmake" / "furuta" / f).is_file(), f
    assert (prefix / "include" / "furuta.h").is_file() and (libdir / "libfuruta.a").is_file()
    _run(["cmake", "-S", ROOT / "examples" / "embed", "-B", work / "build" / "embed", f"-DCMAKE_PREFIX_PATH={prefix}"], work)
    _run(["cmake", "--build", work / "build" / "embed"], work)
    out = _run([work / "build" / "embed" / "embed_furuta"], work).splitlines()
    # the same computations through the cffi build of the same C, and the Python mirror
    m, py = build.load(GEN), build.load_python(GEN)
    x0, u = np.array([0.0, np.pi - 0.2, 0.0, 0.0]), np.array([0.01])
    qdd = np.array([float(v) for v in out[0].split()[1:]])
    assert np.allclose(qdd, m.qdd(x0, u), rtol=1e-14, atol=0) and np.allclose(qdd, py.qdd(x0, u), rtol=1e-12, atol=0)
    X = m.integrate(np.arange(0.0, 1.0001, 0.25), x0, "rk4", h=1e-3, u=u)
    for line, want in zip(out[1:], X[1:]):
        got = np.array([float(v) for v in line.split()[3:]])
        assert np.allclose(got, want, rtol=1e-12, atol=1e-14), (got, want)
    assert len(out) == 5


def test_pkg_config_gives_the_flags(installed, tmp_path):
    if not shutil.which("pkg-config"):
        pytest.skip("pkg-config is not installed (apt-get install pkg-config)")
    prefix = installed / "build" / "prefix"
    pc = next(prefix.rglob("furuta.pc"))
    text = pc.read_text()
    assert "@" not in text and "prefix=${pcfiledir}/../.." in text and "Version: 0." in text
    env = dict(os.environ, PKG_CONFIG_PATH=str(pc.parent))
    flags = _run(["pkg-config", "--cflags", "--libs", "furuta"], tmp_path, env).split()
    include = next(f[2:] for f in flags if f.startswith("-I"))
    assert (Path(include) / "furuta.h").is_file(), flags  # the prefix found from the .pc's own place
    (tmp_path / "main.c").write_text('#include <stdio.h>\n#include "furuta.h"\nint main(void) { double x[4] = {0, 3, 0, 0}, '
                                     'q[2]; int c = furuta_qdd(x, NULL, NULL, q); printf("%d %.17g\\n", c, q[1]); return c; }\n')
    _run(["cc", "-std=c99", "-Wall", "-Wextra", "-Werror", "main.c", "-o", "main", *flags], tmp_path)
    code, q1 = _run([tmp_path / "main"], tmp_path).split()
    assert code == "0" and float(q1) == pytest.approx(build.load(GEN).qdd([0, 3, 0, 0])[1], rel=1e-14)


def test_add_subdirectory_gives_the_same_target(tmp_path):
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.13)\nproject(app C)\n"
        f'add_subdirectory("{GEN}" furuta)\n'
        'file(WRITE ${CMAKE_BINARY_DIR}/app.c "#include \\"furuta.h\\"\\nint main(void) { double x[4] = {0}, q[2]; '
        'return furuta_qdd(x, 0, 0, q); }\\n")\n'
        "add_executable(app ${CMAKE_BINARY_DIR}/app.c)\ntarget_link_libraries(app PRIVATE furuta::furuta)\n")
    _run(["cmake", "-S", tmp_path, "-B", tmp_path / "b"], tmp_path)
    _run(["cmake", "--build", tmp_path / "b"], tmp_path)
    _run([tmp_path / "b" / "app"], tmp_path)
    assert not (GEN / "CMakeCache.txt").exists()  # nothing written into the generated folder
