"""Robot descriptions against the simulators that read them (issue "robot descriptions in and
out").  For each arm imported from its URDF (the examples and three more), φ̈ of the generated C
equals Pinocchio's ABA on the same URDF file (its joints, its zero, its sign) and MuJoCo's on the
same file; every example that URDF or MJCF can hold, exported, loads in Pinocchio and MuJoCo without
a word and gives the same φ̈; and spec → URDF → spec gives the same model.  At 100 random states
and torques each; a joint's damping is in our φ̈ and MuJoCo's, and is given to Pinocchio (whose
ABA has none) as a torque."""
from __future__ import annotations

import re

import numpy as np
import pytest

from gyrochain import exchange, robot, urdf
from gyrochain.randspec import random_spec_text
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, example_params, tiered
from simulators import Mj, Pin

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin; make test installs it) checks the imported arms")
mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco; make test installs it) checks the descriptions")

ROBOTS = ROOT / "specs" / "robots"
PANDA_LOCKS = ["panda_finger_joint1=0.02", "panda_finger_joint2=0.02"]
ARMS = {  # file: --lock options; the first three are the examples specs/ur5, panda, planar2dof
    "ur5_robot.urdf": [], "panda.urdf": PANDA_LOCKS, "double_pendulum.urdf": [],
    "ur10_robot.urdf": [], "xarm7.urdf": [], "so100.urdf": [],
}
EXPORTABLE = ["double_pendulum", "double_pendulum_point", "furuta", "furuta_sym", "ur5", "panda", "planar2dof", "cable64"]
SAMPLES = 100


@pytest.fixture(autouse=True)
def _elsewhere(tmp_path, monkeypatch):
    """MuJoCo writes its warnings (a URDF's empty joint range) to MUJOCO_LOG.TXT in the working folder."""
    monkeypatch.chdir(tmp_path)


def _states(rng, n):
    for _ in range(SAMPLES):
        yield np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0]), rng.normal(size=n) * 5.0


def _relative(a, b) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def _for_mujoco(path, locks: dict) -> str:
    """The URDF as MuJoCo's compiler can read it here: its meshes (not copied, and not dynamics)
    left out, and a locked prismatic joint made fixed at its value (MuJoCo has no locking)."""
    text = re.sub(r"<(visual|collision)\b.*?</\1>", "", path.read_text(), flags=re.S)
    for joint, value in locks.items():
        j = urdf.read(path).joints[joint]
        assert j.kind == "prismatic" and all(float(r) == 0 for r in j.rpy)
        xyz = " ".join(repr(float(o) + float(a) * float(value)) for o, a in zip(j.xyz, j.axis))
        text = re.sub(rf'(<joint name="{joint}" type=")prismatic(">.*?<origin[^>]*xyz=")[^"]*', rf"\g<1>fixed\g<2>{xyz}",
                      text, flags=re.S)
    return text


@pytest.mark.parametrize("file", sorted(ARMS))
def test_imported_arms_match_pinocchio_and_mujoco(file, make_model):
    path, locks = ROBOTS / file, exchange.locks_of(ARMS[file])
    text, _ = exchange.import_text(path, locks=ARMS[file])
    model = make_model(parse_spec(text))
    names = [b.joint.name for b in robot.chain(urdf.read(path), locks=locks).bodies]
    damping = np.array([float(b.damping or 0) for b in model.spec.bodies])
    pinocchio, mj = Pin(path, names, locks, float(model.spec.g)), Mj.of_text(_for_mujoco(path, locks), names)
    worst_pin = worst_mj = 0.0
    for x, tau in _states(np.random.default_rng(len(file)), model.spec.n):
        ours = model.c.qdd(x, tau)
        worst_pin = max(worst_pin, _relative(ours, pinocchio.qdd(x, tau - damping * x[model.spec.n:])))
        worst_mj = max(worst_mj, _relative(ours, mj.qdd(x, tau)))
    print(f"{file}: n = {model.spec.n}, Pinocchio {worst_pin:.1e}, MuJoCo {worst_mj:.1e}")
    assert worst_pin <= 1e-10 and worst_mj <= 1e-8


@pytest.mark.parametrize("name", EXPORTABLE)
def test_exported_descriptions_load_silently_and_agree(name, make_model, tmp_path, capfd):
    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    values = example_params(name) or {}
    model = make_model(spec, values or None)
    n, names = spec.n, [f"joint{k}" for k in range(1, spec.n + 1)]
    files = {}
    for to in ("urdf", "mjcf"):
        try:
            files[to], _ = exchange.export_text(spec, f"{name}.toml", to, values)
        except Exception as exc:  # a point mass is refused for MuJoCo, and said so
            assert to == "mjcf" and "I_c: MuJoCo's compiler refuses" in str(exc), exc
    (tmp_path / "m.urdf").write_text(files["urdf"])
    pinocchio = Pin(tmp_path / "m.urdf", names, {}, float(spec.g.subs({p: values[str(p)] for p in spec.params})))
    mj = Mj.of_text(files["mjcf"], names) if "mjcf" in files else None
    out, err = capfd.readouterr()
    assert out == "" and err == "", (out, err)  # neither loader said a word
    damping = np.array([float(b.damping or 0) for b in model.spec.bodies])
    worst = 0.0
    for x, tau in _states(np.random.default_rng(7), n):
        u = tau[[k - 1 for k in spec.controls]]
        tau = np.zeros(n)
        tau[[k - 1 for k in spec.controls]] = u
        ours = model.c.qdd(x, u if spec.controls else None, params=values or None)
        worst = max(worst, _relative(ours, pinocchio.qdd(x, tau - damping * x[n:])))
        if mj is not None:
            worst = max(worst, _relative(ours, mj.qdd(x, tau)))
    print(f"{name}: exported, worst {worst:.1e}{'' if mj else ' (URDF only)'}")
    assert worst <= 1e-10


RANDOM_ARM = random_spec_text(np.random.default_rng(45), 5, name="random_arm", gyro=False, controls=(2, 5), offsets=True)


# (the Panda, imported from URDF as the UR5 is, in make test-all only)
@pytest.mark.parametrize("name", tiered(["double_pendulum", "furuta", "ur5", "panda", "random_arm"],
                                         {"double_pendulum", "furuta", "ur5", "random_arm"}))
def test_spec_to_urdf_to_spec_is_the_same_model(name, make_model, tmp_path):
    """The same φ̈ to 1e-14; exactly the same where every angle is a multiple of π/2 or written
    exactly (the examples), a few 1e-16 for random θ and offsets."""
    spec = parse_spec(RANDOM_ARM) if name == "random_arm" else load_spec(ROOT / "specs" / f"{name}.toml")
    model = make_model(spec)
    text, _ = exchange.export_text(spec, f"{name}.toml", "urdf", {})
    (tmp_path / "m.urdf").write_text(text)
    # under its own name: where the C comes back the same, the build is the one already made
    again, _ = exchange.import_text(tmp_path / "m.urdf", name=spec.name, controls=bool(spec.controls))
    back = make_model(parse_spec(again))
    worst = 0.0
    for x, tau in _states(np.random.default_rng(11), spec.n):
        u = tau[[k - 1 for k in spec.controls]]
        full = np.zeros(spec.n)
        full[[k - 1 for k in spec.controls]] = u
        ours = model.c.qdd(x, u) if spec.controls else model.c.qdd(x)
        worst = max(worst, _relative(back.c.qdd(x, full) if spec.controls else back.c.qdd(x), ours))
    print(f"{name}: round trip {worst:.1e}")
    assert worst <= 1e-14
