"""What a newcomer reads: every subcommand's --help describes every argument with its default and
format, the grid format is spelled one way, and the commands print what they mean (steady's one
equilibrium, simulate's shortest floats)."""
import argparse
import subprocess
import sys

import pytest

from gyrochain import parsers
from gyrochain.starter import KINDS


def _parsers():
    ap = parsers.build("gyrochain", "", "v", KINDS)
    todo, seen = [("gyrochain", ap)], []
    while todo:
        name, p = todo.pop()
        seen.append((name, p))
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                todo += [(f"{name} {k}", sub) for k, sub in a.choices.items()]
    return seen


def test_every_argument_is_described_with_its_default():
    missing = []
    for name, p in _parsers():
        for a in p._actions:
            if isinstance(a, (argparse._HelpAction, argparse._VersionAction, argparse._SubParsersAction)):
                continue
            what = f"{name} {'/'.join(a.option_strings) or a.dest}"
            if not a.help or a.help == argparse.SUPPRESS:
                missing.append(f"{what}: no description")
            elif a.option_strings and not a.required and "default" not in a.help and a.nargs != 0:
                missing.append(f"{what}: no default in {a.help!r}")
            elif a.nargs == 0 and "--version" not in a.option_strings and not any(
                    w in a.help for w in ("default", "anywhere", "no closing")):
                missing.append(f"{what}: a flag that does not say what happens without it: {a.help!r}")
    assert not missing, "\n".join(missing)
    assert len(_parsers()) >= 17  # gyrochain, its 15 commands, examples' copy and show


def test_one_spelling_of_a_grid():
    texts = " ".join(f"{a.help or ''} {a.metavar or ''}" for _, p in _parsers() for a in p._actions)
    assert "lo:hi:N" in texts and "a:b:N" not in texts and "lo:hi:count" not in texts


def _run(*args):
    return subprocess.run([sys.executable, "-m", "gyrochain", *args], capture_output=True, text=True, timeout=600)


def test_every_subcommand_help_runs_and_shows_its_defaults(capsys):
    from gyrochain.cli import main

    for name, _ in _parsers()[1:]:
        with pytest.raises(SystemExit) as done:
            main([*name.split()[1:], "--help"])
        out = capsys.readouterr().out
        assert done.value.code == 0 and "usage:" in out, name
    r = _run("simulate", "--help")
    assert "(default 1)" in r.stdout and "(default 100)" in r.stdout


def test_a_missing_command_lists_the_commands():
    r = _run()
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert "command: missing; one of generate, check, simulate" in r.stderr and "identify" in r.stderr


def test_simulate_prints_shortest_floats():
    r = _run("simulate", "specs/double_pendulum.toml", "--t1", "0.3", "--steps", "3", "--phi", "0.1,0")
    rows = [ln.split(",") for ln in r.stdout.splitlines()[1:]]
    assert [row[0] for row in rows] == ["0", "0.1", "0.2", "0.3"]
    assert all(repr(float(v)).removesuffix(".0") == v for row in rows for v in row)  # the shortest text of its double


def test_steady_prints_one_equilibrium_of_the_cable():
    r = _run("steady", "specs/cable64.toml", "--at", "phi=0")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[1].startswith("equilibria: 1 found by Newton from phi = [0, 0,")
    assert sum(ln.startswith("  phi = ") for ln in lines) == 1
    ev = lines[3].split(": ", 1)[1].split(", ")
    assert len(ev) == 128 and ev[0].startswith("0+458.5954") and len(ev[0]) >= 12  # 10 significant digits
    assert len(r.stdout) < 5000


def test_steady_says_parameters_and_limits_its_list():
    r = _run("steady", "specs/kapitza.toml", "--param", "a=0.01", "--param", "w=260", "--digits", "6")
    assert r.stdout.splitlines()[0] == "kapitza: n = 1, a = 0.01, w = 260", r.stdout
    assert "multipliers: 0.961089+" in r.stdout  # six digits
    r = _run("steady", "specs/gimbal.toml", "--no-rotations", "--max-equilibria", "1")
    assert "4 found" in r.stdout and "the first 1 printed" in r.stdout and r.stdout.count("  phi = ") == 1
    for args, said in ((["--at", "phi=x"], "--at: expected comma-separated numbers"),
                       (["--at", "1,2,3"], "--at: expected one angle or 2, got 3"),
                       (["--at", "0", "--omega", "1:2:3"], "--omega: --at asks for the one equilibrium"),
                       (["--digits", "0"], "--digits: 0: expected 1 to 17")):
        r = _run("steady", "specs/gimbal.toml", *args)
        assert r.returncode == 2 and r.stderr.startswith(f"error: {said}") and r.stderr.count("\n") == 1, r.stderr
