"""Robot descriptions in (gyrochain import) and out (gyrochain export), without a compiler: the
imported examples are what the command writes from the vendored URDFs, the paper's frames are
right (θ, δ, the data in the body frames), and everything a chain cannot be is one line naming the
joint, the link or the field.  (tests/models/test_robots.py compares the models with Pinocchio's
and MuJoCo's.)"""
from __future__ import annotations

import subprocess
import sys

import mpmath as mp
import pytest

from gyrochain import exchange, robot, robotspec, urdf
from gyrochain.errors import SpecError
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT

ROBOTS = ROOT / "specs" / "robots"
PANDA_LOCKS = ["panda_finger_joint1=0.02", "panda_finger_joint2=0.02"]
# the examples imported from the vendored files, with the options that made them
IMPORTED = {"ur5": ("ur5_robot.urdf", {}), "panda": ("panda.urdf", {"locks": PANDA_LOCKS}),
            "planar2dof": ("double_pendulum.urdf", {"name": "planar2dof"})}


@pytest.mark.parametrize("name", sorted(IMPORTED))
def test_imported_examples_are_what_import_writes(name):
    """specs/NAME.toml is byte for byte what `gyrochain import` writes today (like generated/)."""
    file, kw = IMPORTED[name]
    text, _ = exchange.import_text(ROBOTS / file, **kw)
    assert text == (ROOT / "specs" / f"{name}.toml").read_text(), f"remake it: gyrochain import specs/robots/{file} …"


def test_the_chain_frames_follow_the_paper():
    """UR5 at its zero: the shoulder's axis is vertical (θ¹ = π: ê¹₁ up), the next axis is
    perpendicular to it (θ² = ±π/2) and the elbow's parallel to it (θ³ = 0); each body's ê₂ is the
    common perpendicular of its axis and the next; the joint points are the URDF's."""
    ch = robot.chain(urdf.read(ROBOTS / "ur5_robot.urdf"))
    assert [b.joint.name for b in ch.bodies] == ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                                  "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
    pb = robotspec.paper(ch)
    assert robotspec.angle(pb[0].theta) == '"pi"' and robotspec.angle(abs(pb[1].theta)) == '"pi/2"' and robotspec.angle(pb[2].theta) == "0.0"
    assert [float(x) for x in ch.bodies[1].O] == pytest.approx([0, 0.13585, 0.089159], abs=1e-15)
    assert robotspec.number(pb[1].m) == "8.393" and robotspec.number(pb[0].Ic[2]) == "0.010267495893"  # as written


def test_fixed_links_merge_by_the_parallel_axis_theorem(tmp_path):
    """Two links fixed together are one body: mass, centre and inertia about it."""
    f = tmp_path / "two.urdf"
    f.write_text(_urdf(joints=[("j1", "revolute", "base", "a", "0 0 0", "0 1 0"), ("fx", "fixed", "a", "b", "0 0 -2", "1 0 0")],
                       inertial={"a": ("1", "0 0 0"), "b": ("3", "0 0 0")}))
    ch = robot.chain(urdf.read(f))
    (b,) = ch.bodies
    assert b.links == ("a", "b") and mp.mpf(b.m) == 4
    assert [float(x) for x in b.com] == pytest.approx([0, 0, -1.5])
    # about the centre: their own 0.01 each, and 1·1.5² + 3·0.5² = 3 about x and y
    assert [float(b.Ic[i, i]) for i in range(3)] == pytest.approx([3.02, 3.02, 0.02], rel=1e-15)


def _urdf(joints, inertial, extra: str = "", links=None) -> str:
    names = links or sorted({j[2] for j in joints} | {j[3] for j in joints})
    out = ['<robot name="t">']
    for n in names:
        if n in inertial:
            m, xyz = inertial[n]
            out.append(f'<link name="{n}"><inertial><origin xyz="{xyz}"/><mass value="{m}"/>'
                       '<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>')
        else:
            out.append(f'<link name="{n}"/>')
    for name, kind, parent, child, xyz, axis in joints:
        out.append(f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
                   f'<origin xyz="{xyz}"/><axis xyz="{axis}"/></joint>')
    return "\n".join(out + [extra, "</robot>"])


