"""MJCF in, through MuJoCo's own compiler: every example that MJCF can hold, exported and imported
again, and nine models of DeepMind's Control Suite (tests/mjcf) give the φ̈ of MuJoCo's
``mj_forward`` on the same file to 1e-10.  Where the chain is part of a larger model (the cart of
the cart-pole held at its place), MuJoCo's equations are cut to the chain's joints, the others at
rest: M_cc φ̈ = τ + passive − bias.  The spec is evaluated by the independent model
(gyrochain/derive/reference.py) and, in ``make test-all``, by its emitted C."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain import exchange, pipeline, reference, robot
from gyrochain.errors import SpecError
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, example_params, tiered
from simulators import Mj

mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco; make test installs it) compiles MJCF")

EXPORTABLE = ["double_pendulum", "furuta", "furuta_sym", "ur5", "panda", "planar2dof", "cable64"]
SUITE = ROOT / "tests" / "mjcf" / "dm_control"
STATES = 50


@pytest.fixture(autouse=True)
def _elsewhere(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo may write MUJOCO_LOG.TXT in the working folder


def worst(path, target: str = "reference", **kw) -> tuple[float, int]:
    """The largest relative difference of φ̈ from MuJoCo's over the states: of the imported spec
    evaluated by the independent model ("reference") or of its emitted C ("C")."""
    text, _ = exchange.import_text(path, **kw)
    spec = parse_spec(text)
    ch = reference.numeric(spec)
    if target == "C":
        cm, _ = pipeline.compiled(spec)
        assert len(spec.controls) == spec.n, "every joint of an imported chain has its torque"
        ours = lambda x, tau: cm.qdd(x, tau)  # noqa: E731
    else:
        ours = lambda x, tau: reference.qdd(ch, x, tau)  # noqa: E731
    names = [b.joint.name for b in robot.chain(exchange.read_description(path), kw.get("base"), kw.get("tip")).bodies]
    theirs = Mj.of_file(path, names)
    rng, n, out = np.random.default_rng(n_ := spec.n), spec.n, 0.0
    for _ in range(STATES):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        tau = rng.normal(size=n) * 0.5
        a, b = ours(x, tau), theirs.qdd(x, tau)
        out = max(out, float(np.max(np.abs(a - b)) / np.max(np.abs(b))))
    return out, n_


TARGETS = ("reference", "C")  # make test: the independent model; make test-all: the emitted C too (a build each)


@pytest.mark.parametrize("name, target", tiered([(e, t) for e in EXPORTABLE for t in TARGETS], {"reference"},
                                                key=lambda c: c[1], rows=True))
def test_an_exported_example_comes_back_as_mujoco_simulates_it(name, target, tmp_path):
    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    values = example_params(name) or {}
    try:
        text, _ = exchange.export_text(spec, f"{name}.toml", "mjcf", values)
    except SpecError as exc:  # a point mass is refused for MuJoCo, and said so
        assert "I_c: MuJoCo's compiler refuses" in str(exc)
        pytest.skip(str(exc))
    path = tmp_path / f"{name}.xml"
    path.write_text(text)
    err, n = worst(path, target)
    print(f"{name}.xml ({target}): n = {n}, MuJoCo {err:.1e}")
    assert err <= 1e-10


SUITE_MODELS = [("pendulum.xml", {}), ("acrobot.xml", {}), ("reacher.xml", {}), ("cartpole.xml", {"base": "cart"}),
                # motor armature (and springs, dampers, limits) as the authors wrote them
                ("cheetah.xml", {"base": "torso", "tip": "bfoot"}), ("hopper.xml", {"base": "torso", "tip": "foot"}),
                ("walker.xml", {"base": "torso", "tip": "left_foot"}),
                # joints' reference poses (ref), and a model that disables gravity
                ("finger.xml", {"tip": "distal"}), ("manipulator.xml", {"tip": "fingertip"})]
STYLED = ROOT / "tests" / "mjcf" / "styled"  # models written as Menagerie's and the Control Suite's are


@pytest.mark.parametrize("file, kw, target", tiered([(*m, t) for m in SUITE_MODELS for t in TARGETS], {"reference"},
                                                    key=lambda c: c[-1], rows=True))
def test_control_suite_models_are_mujoco_s(file, kw, target):
    err, n = worst(SUITE / file, target, **kw)
    print(f"{file} ({target}): n = {n}, MuJoCo {err:.1e}")
    assert err <= 1e-10


def test_what_the_spec_cannot_hold_is_said(tmp_path):
    """The cart-pole's slider above the base is held; gravity not along −z is refused; MuJoCo's own
    compiler errors are one line."""
    text, lines = exchange.import_text(SUITE / "cartpole.xml", base="cart")
    assert "slider" in text and "held at their zero" in text
    f = tmp_path / "arm.xml"
    plain = '<body name="a" pos="0 0 0"><joint name="j" axis="0 1 0"/><geom size=".1" pos="0 0 -.5"/></body>'
    f.write_text(f'<mujoco><option gravity="0 -9.81 0"/><worldbody>{plain}</worldbody></mujoco>')
    with pytest.raises(SpecError, match="<option gravity>: \\(0 -9.81 0\\) is not along -z: .*--g sets only its magnitude"):
        exchange.import_text(f)
    # gymnasium's inverted double pendulum: a hair off −z, read along −z and said so
    f.write_text(f'<mujoco><option gravity="1e-05 0 -9.81"/><worldbody>{plain}</worldbody></mujoco>')
    text, _ = exchange.import_text(f)
    assert float(parse_spec(text).g) == 9.81 and "# gravity (1e-05 0 -9.81) read as 9.81 along -z: its horizontal part, 1e-06 of it, left out" in text
    f.write_text(f'<mujoco><option gravity="2e-3 0 -9.81"/><worldbody>{plain}</worldbody></mujoco>')
    with pytest.raises(SpecError, match="is not along -z"):
        exchange.import_text(f)
    f.write_text("<mujoco><worldbody><body><joint type='hinge' axis='0 0 0'/></body></worldbody></mujoco>")
    with pytest.raises(SpecError, match="MuJoCo does not compile it") as err:
        exchange.import_text(f)
    assert "\n" not in str(err.value)


def test_two_joints_in_one_body_and_a_joint_off_the_origin(tmp_path):
    """MuJoCo composes a body's joints in order, each about its axis through its point: a gimbal
    in one body, and a hinge placed away from the body's origin."""
    f = tmp_path / "gimbal.xml"
    f.write_text("""<mujoco model="two in one"><worldbody>
      <body name="ring" pos="0 0 1" euler="10 20 30">
        <joint name="outer" axis="1 0 0" pos="0.1 0 0" damping="0.2"/>
        <joint name="inner" axis="0 1 0.3" pos="0 0.05 -0.02" stiffness="3" springref="0.4"/>
        <geom type="box" size=".1 .2 .3" pos=".05 0 -.4" mass="2"/>
        <body name="tip" pos="0 0 -.8"><joint name="last" axis="0 0 1" pos="0 .1 0"/>
          <geom type="capsule" fromto="0 0 0 .3 .1 -.2" size=".05"/></body>
      </body></worldbody></mujoco>""")
    err, n = worst(f)
    assert n == 3 and err <= 1e-10, err


