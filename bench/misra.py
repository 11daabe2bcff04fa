"""The MISRA C:2012 rules the generated C would break, counted by cppcheck's MISRA addon (which
checks the rules without their texts) over the short examples' C (generated/*/, n < 12; the
64-link cable takes 90 s alone and breaks the same rules).  Prints the Markdown table of
docs/embedding.md: the rule, the violations per example and in all, and why the code does it.

    python bench/misra.py        (needs cppcheck: apt-get install cppcheck)
"""
from __future__ import annotations

import collections
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

# why the generated code breaks each rule it breaks (the table's last column)
WHY = {
    "2.2": "stores into the caller's output arrays, which the addon's dead-code check does not see read",
    "2.5": "the header's #defines (sizes, codes, facts) are for the caller, not used in the C itself",
    "8.7": "the API's functions have external linkage although this file alone calls some of them",
    "8.14": "the parts of long functions and RK4's lanes declare their arrays restrict (they never overlap), "
            "so that the compiler needs no run-time overlap test",
    "9.4": "the integrators' local statistics initialised as {0.0, {0.0}, 0, ...} for the analysers",
    "10.3": "values of another essential type assigned (a double scaled by an int macro, int counts to double)",
    "10.4": "int constants in double arithmetic: d0 / 4",
    "10.8": "a composite int expression cast to double: (double)(k + 1)",
    "11.9": "0 as the null pointer constant (the C includes <math.h> only, which need not define NULL)",
    "12.1": "the precedence of * over + left implicit in the generated formulas (parentheses on every "
            "product would double the text)",
    "12.3": "several variables declared in one line (int i, j;), which the addon counts as the comma operator",
    "13.4": "the result of an assignment tested: if ((code = f(...)) != 0) return code;",
    "14.2": "for loops without a condition, left by a break: for (it = 1;; ++it)",
    "14.4": "pointers tested as conditions: if (qdd), if (!p)",
    "15.4": "more than one break out of an integrator's loop",
    "15.5": "early returns of the error codes (a single exit would need a flag per check)",
    "15.7": "an else-if chain without a final else",
    "17.8": "a parameter reassigned (DOP853's first step h, estimated when given as 0)",
    "18.4": "pointer arithmetic on arrays: xdot + n, the rows of a batch",
}


def short_examples() -> list[str]:
    from conftest import SHORT_EXAMPLES

    return SHORT_EXAMPLES


def count(name: str) -> collections.Counter:
    """Violations per rule of generated/<name>/<name>.c."""
    res = subprocess.run(["cppcheck", "--addon=misra", "--std=c99", "--quiet", "--suppress=missingIncludeSystem",
                          "--template={id}", str(ROOT / "generated" / name / f"{name}.c")],
                         capture_output=True, text=True, check=True)
    rules = [m.group(1) for m in re.finditer(r"misra-c2012-(\d+\.\d+)", res.stderr + res.stdout)]
    return collections.Counter(rules)


def main() -> int:
    names = short_examples()
    counts = {n: count(n) for n in names}
    total = collections.Counter()
    for c in counts.values():
        total.update(c)
    version = subprocess.run(["cppcheck", "--version"], capture_output=True, text=True).stdout.strip()
    print(f"MISRA C:2012 by {version}'s MISRA addon over {len(names)} examples ({', '.join(names)}):\n")
    print("| rule | violations in all | in how many examples | why the generated code does it |")
    print("|---|---|---|---|")
    for rule in sorted(total, key=lambda r: tuple(int(p) for p in r.split("."))):
        seen = sum(1 for c in counts.values() if c[rule])
        print(f"| {rule} | {total[rule]} | {seen} | {WHY.get(rule, '?')} |")
    missing = [r for r in total if r not in WHY]
    if missing:
        print(f"\nrules without a reason in WHY: {', '.join(missing)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
