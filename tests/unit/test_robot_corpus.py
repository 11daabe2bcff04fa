"""Every URDF of the corpus (tests/robots: the 69 descriptions of example-robot-data) answers: a
spec, or one line naming what cannot be modelled; never an internal error, and quickly.  The tree
that ``import --list`` prints names the leaves a chain can end at, and ``--tip`` at any of them
locks the rest of the tree in one go."""
from __future__ import annotations

import time

import numpy as np
import pytest

from gyrochain import exchange, robot
from gyrochain.errors import SpecError
from gyrochain.spec import parse_spec
from conftest import ROOT

CORPUS = sorted((ROOT / "tests" / "robots").glob("*/*.urdf"))


def leaves(path) -> list[tuple[str, int]]:
    """The leaves ``import --list`` names, with their number of revolute joints, most first."""
    text = exchange.tree_text(path)
    if "leaves a chain can end at" not in text:
        return []
    rows = text.split("leaves a chain can end at", 1)[1].splitlines()[1:]
    out = [(row.strip().rsplit(" (", 1)[0], int(row.strip().rsplit("(", 1)[1][:-1])) for row in rows]
    return sorted(out, key=lambda p: -p[1])


def test_the_corpus_is_the_69_descriptions():
    assert len(CORPUS) == 69


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: p.name)
def test_every_description_answers_in_one_line_or_a_spec(path):
    t0 = time.perf_counter()
    try:
        text, lines = exchange.import_text(path)
        parse_spec(text)
        assert lines[0].startswith("imported ")
    except SpecError as err:
        assert "\n" not in str(err) and str(err).startswith(str(path)), str(err)
    assert time.perf_counter() - t0 < 10


def test_a_leg_of_a_quadruped_in_one_command():
    """Go1: the trunk's own inertia is impossible (principal moments −2e-22, 9e-23, 3e-6) but it is
    the platform's, which plays no part; --tip locks the other three legs at once and says so."""
    path = ROOT / "tests" / "robots" / "go1_description" / "go1.urdf"
    text, lines = exchange.import_text(path, tip="FL_foot")
    spec = parse_spec(text)
    assert spec.n == 3
    said = "\n".join(lines)
    assert "locked at their zero" in said and "FR_hip_joint" in said
    for other in ("FR_calf_joint", "RL_hip_joint", "RR_thigh_joint"):
        assert other in text  # the spec lists every joint it locked
    with pytest.raises(SpecError, match="the movable joints branch at .*give --tip"):
        exchange.import_text(path)


def test_an_arm_of_a_humanoid_with_a_lock_value(tmp_path):
    path = ROOT / "tests" / "robots" / "talos_data" / "talos_full_v2.urdf"
    text, lines = exchange.import_text(path, tip="arm_left_7_link", locks=["torso_2_joint=0.1"])
    spec = parse_spec(text)
    assert spec.n == 8 and "torso_2_joint = 0.1" in text
    with pytest.raises(SpecError, match=r"--lock torso_2_joint=9: outside the joint's limits"):
        exchange.import_text(path, tip="arm_left_7_link", locks=["torso_2_joint=9"])


def test_a_fixed_joint_s_axis_is_ignored_as_the_format_says():
    """SO-101's fixed joints are written with <axis xyz="0 0 0"/>, which URDF ignores."""
    text, _ = exchange.import_text(ROOT / "tests" / "robots" / "so_arm_description" / "so101.urdf")
    assert parse_spec(text).n == 6


def test_a_massless_link_with_an_inertia_adds_it():
    """Bolt's feet have mass 0 and an inertia; Pinocchio adds it, and so do we."""
    path = ROOT / "tests" / "robots" / "bolt_description" / "bolt.urdf"
    desc = exchange.read_description(path)
    ch = robot.chain(desc, tip="FL_FOOT")
    foot = desc.links["FL_FOOT"]
    assert float(foot.m) == 0 and float(foot.I[0]) > 0
    without = robot.chain(robot.Description(desc.name, desc.source, {**desc.links, "FL_FOOT": None}, desc.joints),
                          tip="FL_FOOT")
    assert abs(float(ch.bodies[-1].Ic[0, 0] - without.bodies[-1].Ic[0, 0]) - float(foot.I[0])) < 1e-15


@pytest.mark.parametrize("path", [p for p in CORPUS if p.name in ("solo.urdf", "baxter.urdf", "iris_simple.urdf")],
                         ids=lambda p: p.name)
