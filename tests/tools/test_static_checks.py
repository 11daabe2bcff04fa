"""Static checks the embedded world uses, on the generated C: cppcheck (Debian's) finds nothing at
its warning, performance and portability levels in any example; its MISRA C:2012 addon breaks no
rule that docs/embedding.md does not list with its reason (bench/misra.py prints the table)."""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from conftest import ONE_ARM, ROOT

pytestmark = pytest.mark.skipif(shutil.which("cppcheck") is None, reason="cppcheck is not installed (apt-get install cppcheck)")

GEN = ROOT / "generated"
CHECK = ["cppcheck", "--enable=warning,performance,portability", "--std=c99", "--quiet", "--error-exitcode=1",
         "--suppress=missingIncludeSystem", "--template={file}:{line}: {severity}: {id}: {message}"]


@pytest.mark.parametrize("name", ONE_ARM)
def test_cppcheck_finds_nothing(name):
    res = subprocess.run([*CHECK, str(GEN / name / f"{name}.c")], capture_output=True, text=True, timeout=600)
    assert res.returncode == 0 and not res.stderr.strip(), res.stderr


def test_a_planted_defect_is_found(tmp_path):
    """The check can fail: a read of an uninitialised variable planted in the gimbal's C."""
    src = (GEN / "gimbal" / "gimbal.c").read_text()
    src = src.replace("int gimbal_mass_matrix(const double *q, const gimbal_params *p, double *M)\n{\n",
                      "int gimbal_mass_matrix(const double *q, const gimbal_params *p, double *M)\n{\n    double planted_;\n"
                      "    M[0] = planted_;\n", 1)
    for ext in (".h",):
        shutil.copy2(GEN / "gimbal" / f"gimbal{ext}", tmp_path / f"gimbal{ext}")
    (tmp_path / "gimbal.c").write_text(src)
    res = subprocess.run([*CHECK, str(tmp_path / "gimbal.c")], capture_output=True, text=True, timeout=600)
    assert res.returncode != 0 and "uninitvar" in res.stderr


def test_misra_rules_broken_are_the_documented_ones(tmp_path):
    """The rules the addon finds in two examples are all in the documented table, with a reason.
    The addon writes its dump beside the source: a copy is checked, so that generated/ stays the
    generator's alone while other tests read it."""
    page = (ROOT / "docs" / "embedding.md").read_text()
    listed = set(re.findall(r"^\| (\d+\.\d+) \| \d+ \| \d+ \| .+ \|$", page, re.M))
    assert len(listed) >= 10
    found = set()
    for name in ("gimbal", "kapitza"):
        for ext in (".c", ".h"):
            shutil.copy2(GEN / name / f"{name}{ext}", tmp_path / f"{name}{ext}")
        res = subprocess.run(["cppcheck", "--addon=misra", "--std=c99", "--quiet", "--suppress=missingIncludeSystem",
                              "--template={id}", str(tmp_path / f"{name}.c")], capture_output=True, text=True, timeout=600)
        found |= set(re.findall(r"misra-c2012-(\d+\.\d+)", res.stderr))
    assert found and found <= listed, found - listed
