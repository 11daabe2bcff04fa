"""identify and excite on simulated experiments: the Furuta pendulum (one motor, a passive
pendulum) and a gimbal on a test bench (a motor on each axis, a spinning rotor whose momentum λ
is identified beside the inertias and the joints' damping).  The data are the spec's own C
driven by the excitation, the torques with 1 % noise, the angles through a 4096-count encoder."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import ROOT
from gyrochain import cli, identify, pipeline
from gyrochain.spec import load_spec, parse_spec

FURUTA = ROOT / "specs" / "furuta.toml"
BENCH = """\
name = "gimbal_bench"
description = "the gyroscope of gimbal.toml on a test bench: a motor on each axis, the rotor spinning"
g = 9.81

[[body]]
theta = 0.0
m = 0.5
c = [0.0, 0.0, 0.0]
A = [[0.005, 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.003]]
s = [0.0, 0.0, 0.0]
control = true
damping = 0.002

[[body]]
theta = "pi/2"
m = 1.2
c = [0.0, 0.0, 0.01]
A = [[0.006, 0.0, 0.0], [0.0, 0.006, 0.0], [0.0, 0.0, 0.009]]
lambda = [0.0, 0.0, 0.5]
control = true
damping = 0.002
"""


def _cli(capsys, *words) -> tuple[int, str]:
    try:
        code = cli.main([str(w) for w in words])
    except SystemExit as exc:  # argparse's own refusal (an unknown option)
        code = exc.code
    out = capsys.readouterr()
    return code, out.out + out.err


@pytest.fixture(scope="module")
def furuta_data(tmp_path_factory):
    """30 s to identify from and 10 s of another excitation to validate on."""
    folder = tmp_path_factory.mktemp("furuta")
    for name, seconds, seed in (("data.csv", 30, 0), ("held.csv", 10, 1)):
        assert cli.main(["excite", str(FURUTA), "--period", "5", "--harmonics", "3", "--evaluations", "100",
                         "--u-max", "0.05", "--experiment", str(seconds), "--seed", str(seed), "-o", str(folder / name)]) == 0
    return folder


def _true_beta(spec):
    cm, _ = identify.compiled(spec)
    return cm.base_parameters(cm.standard_parameters())


def test_furuta_is_identified_within_three_standard_errors(furuta_data, tmp_path):
    spec = load_spec(FURUTA)
    lines = []
    fig = identify.run(spec, str(furuta_data / "data.csv"), {}, str(tmp_path / "id.toml"), False,
                       validate=str(furuta_data / "held.csv"), plot=str(tmp_path / "fit.png"), say=lines.append)
    true = _true_beta(spec)
    z = (fig["beta_free"] - true) / fig["se"]
    print("\n".join(lines))
    print("estimate - true in standard errors:", np.round(z, 2))
    assert np.all(np.abs(z) <= 3.0), z
    # held out: the torque the estimates predict and the motion they give under the measured torques
    rel_torque = fig["torque_rms"][0] / fig["torque_scale"][0]
    rel_phi = fig["phi_rms"] / fig["phi_span"]
    print(f"held out: torque RMS error {100 * rel_torque:.2f}% of its RMS, phi RMS error {np.round(100 * rel_phi, 2)}% of the range")
    assert rel_torque <= 0.05 and np.all(rel_phi <= 0.02)
    assert (tmp_path / "fit.png").stat().st_size > 10_000
    # the spec written has physically possible bodies with these base parameters
    written = load_spec(tmp_path / "id.toml")
    cm, _ = pipeline.compiled(written, regressor=True)
    beta_written = cm.base_parameters(cm.standard_parameters(written.values))
    assert np.all(np.abs(beta_written - fig["beta"]) <= max(fig["moved"], 1e-9) * fig["se"] * 1.01 + 1e-15)


def test_the_gimbal_rotor_momentum_is_identified(tmp_path):
    """Every joint controlled: excite designs the joints' trajectories (Swevers' series), the bench
    tracks them with a PD loop; λ² (its y and z components), the dampers and the inertias come out."""
    spec_path = tmp_path / "gimbal_bench.toml"
    spec_path.write_text(BENCH)
    for name, seconds, seed in (("data.csv", 30, 0), ("held.csv", 5, 1)):
        assert cli.main(["excite", str(spec_path), "--period", "8", "--harmonics", "4", "--evaluations", "300",
                         "--phi-max", "1.2", "--phidot-max", "3", "--experiment", str(seconds), "--seed", str(seed),
                         "-o", str(tmp_path / name)]) == 0
    spec = parse_spec(BENCH)
    fig = identify.run(spec, str(tmp_path / "data.csv"), {}, str(tmp_path / "id.toml"), False,
                       validate=str(tmp_path / "held.csv"), say=print)
    _, model = identify.compiled(spec)
    names = [model.reg.params[j].name for j in model.base.columns]
    true = _true_beta(spec)
    z = (fig["beta_free"] - true) / fig["se"]
    print(dict(zip(names, np.round(z, 2))))
    assert {"lamy2", "lamz2", "b1", "b2"} <= set(names)
    assert np.all(np.abs(z) <= 3.0), z
    lam = fig["beta_free"][names.index("lamz2")]
    assert abs(lam - 0.5) <= 3 * fig["se"][names.index("lamz2")] and fig["se"][names.index("lamz2")] < 0.01


@pytest.mark.parametrize("case, rows, words", [
    ("missing column", "t,phi1,u1\n0,0,0\n", "no column 'phi2'"),
    ("t not increasing", "t,phi1,phi2,u1\n0,0,0,0\n0.001,0,0,0\n0.001,0,0,0\n", "t does not increase on line 4"),
    ("NaN", "t,phi1,phi2,u1\n0,0,0,0\n0.001,nan,0,0\n", "line 3, column 'phi1' is not finite"),
    ("not uniform", "t,phi1,phi2,u1\n" + "".join(f"{t},0,0,0\n" for t in (0, 0.001, 0.003, 0.004)), "not sampled uniformly"),
    ("too few samples", "t,phi1,phi2,u1\n" + "".join(f"{i / 1000},0,0,0\n" for i in range(300)), "samples; the filter's edges"),
    ("too few for the rank", "t,phi1,phi2,u1\n" + "".join(f"{i / 1000},{np.sin(i / 100)},{np.cos(i / 90)},{np.sin(i / 50)}\n"
                                                          for i in range(1300)), "equations for 8 base parameters"),
    ("not a CSV", "\x00\x01\x02", "csv"),
])
def test_a_bad_csv_is_one_line(case, rows, words, tmp_path, capsys):
    data = tmp_path / "bad.csv"
    data.write_text(rows)
    code, text = _cli(capsys, "identify", FURUTA, data, "-o", tmp_path / "out.toml")
    assert code == 2, text
    assert text.count("\n") == 1 and text.startswith("error: ") and words in text, (case, text)
    assert not (tmp_path / "out.toml").exists()


def test_newcomer_mistakes_are_one_line(tmp_path, capsys):
    gimbal = ROOT / "specs" / "gimbal.toml"
    for words, said in (
        (("identify", FURUTA, tmp_path / "nothing.csv"), "nothing.csv"),
        (("identify", FURUTA, FURUTA), "furuta.toml"),
        (("identify", FURUTA, "x.csv", "--windw", "0.1"), "--window"),
        (("excite", gimbal, "-o", tmp_path / "e.csv"), "no control torque"),
        (("excite", FURUTA, "--phi-max", "1,2,3", "-o", tmp_path / "e.csv"), "--phi-max"),
        (("excite", FURUTA, "--period", "-1", "-o", tmp_path / "e.csv"), "--period"),
        (("excite", FURUTA, "--harmonics", "0", "-o", tmp_path / "e.csv"), "--harmonics"),
        (("excite", FURUTA, "--experiment", "0", "-o", tmp_path / "e.csv"), "--experiment"),
        (("excite", FURUTA, "--noise", "-1", "-o", tmp_path / "e.csv"), "--noise"),
        (("excite", FURUTA, "--encoder", "-3", "-o", tmp_path / "e.csv"), "--encoder"),
        (("excite", FURUTA, "--experiment", "10000", "-o", tmp_path / "e.csv"), "more than 2000000"),
        (("excite", FURUTA, "--u-max", "0", "-o", tmp_path / "e.csv"), "--u-max"),
        (("identify", FURUTA, "x.csv", "--cutoff", "0"), "--cutoff"),
        (("identify", FURUTA, "x.csv", "--order", "12"), "--order"),
        (("identify", FURUTA, "x.csv", "--filter", "bogus"), "--filter"),
        (("identify", FURUTA, "x.csv", "--param", "r=2"), "--param r"),
    ):
        code, text = _cli(capsys, *words)
        assert code == 2 and text.count("\n") == 1 and said in text, (words, text)
    assert not (tmp_path / "e.csv").exists()


def test_generate_regressor_refuses_a_rotor_spinning_up(tmp_path, capsys):
    from gyrochain.randspec import random_general_spec_text

    spin = tmp_path / "spin.toml"
    spin.write_text(random_general_spec_text(np.random.default_rng(3), 2, name="spin"))
    code, text = _cli(capsys, "generate", spin, "--regressor", "-o", tmp_path / "out", "-q")
    assert code == 2 and text.count("\n") == 1 and "body[1].lambda: depends on t" in text, text
    assert not (tmp_path / "out").exists()


def test_physically_possible_bodies_near_estimates_they_cannot_have():
    """The Furuta pendulum's rod is thin (A²₃₃ = 1e-5): base parameters with A²₂₂ − A²₃₃ above A²₁₁
    break its triangle inequality whatever the free directions.  The projection returns possible
    bodies (J ≻ 0) whose β is within a fraction of a standard error; feasible β come back exactly."""
    from gyrochain.consistency import _bodies, _body_columns, _pseudo, consistent

    spec = load_spec(FURUTA)
    cm, model = identify.compiled(spec)
    pi0 = cm.standard_parameters()
    true = cm.base_parameters(pi0)
    se = np.abs(true) * 0.01 + 1e-6
    pi, moved = consistent(model, true, se, pi0)
    assert moved < 1e-6 and np.allclose(cm.base_parameters(pi), true, rtol=0, atol=1e-12)
    bad = true.copy()
    bad[6] = true[3] + 5e-6  # A22 - A33 > A11: impossible for any A33 >= 0
    pi, moved = consistent(model, bad, se, pi0)
    cols = _body_columns(model.reg.params)
    assert all(np.linalg.eigvalsh(_pseudo(*b))[0] > 0 for b in _bodies(pi, cols))
    print(f"moved {moved:.3g} standard errors")
    assert 0 < moved < 1.0
