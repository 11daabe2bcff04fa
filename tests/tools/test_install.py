"""The package as its users get it: ``python -m build`` makes the sdist and, from the sdist, the
wheel (no warning); ``twine check --strict`` passes both; the wheel, not editable, goes into a fresh
virtual environment outside the repository beside a distribution that owns a top-level ``codegen``
package (a stand-in for the unrelated "codegen" on the index, built here); and from an empty folder,
with a home of its own (so the default per-user cache), every block of the pages a newcomer follows
(README.md, README-pypi.md, docs/getting-started.md, docs/tutorial.md) runs command for command,
output compared as tests/docrun.py compares it (the README's first instruction, ``pip install
"./gyrochain-VERSION.tar.gz[sweep,view]"``, as written, with the source archive in the user's folder).  Then the generated folder builds with CMake, the cache is private, and
the optional extras (sweep, view) run a small sweep, its map and a GIF.

Needs the package index for the build backend and the dependencies (pip's cache makes a second
run quick): about a minute and a half on two cores."""
from __future__ import annotations

import base64
import hashlib
import os
import shutil
import stat
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tests"))
import docrun  # noqa: E402

STANDIN = "the unrelated codegen distribution (a stand-in)"


def sh(args, **kw) -> subprocess.CompletedProcess:
    kw.setdefault("timeout", 600)
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)


def source_tree(dest: Path) -> Path:
    """What a release is built from: the files git tracks or would track (no build products, no
    __pycache__), symbolic links kept; outside a git checkout (tests run from an unpacked sdist),
    the tree without its build products."""
    dest.mkdir(parents=True)
    r = sh(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT) if (ROOT / ".git").exists() else None
    if r is not None and r.returncode == 0:
        names = sorted(n for n in set(r.stdout.split("\0")) if n and ((ROOT / n).exists() or (ROOT / n).is_symlink()))
    else:
        names = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if (p.is_file() or p.is_symlink())
                 and not {"__pycache__", ".venv", "build", "dist", ".git"} & set(p.relative_to(ROOT).parts)]
    for name in names:
        src, dst = ROOT / name, dest / name
        dst.parent.mkdir(parents=True, exist_ok=True)
        if src.is_symlink():
            os.symlink(os.readlink(src), dst)
        elif src.is_file():
            shutil.copy2(src, dst)
    return dest


def standin_wheel(folder: Path) -> Path:
    """A wheel of a distribution "codegen" 0.57 that installs a top-level package ``codegen``, as
    the unrelated project of that name on the index does (its real wheels need Python >= 3.12)."""
    files = {"codegen/__init__.py": f"WHO = {STANDIN!r}\n",
             "codegen-0.57.dist-info/METADATA": "Metadata-Version: 2.1\nName: codegen\nVersion: 0.57\n",
             "codegen-0.57.dist-info/WHEEL": "Wheel-Version: 1.0\nGenerator: test_install\nRoot-Is-Purelib: true\nTag: py3-none-any\n"}
    record = [f"{k},sha256={base64.urlsafe_b64encode(hashlib.sha256(v.encode()).digest()).rstrip(b'=').decode()},{len(v.encode())}"
              for k, v in files.items()] + ["codegen-0.57.dist-info/RECORD,,"]
    path = folder / "codegen-0.57-py3-none-any.whl"
    with zipfile.ZipFile(path, "w") as z:
        for k, v in files.items():
            z.writestr(k, v)
        z.writestr("codegen-0.57.dist-info/RECORD", "\n".join(record) + "\n")
    return path


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    pytest.importorskip("build", reason="the test extra (make test installs it)")
    work = tmp_path_factory.mktemp("dist")
    src = source_tree(work / "src")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    r = sh([sys.executable, "-m", "build", "-o", work / "dist", src], env=env)  # the sdist, then the wheel from it
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    warnings = [ln for ln in (r.stdout + r.stderr).splitlines() if "warning" in ln.lower()]
    assert not warnings, warnings
    (sdist,), (wheel,) = sorted((work / "dist").glob("*.tar.gz")), sorted((work / "dist").glob("*.whl"))
    return sdist, wheel


