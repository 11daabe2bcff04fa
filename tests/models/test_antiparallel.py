"""Anti-parallel consecutive axes (θ = π, which ``import`` writes for every flipped axis) through
the emitted code: Kinova's arm (tests/robots/kinova_description), a leg of Ghost Robotics'
Spirit 40 quadruped (pybullet's data, tests/models/data/spirit40.urdf, MIT licence in its header)
and a three-body chain whose second and third axes are flipped (tests/models/data/flipped3.urdf:
offsets, products of inertia), imported as users import them, generated in both forms of φ̈, and
the C in double and in float and the Python mirror held to Pinocchio's ABA on the same URDF."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain import exchange, pipeline, robot
from gyrochain.spec import parse_spec
from conftest import ROOT
from simulators import Pin

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin; make test installs it) is the other model")

FILES = {"kinova": ROOT / "tests" / "robots" / "kinova_description" / "kinova.urdf",
         "flipped3": ROOT / "tests" / "models" / "data" / "flipped3.urdf",
         "spirit40": ROOT / "tests" / "models" / "data" / "spirit40.urdf"}
TIPS = {"spirit40": "toe0"}  # one leg of the quadruped
STATES = 40
FLOAT_MAX = 1e-3  # float's φ̈ relative to the largest entry, worst of the states (docs/embedding.md: 99 % under 1e-4)


def _imported(which):
    path, tip = FILES[which], TIPS.get(which)
    text, _ = exchange.import_text(path, tip=tip)
    spec = parse_spec(text)
    assert any(str(b.theta) in ("pi", "-pi") for b in spec.bodies), "an anti-parallel pair"
    names = [b.joint.name for b in robot.chain(exchange.read_description(path), None, tip, {}).bodies]
    return spec, Pin(path, names, {}, robot.GRAVITY)


@pytest.mark.parametrize("qdd_form", ["composite", "articulated"])
@pytest.mark.parametrize("which", sorted(FILES))
def test_anti_parallel_axes_are_pinocchio_s_through_the_emitted_code(which, qdd_form, make_model):
    spec, other = _imported(which)
    model = make_model(spec, qdd_form=qdd_form)
    files, _ = pipeline.derive_and_render(spec, targets=("c",), qdd_form=qdd_form, real="float")
    single = pipeline.compile(files, spec.name)
    rng, n = np.random.default_rng(len(spec.bodies)), spec.n
    damping = np.array([float(b.damping or 0) for b in spec.bodies])
    worst = {"C": 0.0, "Python": 0.0, "float": 0.0}
    for _ in range(STATES):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        tau = rng.normal(size=n) * 5.0
        u = tau[[k - 1 for k in spec.controls]]
        want = other.qdd(x, tau - damping * x[n:])
        scale = np.max(np.abs(want))
        for what, got in (("C", model.c.qdd(x, u)), ("Python", model.py.qdd(x, u)),
                          ("float", single.qdd(x.astype(np.float32), u.astype(np.float32)))):
            worst[what] = max(worst[what], float(np.max(np.abs(got - want))) / scale)
    print(which, qdd_form, worst)
    assert worst["C"] <= 1e-10 and worst["Python"] <= 1e-10 and worst["float"] <= FLOAT_MAX, worst


def test_a_passive_leg_keeps_its_energy(tmp_path):
    """The Spirit 40's leg imported without controls and simulated from rest at (0.5, 1, 2): its
    energy rose 0.2541 → 0.2651 → 0.2806 J over a second through the emitted C; it is constant."""
    import subprocess
    import sys

    text, _ = exchange.import_text(FILES["spirit40"], tip="toe0", controls=False)
    (tmp_path / "spirit_toe0.toml").write_text(text)
    run = subprocess.run([sys.executable, "-m", "gyrochain", "simulate", "spirit_toe0.toml", "--phi", "0.5,1,2", "--t1", "1",
                          "--steps", "2"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    energy = np.array([float(row.split(",")[-1]) for row in run.stdout.splitlines()[1:]])
    assert len(energy) == 3 and np.max(np.abs(energy - energy[0])) <= 1e-9 * abs(energy[0]), energy