TWO_ARMS = [("j1", "revolute", "base", "a", "0 0 0", "0 0 1"), ("l", "revolute", "a", "left", "0 1 0", "1 0 0"),
            ("r", "revolute", "a", "right", "0 -1 0", "1 0 0")]
MASS = {k: ("1", "0 0 -0.1") for k in ("a", "left", "right", "b", "c")}


@pytest.mark.parametrize("case, words", [
    ("prismatic", "joint 'p': a prismatic joint: the paper's chain has revolute joints only (lock it with --lock p=VALUE)"),
    ("floating", "joint 'p': a floating joint"),
    ("planar", "joint 'p': a planar joint"),
    ("mimic", "joint 'm': mimics 'j1'"),
    ("branch", "--tip: the movable joints branch at l, r: give --tip, one of left, right"),
    ("loop", "joint 'again': closes a loop: link 'a' is already the child of joint 'j1'"),
    ("massless", "link 'b': joint 'j2' turns no mass"),
    ("nan", "<origin xyz>: 'nan' is not a finite number"),
    ("xml", "not well-formed XML"),
    ("doctype", "has a document type declaration"),
    ("negative mass", "<mass value>: a negative mass (-1)"),
    ("inertia", "link 'a': <inertia>: the body of joint 'j1' is not physically possible (of its links, a alone is not)"),
    ("missing link", "joint 'j1': names the link 'nowhere'"),
    ("zero axis", "<axis xyz>: a zero axis has no direction"),
    ("not urdf", "MuJoCo does not compile it: XML Error"),
    ("no revolute", "no revolute or continuous joint below base"),
    ("other xml", "the root element is <svg>, not <robot>: not a URDF"),
])
def test_what_a_chain_cannot_be_is_one_line(case, words, tmp_path):
    j1 = ("j1", "revolute", "base", "a", "0 0 0", "0 0 1")
    text = {
        "prismatic": _urdf([j1, ("p", "prismatic", "a", "b", "0 0 0", "0 0 1")], MASS),
        "floating": _urdf([j1, ("p", "floating", "a", "b", "0 0 0", "0 0 1")], MASS),
        "planar": _urdf([j1, ("p", "planar", "a", "b", "0 0 0", "0 0 1")], MASS),
        "mimic": _urdf([j1, ("m", "revolute", "a", "b", "0 0 0", "0 1 0")], MASS).replace(
            '<joint name="m" type="revolute">', '<joint name="m" type="revolute"><mimic joint="j1"/>'),
        "branch": _urdf(TWO_ARMS, MASS),
        "loop": _urdf([j1, ("b1", "revolute", "a", "b", "0 0 0", "1 0 0"), ("again", "revolute", "b", "a", "0 0 0", "1 0 0")], MASS),
        "massless": _urdf([j1, ("j2", "revolute", "a", "b", "0 0 0", "1 0 0")], {"a": MASS["a"]}),
        "nan": _urdf([j1], MASS).replace('<origin xyz="0 0 0"/><axis', '<origin xyz="0 nan 0"/><axis'),
        "xml": _urdf([j1], MASS)[:-20],
        "doctype": '<!DOCTYPE r [<!ENTITY a "aaaa">]>' + _urdf([j1], MASS),
        "negative mass": _urdf([j1], {"a": ("-1", "0 0 0")}),
        "inertia": _urdf([j1], MASS).replace('ixx="0.01"', 'ixx="0.05"'),
        "missing link": _urdf([j1], MASS, links=["base"]).replace('child link="a"', 'child link="nowhere"'),
        "zero axis": _urdf([("j1", "revolute", "base", "a", "0 0 0", "0 0 0")], MASS),
        "not urdf": "<mujoco><worldbody><nonsense/></worldbody></mujoco>",
        "no revolute": _urdf([("f", "fixed", "base", "a", "0 0 0", "1 0 0")], MASS),
        "other xml": "<svg/>",
    }[case]
    f = tmp_path / "r.urdf"
    f.write_text(text)
    with pytest.raises(SpecError) as err:
        exchange.import_text(f)
    assert words in str(err.value) and "\n" not in str(err.value), str(err.value)