def test_the_wheel_and_sdist_carry_everything(dist):
    sdist, wheel = dist
    from gyrochain import __version__

    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
    assert {n.split("/")[0] for n in names} == {"gyrochain", f"gyrochain-{__version__}.dist-info"}  # nothing else at the top
    for need in ("gyrochain/templates/model.c.jinja", "gyrochain/templates/viewer.js", "gyrochain/templates/new_spec.toml.jinja",
                 "gyrochain/kernels/dop853.c", "gyrochain/examples/gimbal.toml", "gyrochain/examples/cable64.toml",
                 f"gyrochain-{__version__}.dist-info/licenses/LICENSE"):
        assert need in names, need
    shipped = [p.relative_to(ROOT / "specs") for p in (ROOT / "specs").rglob("*") if p.is_file()]
    assert sorted(n for n in names if n.startswith("gyrochain/examples/")) == sorted(f"gyrochain/examples/{p}" for p in shipped)
    with tarfile.open(sdist) as t:
        inside = {m.name.split("/", 1)[1] for m in t.getmembers() if "/" in m.name}
    for need in ("LICENSE", "Makefile", "README.md", "README-pypi.md", "pyproject.toml", "tests/conftest.py",
                 "tests/tools/test_install.py", "specs/gimbal.toml", "docs/getting-started.md", "generated/gimbal/gimbal.c",
                 "gyrochain/examples/gimbal.toml", "gyrochain/templates/model.h.jinja", ".ci/run",
                 "specs/robots/ur5_robot.urdf", "specs/robots/README.md", "specs/robots/LICENSE-Apache-2.0"):
        assert need in inside, need
    assert not [n for n in inside if "__pycache__" in n or n.endswith((".so", ".pyc"))]


def test_twine_check_strict(dist):
    pytest.importorskip("twine", reason="the test extra (make test installs it)")
    r = sh([sys.executable, "-m", "twine", "check", "--strict", *dist])
    assert r.returncode == 0 and r.stdout.count("PASSED") == 2, r.stdout + r.stderr


def test_the_classifiers_are_the_index_s():
    trove = pytest.importorskip("trove_classifiers", reason="the test extra (make test installs it)")
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert [c for c in project["classifiers"] if c not in trove.classifiers] == []
    assert project["license"] == "MIT" and (ROOT / "LICENSE").read_text().startswith("MIT License")


@pytest.fixture(scope="module")
def installed(dist, tmp_path_factory):
    """A fresh venv with the stand-in codegen and our wheel (not editable), and a user's empty
    folder and home; run(line) runs a shell line there as the user would."""
    _, wheel = dist
    base = tmp_path_factory.mktemp("user")
    venv, home, here = base / "venv", base / "home", base / "empty"
    home.mkdir()
    here.mkdir()
    r = sh([sys.executable, "-m", "venv", venv])
    assert r.returncode == 0, r.stderr
    env = {"PATH": f"{venv / 'bin'}:/usr/local/bin:/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8", "COLUMNS": "100",
           "PIP_DISABLE_PIP_VERSION_CHECK": "1", "TMPDIR": str(base)}
    for keep in ("CC", "PIP_INDEX_URL", "PIP_EXTRA_INDEX_URL", "PIP_TRUSTED_HOST", "PIP_CACHE_DIR", "XDG_CACHE_HOME_PIP"):
        if keep in os.environ:
            env[keep] = os.environ[keep]
    env.setdefault("PIP_CACHE_DIR", str(Path.home() / ".cache" / "pip"))  # the user's pip cache: downloads once
    r = sh([venv / "bin" / "pip", "install", "-q", standin_wheel(base)], env=env)
    assert r.returncode == 0, r.stdout + r.stderr

    def run(line: str, folder: str = "", timeout: float = 600) -> subprocess.CompletedProcess:
        """``line`` through the shell in the empty folder ``folder`` (made on first use) of the user."""
        cwd = here / folder
        cwd.mkdir(exist_ok=True)
        return subprocess.run(["bash", "-c", line], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)

    return dict(venv=venv, home=home, here=here, env=env, wheel=wheel, sdist=dist[0], run=run)


def _run_console(block, run, installed, page) -> int:
    """A console block's commands through the shell in the page's folder, as a user types them."""
    here, wheel, ran = installed["here"], installed["wheel"], 0
    for cmd in docrun.commands(block.text):
        line = cmd.line
        assert not line.startswith("make "), f"{block.where}: `{line}` is a checkout's target: mark the block clone"
        if line.startswith(("pip install ./gyrochain-", 'pip install "./gyrochain-')):  # the source archive, in the folder
            archive = line.split()[2].strip('"').removeprefix("./").split("[")[0]
            assert archive == installed["sdist"].name, f"{block.where}: `{line}`, but the release's archive is {installed['sdist'].name}"
            (here / page).mkdir(exist_ok=True)
            shutil.copy(installed["sdist"], here / page / archive)
        elif line.startswith(("pip install gyrochain", 'pip install "gyrochain[')):  # the index's name: the wheel
            extras = line.split("gyrochain", 1)[1].split("]")[0] + "]" if "[" in line else ""
            line = f'pip install -q "{wheel}{extras.strip(chr(34))}"'
        r = run(line + " 2>&1", page)
        want = 2 if any(ln.startswith("error:") for ln in cmd.shown) else 0
        assert r.returncode == want, f"{block.where}: `{cmd.line}` exited {r.returncode}:\n{r.stdout}{r.stderr}"
        if cmd.shown and not cmd.line.startswith("pip "):
            assert docrun.matches(cmd.shown, r.stdout, block.within), (
                f"{block.where}: `{cmd.line}` printed\n{r.stdout}\nwhere the docs show\n" + "\n".join(cmd.shown))
        ran += 1
    return ran


