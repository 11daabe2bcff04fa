"""pipeline.compile: one build per machine however many processes ask at once (the file lock),
and a loaded model per process."""
from __future__ import annotations

import subprocess
import sys

from gyrochain import pipeline
from gyrochain.spec import load_spec
from conftest import ROOT

ASK = r"""
import sys, time
from gyrochain import build, pipeline
from gyrochain.spec import load_spec

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
    entries = sorted(p.name for p in cache.iterdir() if p.is_dir() and p.name != "templates")  # (the compiled templates)
    assert len(entries) == 1 and entries[0].startswith("gimbal-"), entries  # no staging folder left behind


def test_the_same_sources_load_once_per_process(tmp_path, monkeypatch):
    monkeypatch.setenv("GYROCHAIN_CACHE", str(tmp_path))
    files, _ = pipeline.derive_and_render(load_spec(ROOT / "specs" / "double_pendulum.toml"), targets=("c",))
    assert pipeline.compile(files, "double_pendulum") is pipeline.compile(dict(files), "double_pendulum")


AHEAD = r"""
import sys
from pathlib import Path
from gyrochain import generate, pipeline
from gyrochain.spec import load_spec

spec, out = load_spec("specs/double_pendulum.toml"), Path(sys.argv[1])
first = generate.run(spec, out, "double_pendulum.toml").build
files, _ = pipeline.derive_and_render(spec)
here = pipeline.BuildAhead(out, "double_pendulum")
here(files)
current = (here._future is None, here.built())
there = pipeline.BuildAhead(out.parent / "elsewhere", "double_pendulum")
there(files)
started = (there._future is not None, there.built())
print(first, current, started, generate.run(spec, out, "double_pendulum.toml").build)
"""


def test_generate_builds_ahead_only_what_the_folder_lacks(tmp_path):
    """generate's BuildAhead, in a fresh process (it forks only where no other thread runs, and a
    test process may have some): the extension is compiled into the cache by a child while the
    Python and the LaTeX are printed, and generate reports it as compiled; a folder whose
    extension is current starts no build; another folder starts one, which finds the cache's."""
    env = {"GYROCHAIN_CACHE": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)}
    res = subprocess.run([sys.executable, "-c", AHEAD, str(tmp_path / "dp")], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.split("\n")[0] == "compiled (True, False) (True, False) reused", res.stdout
    assert len(list((tmp_path / "cache").glob("double_pendulum-*/_double_pendulum_cffi*.so"))) == 1


def test_no_build_ahead_beside_another_thread(tmp_path):
    """A fork copies only the calling thread (and not the locks the others hold): with another
    thread running, BuildAhead starts nothing and write_tree builds as before."""
    import threading

    files, _ = pipeline.derive_and_render(load_spec(ROOT / "specs" / "double_pendulum.toml"), targets=("c",))
    stop = threading.Event()
    other = threading.Thread(target=stop.wait)
    other.start()
    try:
        ahead = pipeline.BuildAhead(tmp_path / "dp", "double_pendulum")
        ahead(files)
        assert ahead._future is None and ahead.built() is False
    finally:
        stop.set()
        other.join()


NO_LTO_GCC = """#!/bin/sh
# gcc as some images install it: no lto-wrapper, so an -flto object cannot be linked
for a in "$@"; do
    case "$a" in -flto*) lto=1 ;; -shared) shared=1 ;; esac
done
if [ -n "$lto" ] && [ -n "$shared" ]; then
    echo "/usr/bin/ld: error: could not run lto-wrapper" >&2
    exit 1
fi
exec gcc "$@"
"""


def test_a_gcc_without_its_link_time_optimiser_still_builds_the_model(tmp_path):
    """$CC is the compiler the build runs (setuptools takes it before Python's own): where that gcc
    cannot link -flto objects, the model is built without LTO instead of failing at the link."""
    cc = tmp_path / "gcc"
    cc.write_text(NO_LTO_GCC)
    cc.chmod(0o755)
    env = {"GYROCHAIN_CACHE": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT), "CC": str(cc)}
    code = ("from gyrochain import build, pipeline\nfrom gyrochain.spec import load_spec\n"
            "print(build.lto_flags())\n"
            "files, _ = pipeline.derive_and_render(load_spec('specs/double_pendulum.toml'), targets=('c',))\n"
            "print(float(pipeline.compile(files, 'double_pendulum').qdd([0.3, 0.2, 1.0, -0.5])[0]))\n")
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    flags, qdd = run.stdout.splitlines()
    assert flags == "([], [])"
    float(qdd)
    # and the same gcc with LTO (the system's) keeps the parallel link
    env.pop("CC")
    code = "from gyrochain import build; print(build.lto_flags(10**6)[0], build.lto_flags(100_000)[0])"
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=60)
    assert run.stdout.strip() == "['-flto'] []", run.stderr  # (a short C builds sooner without: build.LTO_MIN_BYTES)
