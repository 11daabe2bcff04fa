"""pipeline.compile: one build per machine however many processes ask at once (the file lock),
and a loaded model per process."""
from __future__ import annotations

import subprocess
import sys

from codegen import pipeline
from codegen.spec import load_spec
from conftest import ROOT

ASK = r"""
import sys, time
from codegen import build, pipeline
from codegen.spec import load_spec

real = build.compile_model

def counted(*args, **kwargs):
    with open(sys.argv[1], "a") as log:
        log.write("built\n")
    time.sleep(1.0)  # a slow build: the other process must wait for it, not build again
    return real(*args, **kwargs)

build.compile_model = counted
files, _ = pipeline.derive_and_render(load_spec("specs/gimbal.toml"), targets=("c",))
print(repr(float(pipeline.compile(files, "gimbal").qdd([0.3, 0.2, 1.0, -0.5])[1])))
"""


def test_two_processes_build_once_and_load_the_same_build(tmp_path):
    cache, log = tmp_path / "cache", tmp_path / "log"
    env = {"GYROCHAIN_CACHE": str(cache), "PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)}
    procs = [subprocess.Popen([sys.executable, "-c", ASK, str(log)], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-2000:] for o in outs]
    assert log.read_text().count("built") == 1
    assert outs[0][0] == outs[1][0]
    entries = sorted(p.name for p in cache.iterdir() if p.is_dir())
    assert len(entries) == 1 and entries[0].startswith("gimbal-"), entries  # no staging folder left behind


def test_the_same_sources_load_once_per_process(tmp_path, monkeypatch):
    monkeypatch.setenv("GYROCHAIN_CACHE", str(tmp_path))
    files, _ = pipeline.derive_and_render(load_spec(ROOT / "specs" / "double_pendulum.toml"), targets=("c",))
    assert pipeline.compile(files, "double_pendulum") is pipeline.compile(dict(files), "double_pendulum")


def test_generate_builds_ahead_only_what_the_folder_lacks(tmp_path, monkeypatch):
    """generate's BuildAhead: the extension is compiled into the cache by a child process while
    the Python and the LaTeX are printed, and generate reports it as compiled; a folder whose
    extension is current starts no build at all."""
    from codegen import generate

    monkeypatch.setenv("GYROCHAIN_CACHE", str(tmp_path / "cache"))
    spec, out = load_spec(ROOT / "specs" / "double_pendulum.toml"), tmp_path / "dp"
    assert generate.run(spec, out, "double_pendulum.toml").build == "compiled"
    assert len(list((tmp_path / "cache").glob("double_pendulum-*/_double_pendulum_cffi*.so"))) == 1
    files, _ = pipeline.derive_and_render(spec)
    ahead = pipeline.BuildAhead(out, "double_pendulum")
    ahead(files)
    assert ahead._future is None and ahead.built() is False  # the folder's own extension is current
    ahead = pipeline.BuildAhead(tmp_path / "elsewhere", "double_pendulum")
    ahead(files)
    assert ahead._future is not None and ahead.built() is False  # started; the cache had it already
    assert generate.run(spec, out, "double_pendulum.toml").build == "reused"