def test_the_tour_from_an_empty_folder(installed):
    """Every block of the pages a newcomer follows (the README, the index's page, Getting started,
    the tutorial), in order, each page from an empty folder of its own on the install it documents:
    commands through the shell with their output compared, Python run, specs saved where the page
    says; ``pip install gyrochain`` installs the wheel, the README's ``pip install
    "./gyrochain-VERSION.tar.gz[...]"`` the source archive as written.  Only a checkout's make
    targets (blocks marked clone) are left out."""
    run, here = installed["run"], installed["here"]
    ran, clone = 0, 0
    for path in docrun.user_pages():
        page = path.stem
        for block in docrun.blocks(path):
            assert not block.skip, f"{block.where}: a newcomer's page runs every block"
            if block.clone:
                clone += 1
                continue
            (here / page).mkdir(exist_ok=True)
            if block.save:
                (here / page / block.save).write_text(block.text)
            if block.kind == "python":
                script = here / f"block_{page}_{block.line}.py"
                script.write_text(block.text)
                r = run(f"python {script}", page)
                assert r.returncode == 0, f"{block.where}: {r.stdout}{r.stderr}"
                ran += 1
            elif block.kind == "toml" and block.save:
                r = run(f"gyrochain check {block.save}", page)
                assert r.returncode == 0, f"{block.where}: {r.stdout}{r.stderr}"
            elif block.kind == "console":
                ran += _run_console(block, run, installed, page)
            else:
                assert block.kind in ("text", "toml"), f"{block.where}: a {block.kind} block on a newcomer's page"
    print(f"\nthe newcomer's pages: {ran} commands and programs run, {clone} blocks of a checkout left out")
    assert ran >= 40 and clone <= 3, (ran, clone)
    # it ran the installed package, from outside the repository, beside the other codegen
    r = run("python -c 'import gyrochain, codegen; print(gyrochain.__file__); print(codegen.WHO)'")
    assert r.returncode == 0, r.stderr
    where, who = r.stdout.splitlines()
    assert str(installed["venv"]) in where and not Path(where).is_relative_to(ROOT) and who == STANDIN
    assert run("pip check").returncode == 0
    # the compiled models went to the user's own cache, private to them
    cache = installed["home"] / ".cache" / "gyrochain"
    assert cache.is_dir() and stat.S_IMODE(cache.stat().st_mode) == 0o700
    assert any(p.name.startswith("gimbal-") for p in cache.iterdir())
    assert (here / "README-pypi" / "generated" / "gimbal" / "gimbal.c").read_text().startswith(
        "/* gimbal.c - generated by gyrochain ")
    assert (here / "tutorial" / "generated" / "gyropendulum" / "gyropendulum.pdf").exists()  # generate --pdf


def test_the_generated_folder_builds_with_cmake(installed):
    if not shutil.which("cmake"):
        pytest.skip("no cmake (.ci/run installs it)")
    run = installed["run"]
    r = run("gyrochain examples copy gimbal && gyrochain generate -q --no-build gimbal.toml && "
            "cmake -S generated/gimbal -B build/gimbal -DCMAKE_BUILD_TYPE=Release && cmake --build build/gimbal", "cmake")
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert (installed["here"] / "cmake" / "build" / "gimbal" / "libgimbal.a").exists()


def test_the_extras_sweep_plot_and_gif(installed):
    """pip install "gyrochain[sweep,view]": a small sweep into a Zarr store, its map, a GIF."""
    run, wheel = installed["run"], installed["wheel"]
    r = run(f'pip install -q "{wheel}[sweep,view]"')
    assert r.returncode == 0, r.stdout + r.stderr
    r = run("gyrochain examples copy double_pendulum gimbal >/dev/null && "
            "gyrochain sweep double_pendulum.toml --vary phi1=-1:1:4 --vary phi2=-1:1:3 --t1 1 -q -o map.zarr && "
            "gyrochain plot map.zarr -o map.png && "
            "gyrochain animate gimbal.toml --t1 1 --fps 10 --size 120x120 -q -o gimbal.gif", "extras")
    assert r.returncode == 0, r.stdout + r.stderr
    here = installed["here"] / "extras"
    assert (here / "map.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (here / "gimbal.gif").read_bytes()[:6] == b"GIF89a"


def test_make_dist_builds_without_the_test_extras():
    """`make dist` sets up a venv of its own with build and twine alone, not .venv's extras (CUDA
    wheels, MuJoCo, Pinocchio, CasADi, a browser): the archive in seconds."""
    r = sh(["make", "-n", "-B", "dist"], cwd=ROOT)
    assert r.returncode == 0, r.stderr
    assert "pip install -q --upgrade pip build twine" in r.stdout and "-m build -o dist ." in r.stdout
    assert ".[test" not in r.stdout and "[test," not in r.stdout and ".venv/bin/python" not in r.stdout, r.stdout
