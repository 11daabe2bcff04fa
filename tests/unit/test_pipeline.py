"""The one route from a spec to its files: derive once, render only what is asked, and the
same bytes whichever way the files are asked for."""
from __future__ import annotations

import os

import pytest

from gyrochain import pipeline
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT

GIMBAL = ROOT / "specs" / "gimbal.toml"


def committed(name: str) -> dict[str, str]:
    folder = ROOT / "generated" / name
    # the build's extension and key, and what `make pdf` leaves beside the LaTeX, are not the generator's
    return {p.name: p.read_text() for p in folder.iterdir() if not p.name.endswith((".so", ".key", ".pdf", ".aux", ".log"))}


def test_a_spec_is_derived_once_per_process():
    spec = load_spec(GIMBAL)
    a = pipeline.derive(spec)
    assert pipeline.derive(parse_spec(GIMBAL.read_text())) is a  # the same text: the same Model
    assert pipeline.derive(spec, qdd_form="articulated") is not a  # another form: derived anew
    assert pipeline.derive(spec, qdd_form="articulated").qdd_form == "articulated"


@pytest.mark.parametrize("targets, suffixes", [
    (("c",), {".c", ".h", ".cdef", ".pc.in", ".txt"}),  # with the package files: CMakeLists.txt, NAME.pc.in
    (("python",), {".py"}),
    (("latex",), {".tex"}),
    (("c", "python"), {".c", ".h", ".cdef", ".pc.in", ".txt", ".py"}),
])
def test_render_prints_only_the_asked_targets_and_the_same_bytes(targets, suffixes):
    spec = load_spec(GIMBAL)
    files = pipeline.render(pipeline.derive(spec), "gimbal.toml", targets)
    assert {"." + k.split(".", 1)[1] for k in files} == suffixes
    whole = committed("gimbal")
    for k, v in files.items():
        assert v == whole[k], k


def test_all_targets_are_the_committed_files_with_their_manifest():
    files, _ = pipeline.derive_and_render(load_spec(GIMBAL), "gimbal.toml")
    assert files == committed("gimbal")


def test_a_model_is_printed_once_per_process_and_asked_options(monkeypatch):
    """Rendering the same model with the same label, targets and type again returns the same files
    without printing them again (a command or a test that asks twice pays once), still hands the C
    to on_c, and gives out a copy; another type of real is printed anew."""
    from gyrochain import printers

    pipeline.forget()
    model = pipeline.derive(load_spec(GIMBAL))
    calls: list = []
    real_render = printers.render
    monkeypatch.setattr(printers, "render", lambda *a, **k: calls.append(a[2]) or real_render(*a, **k))
    seen: list = []
    first = pipeline.render(model, "gimbal.toml", ("c", "python"), on_c=seen.append)
    first["gimbal.c"] = "changed by the caller"
    again = pipeline.render(model, "gimbal.toml", ("c", "python"), on_c=seen.append)
    assert calls == [("c", "python")]
    assert again == {k: v for k, v in committed("gimbal").items() if k in again}
    assert len(seen) == 2 and seen[0] == seen[1] and set(seen[1]) == {k for k in again if not k.endswith(".py")}
    single = pipeline.render(model, "gimbal.toml", ("c",), real="float")
    assert "float" in single["gimbal.h"] and len(calls) == 2


def test_a_template_is_compiled_once_per_process(monkeypatch, tmp_path):
    """The printers share one jinja2 environment per templates folder: model.c.jinja is compiled
    once, not at every rendering (half a second each); a template edited on disk is read again."""
    import shutil

    import jinja2

    from gyrochain.printers import common

    compiled: list = []
    real_compile = jinja2.Environment.compile
    monkeypatch.setattr(jinja2.Environment, "compile", lambda self, source, name=None, *a, **k:
                        compiled.append(name) or real_compile(self, source, name, *a, **k))
    folder = tmp_path / "templates"
    shutil.copytree(common.TEMPLATES, folder)
    monkeypatch.setattr(common, "TEMPLATES", folder)
    facts = dict(name="m", version="1", spec_label="m.toml", spec_sha="0", regenerate="r", pc_description="d")
    for _ in range(3):
        assert "Name: m\n" in common.environment().get_template("model.pc.in.jinja").render(facts)
    assert compiled == ["model.pc.in.jinja"]
    source = folder / "model.pc.in.jinja"
    source.write_text(source.read_text() + "# edited\n")
    os.utime(source, (source.stat().st_atime, source.stat().st_mtime + 5))
    assert common.environment().get_template("model.pc.in.jinja").render(facts).endswith("# edited\n")
    assert compiled == ["model.pc.in.jinja"] * 2