def test_the_tree_names_its_leaves(path):
    text = exchange.tree_text(path)
    assert text.splitlines()[0].startswith(f"{path.name}: robot ")
    desc = exchange.read_description(path)
    assert all(f"  {name}" in text for name in desc.links)  # every link, on a line of its own
    for leaf, n in leaves(path)[:3]:
        assert len(robot.chain(desc, tip=leaf).bodies) == n


def test_the_format_as_it_is_written(tmp_path):
    """Two trees (one chosen with --base), unicode and comments, a mesh-only link, a fixed joint's
    zero axis, and the elements the dynamics does not read (transmission, gazebo, calibration,
    safety_controller): read or ignored as the format says, never a crash."""
    f = tmp_path / "roots.urdf"
    f.write_text("""<?xml version="1.0"?>
<!-- two trees; unicode: ✓ -->
<robot name="twö">
  <link name="a"/>
  <link name="b"><inertial><mass value="1"/><origin xyz="0 0 -0.5"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://x/b.stl"/></geometry></visual></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/>
    <safety_controller k_velocity="1"/><calibration rising="0"/><mimic_not joint="x"/></joint>
  <link name="c"/><link name="d"><visual><geometry><mesh filename="d.stl"/></geometry></visual></link>
  <joint name="f" type="fixed"><parent link="c"/><child link="d"/><axis xyz="0 0 0"/></joint>
  <transmission name="t"><type>x</type><joint name="j"/></transmission>
  <gazebo reference="b"><material>Red</material></gazebo>
</robot>""", encoding="utf-8")
    with pytest.raises(SpecError, match="2 links have no parent \\(a, c\\): .*give --base LINK"):
        exchange.import_text(f)
    text, _ = exchange.import_text(f, base="a")
    assert parse_spec(text).n == 1 and "left out (not below the base a): c, d" in text
    tree = exchange.tree_text(f)
    assert "1 degree of freedom" in tree and "  b (1)" in tree


def _legged(tmp_path, second_root: str | None = None):
    """A trunk on a floating joint with two legs (a quadruped's root), and a tail on the world
    whose root joint is ``second_root`` (None: no tail)."""
    leg = lambda side, y: f"""
  <link name="{side}_hip"><inertial><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{side}_hip_joint" type="revolute"><parent link="trunk"/><child link="{side}_hip"/><origin xyz="0.2 {y} 0"/><axis xyz="1 0 0"/></joint>
  <link name="{side}_calf"><inertial><origin xyz="0 0 -0.1"/><mass value="0.3"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{side}_knee" type="revolute"><parent link="{side}_hip"/><child link="{side}_calf"/><origin xyz="0 0 -0.2"/><axis xyz="0 1 0"/></joint>"""  # noqa: E731
    tail = "" if second_root is None else f"""  <link name="tail"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="tail_root" type="{second_root}"><parent link="world"/><child link="tail"/></joint>
  <link name="tip"><inertial><origin xyz="0 0 -0.1"/><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="tail_joint" type="revolute"><parent link="tail"/><child link="tip"/><axis xyz="0 1 0"/></joint>
"""
    f = tmp_path / "legged.urdf"
    f.write_text(f"""<robot name="legged"><link name="world"/>
  <link name="trunk"><inertial><mass value="5"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="root" type="floating"><parent link="world"/><child link="trunk"/></joint>{leg("FL", 0.1)}{leg("FR", -0.1)}
{tail}</robot>""")
    return f


def test_a_floating_root_is_shown_with_the_base_it_needs(tmp_path):
    """Below a floating joint a chain needs --base: --list shows a command that works, and a plain
    import or a --tip alone names the same command, with the leaves it can end at."""
    f = _legged(tmp_path, second_root="floating")
    tree = exchange.tree_text(f)
    assert "(`import legged.urdf [--base BASE] --tip LINK`" in tree
    rows = tree.split("leaves a chain can end at", 1)[1].splitlines()[1:]
    assert "  FL_calf (2; --base trunk)" in rows and "  tip (1; --base tail)" in rows
    for row in rows:  # each as the list says
        leaf, rest = row.strip().split(" (", 1)
        text, _ = exchange.import_text(f, base=rest.split("--base ")[1][:-1], tip=leaf)
        assert parse_spec(text).n == int(rest.split(";")[0])
    one = _legged(tmp_path)  # every leaf below the trunk's floating joint
    tree = exchange.tree_text(one)
    assert "(`import legged.urdf --base trunk --tip LINK`, the chain below the floating joint; " in tree
    for tip in (None, "FL_calf"):
        with pytest.raises(SpecError, match=r"joint 'root': a floating joint: .*\(the chain starts below it: "
                                            r"`import legged.urdf --base trunk --tip LINK`, LINK one of FR_calf, FL_calf\)"):
            exchange.import_text(one, tip=tip)