def test_lock_merges_the_locked_joint_and_tip_picks_a_branch(tmp_path):
    f = tmp_path / "t.urdf"
    f.write_text(_urdf(TWO_ARMS, MASS))
    text, lines = exchange.import_text(f, tip="left", locks=["r=0.5"])
    spec = parse_spec(text)
    assert spec.n == 2 and "locked at the values given: r = 0.5" in "\n".join(lines) and "right" in "\n".join(lines)
    # the locked arm's mass is in body 1 (1 + 1 kg)
    assert float(spec.bodies[0].m) == 2.0
    text, lines = exchange.import_text(f, tip="left")  # the other arm locked at its zero, in one go
    assert parse_spec(text).n == 2 and "locked at their zero (off the chain, or sliding): r" in "\n".join(lines)
    assert "# locked at their zero (off the chain from base to left, or sliding): r" in text
    with pytest.raises(SpecError, match="--tip base: no revolute or continuous joint below base on the way to base"):
        exchange.import_text(f, tip="base")
    with pytest.raises(SpecError, match="--lock r: the joint is neither below the base left nor between it and the root"):
        exchange.import_text(f, base="left", locks=["r=0.1"])
    with pytest.raises(SpecError, match="--lock nope: no such joint"):
        exchange.import_text(f, tip="left", locks=["nope=1"])
    with pytest.raises(SpecError, match="expected joint=number"):
        exchange.import_text(f, tip="left", locks=["r=x"])


def test_the_command_writes_a_spec_the_other_commands_accept(tmp_path):
    out = tmp_path / "arm.toml"
    r = subprocess.run([sys.executable, "-m", "gyrochain", "import", str(ROBOTS / "ur5_robot.urdf"), "-o", str(out)],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0 and "imported ur5" in r.stdout and r.stderr == "", r.stderr
    assert load_spec(out).n == 6
    r = subprocess.run([sys.executable, "-m", "gyrochain", "import", str(ROBOTS / "ur5_robot.urdf"), "-o", str(out)],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "exists; pass --force" in r.stderr


@pytest.mark.parametrize("name, to, words", [
    ("gimbal", "urdf", "body[2].lambda: a rotor's relative angular momentum has no element"),
    ("kapitza", "mjcf", "base: a moving platform has no element"),
    ("ziegler", "mjcf", "body[2].force: a load has no element"),
    ("double_pendulum_point", "mjcf", "body[1].I_c: MuJoCo's compiler refuses"),
])
def test_export_refuses_what_the_format_cannot_hold(name, to, words):
    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    with pytest.raises(SpecError) as err:
        exchange.export_text(spec, f"{name}.toml", to, dict(spec.values))
    assert words in str(err.value), str(err.value)


def test_a_spring_goes_to_mjcf_not_urdf():
    text = (ROOT / "specs" / "double_pendulum.toml").read_text().replace("[[body]]", "[[body]]\nspring = 2.0\nrest = 0.1", 1)
    spec = parse_spec(text)
    with pytest.raises(SpecError, match="body\\[1\\].spring: URDF has no joint stiffness"):
        exchange.export_text(spec, "dp.toml", "urdf", {})
    xml, _ = exchange.export_text(spec, "dp.toml", "mjcf", {})
    assert 'stiffness="2.0" springref="0.1"' in xml
