"""The chains of the URDF corpus (tests/robots: 69 real robots) against Pinocchio.  For every
description with a leaf that revolute joints reach, the chain ``import --tip LEAF`` writes (the leaf
with the most such joints that imports) has the φ̈ of Pinocchio's ABA on its reduced model
(``buildReducedModel``, every other joint locked at the same value), to 1e-10 at 50 random states
and torques: the spec evaluated by the independent model (gyrochain/derive/reference.py), and, in
``make test-all``, the emitted C of the same spec, generated and compiled as users get it.  A chain
from a link inside the tree (``--base``) keeps gravity along the world's −z."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain import exchange, pipeline, reference, robot
from gyrochain.errors import SpecError
from gyrochain.spec import parse_spec
from conftest import ROOT, tiered
from simulators import Pin

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin; make test installs it) checks the corpus")

CORPUS = sorted((ROOT / "tests" / "robots").glob("*/*.urdf"))
STATES = 50
# what the corpus holds that the paper's chain cannot be, and the line that says so (none now:
# human.urdf's massless frames between joints, its ball joints, are bodies of mass 0)
REFUSED: dict = {}


def _leaves(path):
    text = exchange.tree_text(path)
    if "leaves a chain can end at" not in text:
        return []
    rows = text.split("leaves a chain can end at", 1)[1].splitlines()[1:]
    return sorted(((r.strip().rsplit(" (", 1)[0], int(r.strip().rsplit("(", 1)[1][:-1])) for r in rows), key=lambda p: -p[1])


def worst(path, tip=None, base=None, locks=(), target: str = "reference") -> tuple[float, int]:
    """The largest relative difference of φ̈ (imported spec against Pinocchio) over the states;
    ``target``: the spec evaluated by the independent model ("reference") or its emitted C ("C")."""
    text, _ = exchange.import_text(path, base=base, tip=tip, locks=list(locks))
    spec = parse_spec(text)
    ch = reference.numeric(spec)
    if target == "C":
        cm, _ = pipeline.compiled(spec)
        qdd = lambda x, tau: cm.qdd(x, tau[[k - 1 for k in spec.controls]] if spec.controls else None)  # noqa: E731
        assert len(spec.controls) == spec.n, "every joint of an imported chain has its torque"
    else:
        qdd = lambda x, tau: reference.qdd(ch, x, tau)  # noqa: E731
    names = [b.joint.name for b in robot.chain(exchange.read_description(path), base, tip,
                                                 exchange.locks_of(locks)).bodies]
    other = Pin(path, names, exchange.locks_of(locks), robot.GRAVITY)
    rng, n = np.random.default_rng(len(names)), spec.n
    damping = np.array([float(b.damping or 0) for b in spec.bodies])
    out = 0.0
    for _ in range(STATES):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        tau = rng.normal(size=n) * 5.0
        ours, theirs = qdd(x, tau), other.qdd(x, tau - damping * x[n:])
        out = max(out, float(np.max(np.abs(ours - theirs)) / np.max(np.abs(theirs))))
    return out, n


# make test holds the independent model's φ̈ of every chain to Pinocchio; make test-all the emitted C's too
# (a build of C each)
TARGETS = ("reference", "C")


@pytest.mark.parametrize("path, target", tiered([(p, t) for p in CORPUS for t in TARGETS], {"reference"}, key=lambda c: c[1], rows=True),
                         ids=[f"{p.parent.name}/{p.name}-{t}" for p in CORPUS for t in TARGETS])
def test_one_chain_of_every_robot_is_pinocchio_s(path, target):
    try:
        leaves = _leaves(path)
    except SpecError as err:  # not a tree we can list (a description with no link)
        assert "\n" not in str(err)
        return
    refusals = []
    for leaf, _ in leaves:
        try:
            err, n = worst(path, tip=leaf, target=target)
        except SpecError as exc:
            refusals.append(str(exc))
            continue
        print(f"{path.name} --tip {leaf} ({target}): n = {n}, Pinocchio {err:.1e}")
        assert err <= 1e-10, (leaf, err)
        assert path.name not in REFUSED
        return
    if leaves:  # only the refusals the corpus is known to need, each one line
        assert path.name in REFUSED and all(REFUSED[path.name] in r and "\n" not in r for r in refusals), refusals


INSIDE = [
    ("talos_data/talos_full_v2.urdf", "torso_2_link", "arm_left_7_link", ()),
    ("talos_data/talos_full_v2.urdf", None, "arm_right_7_link", ("torso_1_joint=0.3", "torso_2_joint=-0.2")),
    ("baxter_description/baxter.urdf", "torso", "left_hand_link", ()),
    ("tiago_description/tiago.urdf", "base_footprint", "arm_7_link", ("torso_lift_joint=0.2",)),
    ("romeo_description/romeo.urdf", "LHipRollLink", "l_sole", ("LHipYaw=0.2", "LHipRoll=-0.25")),
]


@pytest.mark.parametrize("file, base, tip, locks, target",
                         tiered([(*c, t) for c in INSIDE for t in TARGETS], {"reference"}, key=lambda c: c[-1], rows=True))
def test_chains_from_inside_the_tree_with_locks(file, base, tip, locks, target):
    """A base below the root (its attitude from the joints above it), and joints locked at values:
    a turned torso, a lifted one (a prismatic joint)."""
    err, n = worst(ROOT / "tests" / "robots" / file, tip=tip, base=base, locks=locks, target=target)
    print(f"{file} --base {base} --tip {tip} {locks} ({target}): n = {n}, Pinocchio {err:.1e}")
    assert err <= 1e-10