VENDORED = CORPUS + sorted((ROOT / "specs" / "robots").glob("*.urdf"))


def _written_limits(path, joint: str) -> dict:
    """The <limit> of ``joint`` as the file writes it, read here with ElementTree: what a spec keeps
    of it (a range where lower < upper, not for a continuous joint; a positive speed and effort)."""
    import xml.etree.ElementTree as ET

    el = next(j for j in ET.parse(path).getroot().findall("joint") if j.get("name") == joint)
    lim = el.find("limit")
    got = {k: float(lim.get(k)) for k in ("lower", "upper", "velocity", "effort") if lim is not None and lim.get(k) is not None}
    out = {}
    if el.get("type") != "continuous" and "lower" in got and "upper" in got and got["lower"] < got["upper"]:
        out.update(lower=got["lower"], upper=got["upper"])
    return {**out, **{k: got[k] for k in ("velocity", "effort") if k in got and got[k] > 0}}


def test_the_limits_of_every_vendored_urdf_are_data_of_its_spec():
    """Every vendored URDF, imported (to its first leaf where the tree branches): each joint's
    <limit> is the spec's ``limits``, and the header's initializers, MANIFEST.json's rows and the
    CasADi model's bounds are made from them (one full generate of a robot checks the files in
    tests/tools/test_casadi.py)."""
    from gyrochain.casadi.external import bounds_of
    from gyrochain.chainspec.tables import spec_limits
    from gyrochain.printers import _limits_json
    from gyrochain.printers.c import limit_defines

    seen = 0
    for path in VENDORED:
        try:
            tip = (leaves(path) or [(None, 0)])[0][0]
            text, _ = exchange.import_text(path, tip=tip)
        except SpecError:
            continue  # a description the chain cannot be (test_every_description_answers_in_one_line_or_a_spec)
        spec = parse_spec(text)
        names = [b.joint.name for b in robot.chain(exchange.read_description(path), None, tip).bodies]
        written = [_written_limits(path, j) for j in names]
        assert [dict(b.limits) for b in spec.bodies] == written, path
        lim = spec_limits(spec)
        defines = {key: value for key, value, _ in limit_defines(lim)}
        assert defines["HAS_LIMITS"] == int(any(written))
        for key, macro, none in (("lower", "PHI_LOWER", "-HUGE_VAL"), ("upper", "PHI_UPPER", "HUGE_VAL"),
                                 ("velocity", "PHIDOT_MAX", "HUGE_VAL"), ("effort", "EFFORT_MAX", "HUGE_VAL")):
            if any(key in w for w in written):
                assert defines[macro] == "{" + ", ".join(repr(w[key]) if key in w else none for w in written) + "}", (path, key)
            else:
                assert macro not in defines
        assert [{k: v for k, v in row.items() if k != "joint"} for row in _limits_json(spec)] == written
        b = bounds_of(lim, spec.n, spec.controls)
        n = spec.n
        for k, w in enumerate(written):
            assert (b.lbx[k], b.ubx[k]) == (w.get("lower", -np.inf), w.get("upper", np.inf))
            assert (b.lbx[n + k], b.ubx[n + k]) == (-w.get("velocity", np.inf), w.get("velocity", np.inf))
            assert (b.lbu[k], b.ubu[k]) == (-w.get("effort", np.inf), w.get("effort", np.inf))  # every joint controlled
        seen += any(written)
    assert seen >= 60, seen


def test_a_free_object_beside_the_arm_is_not_offered_as_a_base(tmp_path):
    """A scene: an arm on the world, and an object on a floating joint with nothing below it. The
    plain import's line must not suggest --base OBJECT (nothing turns there), and --tip works."""
    f = tmp_path / "scene.urdf"
    inertial = '<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'
    f.write_text(f"""<robot name="scene"><link name="world"/><link name="arm">{inertial}</link><link name="box">{inertial}</link>
  <joint name="shoulder" type="revolute"><parent link="world"/><child link="arm"/><axis xyz="0 1 0"/></joint>
  <joint name="free" type="floating"><parent link="world"/><child link="box"/></joint></robot>""")
    with pytest.raises(SpecError, match="joint 'free': a floating joint: .*nothing turns below it: --tip LINK takes a chain"):
        exchange.import_text(f)
    assert parse_spec(exchange.import_text(f, tip="arm")[0]).n == 1