def test_the_next_process_reads_the_compiled_templates(monkeypatch, tmp_path):
    """The templates compiled by one command are kept in the build cache for the next: a new
    process (here: the per-process environment forgotten) renders the gimbal's C without compiling
    a template file, the same bytes; a kept template whose text has changed is compiled again."""
    import jinja2

    from gyrochain.printers import common

    monkeypatch.setenv("GYROCHAIN_CACHE", str(tmp_path / "cache"))
    compiled: list = []
    real_compile = jinja2.Environment.compile

    def counted(self, source, name=None, *args, **kwargs):
        if name is not None:  # a template file (the one-line glue of printers/c.py has no name)
            compiled.append(name)
        return real_compile(self, source, name, *args, **kwargs)

    monkeypatch.setattr(jinja2.Environment, "compile", counted)
    model = pipeline.derive(load_spec(GIMBAL))
    outputs = []
    for _ in range(2):
        pipeline.forget()  # the renderings kept by this process
        common._environment.cache_clear()  # and its environments: as a new process starts
        compiled.clear()
        outputs.append(pipeline.render(model, "gimbal.toml", ("c",)))
        if len(outputs) == 1:
            assert "model.c.jinja" in compiled
    assert compiled == [] and outputs[0] == outputs[1] == {k: v for k, v in committed("gimbal").items() if k in outputs[0]}
    kept = tmp_path / "cache" / "templates"
    assert oct(kept.stat().st_mode & 0o777) == "0o700" and all(p.stat().st_mode & 0o077 == 0 for p in kept.iterdir())
    folder = tmp_path / "templates"  # the same templates, one of them edited
    import shutil

    shutil.copytree(common.TEMPLATES, folder)
    monkeypatch.setattr(common, "TEMPLATES", folder)
    for edit in ("", "/* edited */\n"):
        (folder / "model.cdef.jinja").write_text((folder / "model.cdef.jinja").read_text() + edit)
        pipeline.forget()
        common._environment.cache_clear()
        compiled.clear()
        again = pipeline.render(model, "gimbal.toml", ("c",))
    assert compiled == ["model.cdef.jinja"] and again["gimbal.cdef"].endswith("/* edited */\n")
    pipeline.forget()


def test_compiled_templates_are_kept_only_in_a_private_cache(monkeypatch, tmp_path):
    """A compiled template is code: a cache folder another user could have written (the build
    cache's own checks) is neither read nor written, and rendering goes on without it."""
    from gyrochain.printers import common

    shared = tmp_path / "shared"
    (shared / "templates").mkdir(parents=True)
    shared.chmod(0o777)
    monkeypatch.setenv("GYROCHAIN_CACHE", str(shared))
    assert pipeline.compiled_templates() is None
    mine = tmp_path / "mine"
    monkeypatch.setenv("GYROCHAIN_CACHE", str(mine))
    assert pipeline.compiled_templates() == (mine / "templates").resolve()
    (mine / "templates").chmod(0o777)  # the cache is private, its templates folder is not
    assert pipeline.compiled_templates() is None
    before = sorted((mine / "templates").iterdir())
    pipeline.forget()
    common._environment.cache_clear()
    files = pipeline.render(pipeline.derive(load_spec(GIMBAL)), "gimbal.toml", ("c",))
    assert files["gimbal.c"] == committed("gimbal")["gimbal.c"] and sorted((mine / "templates").iterdir()) == before
    monkeypatch.setenv("GYROCHAIN_CACHE", "")
    assert pipeline.compiled_templates() is None
    pipeline.forget()


def test_an_unknown_target_is_refused():
    with pytest.raises(ValueError, match="unknown target 'fortran'"):
        pipeline.render(pipeline.derive(load_spec(GIMBAL)), "gimbal.toml", ("c", "fortran"))


def test_the_latex_of_the_general_case_reads_the_derived_model():
    """A moving platform: derive(latex=False) skips the symbolic-platform stages; rendering the
    LaTeX adds them once, and the document is the committed one."""
    pipeline.forget()
    spec = load_spec(ROOT / "specs" / "kapitza.toml")
    model = pipeline.derive(spec, latex=False)
    assert model.symbolic is None
    again = pipeline.derive(spec)  # the LaTeX asked: the same derivation, with the symbolic stages
    assert again.symbolic is not None and again.lines is model.lines
    assert pipeline.derive(spec) is again
    got = pipeline.render(again, "kapitza.toml", ("latex",))["kapitza.tex"]
    assert got == committed("kapitza")["kapitza.tex"]


def test_header_defines_come_from_the_one_table():
    from gyrochain.codes import METHODS, MOTIONS, STATUS

    header = committed("gimbal")["gimbal.h"]  # the gimbal has the quadratures: every code appears
    for key, value in STATUS.items():
        assert f"#define GIMBAL_{key} {value}\n" in header, key
    for key, value in {**METHODS, **MOTIONS}.items():
        assert f"#define GIMBAL_{key.upper()} {value}\n" in header, key


def test_a_disturbance_torque_is_an_input_every_target_names():
    """disturbance = true on the Furuta pendulum's joint: an entry of u (NAME_NU 2), which the header,
    the Python module (DISTURBANCES) and the LaTeX's table of bodies name as a disturbance."""
    head, arm, pendulum = (ROOT / "specs" / "furuta.toml").read_text().split("[[body]]")
    spec = parse_spec("[[body]]".join([head.replace('name = "furuta"', 'name = "fd"'), arm,
                                       pendulum.replace("\n", "\ndisturbance = true\n", 1)]))
    assert spec.controls == (1, 2) and spec.disturbances == (2,)
    files, _ = pipeline.derive_and_render(spec, targets=("c", "python", "latex"))
    assert "#define FD_NU 2\n" in files["fd.h"] and "joint 2 takes a disturbance torque" in files["fd.h"]
    assert "\nDISTURBANCES = (2, )" in files["fd.py"] and "DISTURBANCES" not in committed("furuta")["furuta.py"]
    assert "& disturbance \\\\" in files["fd.tex"]
    assert "Control torques: $L^{1}$. Disturbance torques (inputs no controller sets): $L^{2}$." in files["fd.tex"]