@pytest.mark.parametrize("file, target", tiered([(f, t) for f in ("arm_armature.xml", "cheetah_leg.xml") for t in TARGETS],
                                                {"reference"}, key=lambda c: c[-1], rows=True))
def test_armature_and_reference_poses_as_the_authors_wrote_them(file, target):
    """Joint classes with motor armature (Menagerie's arms), ``ref`` poses and springs about
    springref (the Control Suite's cheetah): imported as written, the spec's angles are MuJoCo's
    qpos, and φ̈ is ``mj_forward``'s qacc."""
    text, _ = exchange.import_text(STYLED / file)
    assert "armature = " in text and "ref " in text
    err, n = worst(STYLED / file, target)
    print(f"{file} ({target}): n = {n}, MuJoCo {err:.1e}")
    assert err <= 1e-10


def test_armature_goes_back_out_to_mjcf(tmp_path):
    """A spec's armature is written to MJCF's joints (MuJoCo's φ̈ equal to the spec's again), and
    refused for URDF, which has no element for it."""
    spec = parse_spec(exchange.import_text(STYLED / "arm_armature.xml")[0])
    text, _ = exchange.export_text(spec, "arm.toml", "mjcf", {})
    assert text.count('armature="') == spec.n
    path = tmp_path / "back.xml"
    path.write_text(text)
    err, n = worst(path)
    assert n == spec.n and err <= 1e-10, err
    with pytest.raises(SpecError, match=r"body\[1\]\.armature: URDF has no motor armature"):
        exchange.export_text(spec, "arm.toml", "urdf", {})


def test_a_reference_pose_off_the_chain_or_locked_is_no_refusal(tmp_path):
    """A joint's ref off the chain (held at its zero) or locked (at the value given, in MuJoCo's
    qpos) stops nothing."""
    f = tmp_path / "two.xml"
    f.write_text("""<mujoco><compiler angle="radian"/><worldbody>
      <body name="target" pos=".1 0 .5"><joint name="tx" type="slide" axis="1 0 0" ref="0.1"/>
        <joint name="ty" axis="0 0 1" ref="0.2"/><geom size=".01" mass=".1"/></body>
      <body name="arm" pos="0 0 1"><joint name="a1" axis="0 1 0" ref="0.3"/><geom type="capsule" fromto="0 0 0 .3 0 0" size=".02"/>
        <body name="hand" pos=".3 0 0"><joint name="a2" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 .2 0 0" size=".02"/></body>
      </body></worldbody></mujoco>""")
    for kw in ({"tip": "hand"}, {"tip": "hand", "locks": ["tx=0.1", "ty=0.2"]}):
        text, _ = exchange.import_text(f, **kw)
        assert "ref 0.3" in text
    err, n = worst(f, tip="hand")
    assert n == 2 and err <= 1e-10, err


def test_limits_go_out_and_come_back(tmp_path):
    """The spec's limits exported: MJCF's range and actuatorfrcrange (velocity said dropped),
    URDF's revolute <limit>; imported again, the spec's limits are the same (φ̈ too)."""
    spec = load_spec(ROOT / "specs" / "panda.toml")
    want = [dict(b.limits) for b in spec.bodies]
    for to, keep in (("mjcf", ("lower", "upper", "effort")), ("urdf", ("lower", "upper", "effort", "velocity"))):
        text, said = exchange.export_text(spec, "panda.toml", to, {})
        assert ("dropped: the joints' velocity limits" in "\n".join(said)) == (to == "mjcf")
        path = tmp_path / f"panda.{'xml' if to == 'mjcf' else 'urdf'}"
        path.write_text(text)
        back = parse_spec(exchange.import_text(path)[0])
        assert [dict(b.limits) for b in back.bodies] == [{k: v for k, v in w.items() if k in keep} for w in want], to
        if to == "mjcf":
            err, _ = worst(path)
            assert err <= 1e-10, err
