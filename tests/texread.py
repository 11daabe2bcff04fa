"""Read the generated LaTeX back: its equations as sympy expressions, by a parser of the small
grammar the LaTeX printer uses (gyrochain/printers/texterms.py) — written apart from the printer, so
that a formula printed wrong reads back wrong.  Anything outside the grammar is an error."""
from __future__ import annotations

import re

import sympy as sp

FUNCS = {r"\cos": sp.cos, r"\sin": sp.sin, r"\tan": sp.tan, r"\exp": sp.exp, r"\log": sp.log, r"\sinh": sp.sinh,
         r"\cosh": sp.cosh, r"\tanh": sp.tanh, r"\arcsin": sp.asin, r"\arccos": sp.acos, r"\arctan": sp.atan}


class TexSyntaxError(ValueError):
    pass


MATHRM = re.compile(r"\\mathrm\{[^{}]*\}")
RECURSION = r"\subsection*{The recursion}"
SHARES = r"\subsection*{Each body's share}"


def document_names(tex: str, n: int) -> dict[str, sp.Symbol]:
    """The names a document's formulas use: the joint state, the torques, time, the platform's
    quantities and the symbolic parameters its scene section lists as "$tex$ (\\texttt{name})"."""
    names = {"t": sp.Symbol("t"), r"\pi": sp.pi}
    for k in range(1, n + 1):
        names[rf"\varphi^{{{k}}}"] = sp.Symbol(f"phi{k}")
        names[rf"\dot\varphi^{{{k}}}"] = sp.Symbol(f"phidot{k}")
        names[rf"\ddot\varphi^{{{k}}}"] = sp.Symbol(f"qdd{k}")
        names[rf"L^{{{k}}}"] = sp.Symbol(f"u{k}")
    if n == 2:  # the quadratures call the angle of joint 2 φ
        names[r"\varphi"], names[r"\dot\varphi"] = sp.Symbol("phi2"), sp.Symbol("phidot2")
    for i in range(1, 4):
        names[rf"\omega^{{0}}_{{{i}}}"] = sp.Symbol(f"omega0_{i}")
        names[rf"\varepsilon^{{0}}_{{{i}}}"] = sp.Symbol(f"epsilon0_{i}")
        names[rf"\dot v_{{0,{i}}}"] = sp.Symbol(f"vdot0_{i}")
        names[rf"\gamma^{{0}}_{{{i}}}"] = sp.Symbol(f"gamma0_{i}")
    line = next((ln for ln in tex.splitlines() if ln.startswith("Symbolic parameters")), None)
    if line is not None:
        i = tex.splitlines().index(line)
        listing = " ".join(tex.splitlines()[i + 1:i + 1 + 200]).split(".\n")[0]
        for t, name in re.findall(r"\$([^$]+)\$ \(\\texttt\{([^}]*)\}\)", listing):
            names[t] = sp.Symbol("param_" + name.replace(r"\_", "_"))
    for lhs, _ in recursion(tex):
        names[lhs] = sp.Symbol("rec" + re.sub(r"\W+", "_", lhs))
    # the printed quantities by name (the equations of motion written with them) and the coefficients
    # Q_{k,hr}, Γ_{k,r} that a long velocity group is written with
    sep = "," if n > 9 else ""
    for k in range(1, n + 1):
        for r in range(1, n + 1):
            names[f"M_{{{k}{sep}{r}}}"] = sp.Symbol(f"M_{k}_{r}")
        for g in QUANTITIES:
            names[f"{g}_{{{k}}}"] = sp.Symbol("q" + re.sub(r"\W+", "_", g) + f"_{k}")
    for lhs in coefficients(tex):
        names[lhs] = sp.Symbol("c" + re.sub(r"\W+", "_", lhs))
    offsets = next((ln for ln in tex.splitlines() if ln.startswith("Joint offsets")), "")
    for k, value in re.findall(r"\$\\delta\^\{(\d+)\} = ([^$]+)\$", offsets):  # the joints' offsets δᵏ, as printed
        names[rf"\delta^{{{k}}}"] = parse(value, names)
    return names


QUANTITIES = ("Q", r"\Gamma", "G", r"\Pi", r"\mathring\Lambda", "W", r"\tau")
COEFFICIENT = re.compile(r"(?:Q|\\Gamma)_\{\d+,[\d,]+\}")  # Q_{k,hr}, Γ_{k,r}


def coefficients(tex: str) -> list[str]:
    """The coefficients a long velocity group is written with (Q_{k,hr}, Γ_{k,r}), as printed."""
    return [lhs for lhs in equations(tex) if COEFFICIENT.fullmatch(lhs)]


def recursion(tex: str) -> list[tuple[str, str]]:
    """The definitions of a long chain's recursion section, in order: (name, its formula), each
    written in the text as "$name = formula$", or of its body-by-body section, in its displays.  A line that defines cos 2φᵏ (a function the
    grammar reads itself) defines nothing the formulas need."""
    if SHARES in tex:  # the body-by-body form: numbered displays, read in order
        section = tex.split(SHARES, 1)[1].split(r"\subsection*", 1)[0]
        return list(equations(section).items())
    if RECURSION not in tex:
        return []
    section = tex.split(RECURSION, 1)[1].split(r"\section*", 1)[0]
    section = section[section.index(r"{\footnotesize"):]
    out = []
    for item in re.findall(r"(?<!\\)\$(.+?)(?<!\\)\$", section, flags=re.S):
        lhs, eq, rhs = item.partition(" = ")
        if not eq:
            raise TexSyntaxError(f"a line of the recursion without ' = ': {item[:60]!r}")
        if not lhs.startswith((r"\cos", r"\sin")):
            out.append((lhs.strip(), rhs.strip()))
    return out


class NameTable:
    """A document's names ready for the parser, built once for all its formulas: the \\mathrm{...}
    names (a long chain's recursion has thousands) by lookup, the others by their first token (a
    control word, or one character), longest first in each; a name that starts the text at i
    starts with the token there."""

    def __init__(self, names: dict):
        self.mathrm = {k: v for k, v in names.items() if MATHRM.fullmatch(k)}
        self.by_token: dict[str, list] = {}
        for k, v in sorted(((k, v) for k, v in names.items() if k not in self.mathrm), key=lambda kv: -len(kv[0])):
            self.by_token.setdefault(_token(k, 0), []).append((k, v))


class Parser:
    def __init__(self, text: str, names: dict | NameTable):
        self.s = text
        self.i = 0
        prepared = table(names)
        self.mathrm, self.names = prepared.mathrm, prepared.by_token

    # ---- lexing helpers
    def ws(self) -> None:
        while True:
            while self.i < len(self.s) and self.s[self.i] in " \n\t":
                self.i += 1
            if self.s.startswith(r"\,", self.i):
                self.i += 2
            elif self.s.startswith(r"&\quad", self.i):
                self.i += 6
            else:
                return

    def peek(self, tok: str) -> bool:
        self.ws()
        return self.s.startswith(tok, self.i)

    def take(self, tok: str) -> bool:
        if self.peek(tok):
            self.i += len(tok)
            return True
        return False

    def expect(self, tok: str) -> None:
        if not self.take(tok):
            raise TexSyntaxError(f"expected {tok!r} at {self.s[self.i:self.i + 40]!r}")

    def braced_int(self) -> int:
        self.expect("{")
        m = re.match(r"-?\d+", self.s[self.i:])
        if not m:
            raise TexSyntaxError(f"expected an integer at {self.s[self.i:self.i + 20]!r}")
        self.i += m.end()
        self.expect("}")
        return int(m.group())

    # ---- grammar
    def parse(self) -> sp.Expr:
        e = self.sum()
        self.ws()
        if self.i != len(self.s):
            raise TexSyntaxError(f"unread text {self.s[self.i:self.i + 60]!r}")
        return e

    def sum(self) -> sp.Expr:
        terms = []
        sign = -1 if self.take("-") else 1
        if sign == 1:
            self.take("+")
        terms.append(sign * self.term())
        while True:
            if self.take("+"):
                terms.append(self.term())
            elif self.take("-"):
                terms.append(-self.term())
            else:
                return sp.Add(*terms)

    def term(self) -> sp.Expr:
        factors = []
        while True:
            f = self.factor()
            if f is None:
                break
            factors.append(f)
        if not factors:
            raise TexSyntaxError(f"expected a term at {self.s[self.i:self.i + 40]!r}")
        return sp.Mul(*factors)

    def power(self, base) -> sp.Expr:
        if self.take("^"):
            return base ** self.braced_int()
        return base

    def factor(self):
        self.ws()
        rest = self.s[self.i:]
        m = re.match(r"\d+(\.\d+)?", rest)
        if m:
            self.i += m.end()
            value = sp.Rational(m.group())
            if self.peek(r"\cdot 10^"):
                self.expect(r"\cdot 10^")
                value *= sp.Rational(10) ** self.braced_int()
            return value
        if self.take(r"\frac"):
            self.expect("{")
            top = self.sum()
            self.expect("}")
            self.expect("{")
            bottom = self.sum()
            self.expect("}")
            return top / bottom
        if self.take(r"\sqrt"):
            self.expect("{")
            inner = self.sum()
            self.expect("}")
            return self.power(sp.sqrt(inner))
        for opener, closer in ((r"\left(", r"\right)"), (r"\Big(", r"\Big)"), (r"\Bigl(", r"\Bigr)")):
            if self.take(opener):
                inner = self.sum()
                self.expect(closer)
                return self.power(inner)
        for tex, fn in sorted(FUNCS.items(), key=lambda kv: -len(kv[0])):
            if rest.startswith(tex) and not rest[len(tex):len(tex) + 1].isalpha():
                self.i += len(tex)
                e = self.braced_int() if self.take("^") else 1
                if self.peek(r"\left("):
                    self.expect(r"\left(")
                    arg = self.sum()
                    self.expect(r"\right)")
                else:
                    arg = self.name()
                    if arg is None:
                        raise TexSyntaxError(f"a function without an argument at {self.s[self.i:self.i + 40]!r}")
                return fn(arg) ** e
        sym = self.name()
        return None if sym is None else self.power(sym)

    def name(self):
        self.ws()
        m = MATHRM.match(self.s, self.i)
        if m and m.group() in self.mathrm:
            self.i = m.end()
            return self.mathrm[m.group()]
        for tex, sym in self.names.get(_token(self.s, self.i), ()):
            if self.s.startswith(tex, self.i):
                after = self.s[self.i + len(tex):self.i + len(tex) + 1]
                if tex[-1].isalpha() and after.isalpha():
                    continue
                self.i += len(tex)
                return sym
        return None


CONTROL_WORD = re.compile(r"\\[A-Za-z]+")


def _token(text: str, i: int) -> str:
    """The first token of text[i:]: a control word (a backslash and its letters), else one character."""
    m = CONTROL_WORD.match(text, i)
    return m.group() if m else text[i:i + 1]


def table(names: dict | NameTable) -> NameTable:
    """``names`` ready for the parser (a helper that parses many formulas builds it once)."""
    return names if isinstance(names, NameTable) else NameTable(names)


def parse(text: str, names: dict | NameTable) -> sp.Expr:
    return Parser(text, names).parse()


TAG = re.compile(r"\\tag\*?\{(?:[^{}]|\{(?:[^{}]|\{[^{}]*\})*\})*\}")


def equations(tex: str) -> dict[str, str]:
    """Every "lhs &= rhs" of the document's align* blocks (continuations joined; several to a row
    as "lhs &= rhs & lhs &= rhs"; the equation numbers \\tag{…} dropped), and every quantity an
    "Identically zero:" line names, as "0"."""
    out: dict[str, str] = {}
    for block in re.findall(r"\\begin\{align\*\}(.*?)\\end\{align\*\}", tex, flags=re.S):
        if r"\begin{pmatrix}" in block:  # the direction cosines' matrices (direction_cosines reads them)
            continue
        current = None
        for chunk in re.split(r"\\\\\*?", TAG.sub("", block)):
            chunk = chunk.strip()
            if not chunk:
                continue
            if "&=" in chunk:
                parts = chunk.split("&=")
                lhs = parts[0]
                for i, part in enumerate(parts[1:], start=1):
                    rhs, _, nxt = part.rpartition(" & ") if i < len(parts) - 1 else (part, "", "")
                    current = lhs.strip()
                    out[current] = rhs.strip()
                    lhs = nxt
            elif chunk.startswith(r"&\quad") and current is not None:
                out[current] += " " + chunk[len(r"&\quad"):].strip()
    for line in re.findall(r"^Identically zero: (.*)\.$", tex, flags=re.M):
        for name in re.findall(r"\$([^$]+)\$", line):
            out[name] = "0"
    return out


def pmatrix(text: str, names: dict) -> list[list[sp.Expr]]:
    r"""``\begin{pmatrix}a & b \\ c & d\end{pmatrix}`` as rows of expressions (a column: one per row)."""
    text = text.strip()
    head, tail = r"\begin{pmatrix}", r"\end{pmatrix}"
    if not (text.startswith(head) and text.endswith(tail)):
        raise TexSyntaxError(f"not a pmatrix: {text[:40]!r}")
    body, names = text[len(head):-len(tail)], table(names)
    return [[parse(cell, names) for cell in row.split("&")] for row in body.split(r"\\")]


def _vector(text: str, names: dict) -> list[list[sp.Expr]]:
    """A printed 3-vector, a column or a row of a pmatrix, as three one-element rows."""
    m = pmatrix(text, names)
    return [[x] for x in m[0]] if len(m) == 1 else m


def body_table(tex: str, names: dict) -> list[dict]:
    r"""The scene's tables of the bodies, a row per body: θ, m, c, s (None for the last), λ as
    the document prints them (expressions), the control flag, and A from the table of the inertia
    tensors (its six components, or the matrix)."""
    head = r"$k$ & $\theta^k$ & $m^k$ & $\mathbf c^k$ & $\mathbf s^k$ & $\boldsymbol\lambda^k$ & control"
    start, names = tex.index(head) + len(head), table(names)
    rows = []
    for line in tex[start:tex.index(r"\end{longtable}", start)].splitlines():
        cells = re.findall(r"\$(.*?)\$", line)
        if len(cells) != 6:
            continue
        k, theta, m, c, s, lam = cells
        for k in _ks(k):
            rows.append(dict(k=k, theta=parse(theta, names), m=parse(m, names), c=_vector(c, names),
                             s=None if s.startswith(r"\text") else _vector(s, names), lam=_vector(lam, names),
                             control=re.sub(r"\\\\(\[[^]]*\])?\s*$", "", line).rsplit("&", 1)[1].strip()))
    inertia = {}
    for head in (r"$k$ & $A^k_{11}$ & $A^k_{22}$ & $A^k_{33}$ & $A^k_{12}$ & $A^k_{13}$ & $A^k_{23}$", r"$k$ & $\mathbf A^k$"):
        if head not in tex:
            continue
        start = tex.index(head) + len(head)
        for line in tex[start:tex.index(r"\end{longtable}", start)].splitlines():
            cells = re.findall(r"\$(.*?)\$", line)
            if len(cells) == 7:
                a11, a22, a33, a12, a13, a23 = (parse(x, names) for x in cells[1:])
                for k in _ks(cells[0]):
                    inertia[k] = [[a11, a12, a13], [a12, a22, a23], [a13, a23, a33]]
            elif len(cells) == 2:
                for k in _ks(cells[0]):
                    inertia[k] = pmatrix(cells[1], names)
    for row in rows:
        row["A"] = inertia[row["k"]]
    return rows


def _ks(cell: str) -> list[int]:
    """A table's k: one body, or a run "a,\\dots,b" of bodies with the same row."""
    m = re.fullmatch(r"(\d+),\\dots,(\d+)", cell.strip())
    return list(range(int(m.group(1)), int(m.group(2)) + 1)) if m else [int(cell)]


def direction_cosines(tex: str, names: dict) -> dict[int, list[list[sp.Expr]]]:
    r"""α^{k,k−1} of the direction cosines' section, by k."""
    found = re.findall(r"\\alpha\^\{(\d+),(\d+)\} &= (\\begin\{pmatrix\}.*?\\end\{pmatrix\})", tex, flags=re.S)
    names = table(names)
    return {int(k): pmatrix(m, names) for k, j, m in found if int(j) == int(k) - 1}


def _table_rows(tex: str, head: str) -> list[list[str]]:
    """The rows of the longtable whose header line starts with ``head``: each row's cells as text."""
    if head not in tex:
        return []
    start = tex.index(r"\endhead", tex.index(head)) + len(r"\endhead")
    body = tex[start:tex.index(r"\end{longtable}", start)]
    return [[c.strip() for c in re.sub(r"\\\\(\[[^]]*\])?\s*$", "", line).split(" & ")] for line in body.splitlines() if " & " in line]


def _cell(text: str, names: dict):
    """A table cell: None for '--' (no such element), else the expression or the column vector."""
    text = text.strip().strip("$")
    if text == r"\text{--}":
        return None
    if text.startswith(r"\begin{pmatrix}"):
        return [row[0] for row in pmatrix(text, names)]
    return parse(text, names)


def joint_table(tex: str, names: dict) -> dict[int, dict]:
    """The joints' table by k: stiffness, rest angle, damping, torque expression (None where '--')."""
    rows = _table_rows(tex, r"$k$ & stiffness $\kappa^k$")
    return {int(r[0].strip("$")): dict(zip(("spring", "rest", "damping", "torque"), (_cell(c, names) for c in r[1:5])))
            for r in rows}


def load_table(tex: str, names: dict) -> list[dict]:
    """The loads' table, in order: k, kind, components, frame, point (None for a moment)."""
    rows = _table_rows(tex, r"$k$ & load & components & frame & point")
    return [dict(k=int(r[0].strip("$")), kind=r[1], vec=_cell(r[2], names), frame=r[3],
                 point=None if r[4] == "(a moment)" else _cell(r[4], names)) for r in rows]


def platform_motion(tex: str, names: dict) -> dict | None:
    """The platform's motion as the scene states it: r₀(t) and the rotations (angle, axis) in order."""
    m = re.search(r"\$O\^1\$ at \$\\mathbf r_0\(t\) = (\\begin\{pmatrix\}.*?\\end\{pmatrix\})\$(.*?)\n\n", tex, flags=re.S)
    if m is None:
        return None
    rotations = re.findall(r"by \$(.*?)\$ about \$(\\begin\{pmatrix\}.*?\\end\{pmatrix\})\$", m.group(2), flags=re.S)
    return dict(position=[row[0] for row in pmatrix(m.group(1), names)],
                rotations=[(parse(a, names), [row[0] for row in pmatrix(ax, names)]) for a, ax in rotations])


def initial_state(tex: str) -> tuple[list[float], list[float]] | None:
    r"""The scene's initial state, φ and φ̇, as printed (a vector of equal entries said once, "$\varphi^k =
    0.5$ for $k = 1, \dots, 64$"); None where the spec gives none."""
    line = next((ln for ln in tex.splitlines() if ln.startswith("Initial state: ")), None)
    if line is None:
        return None
    out = []
    for sym in (r"\varphi", r"\dot\varphi"):
        m = re.search(r"(?<![\w\\])\$" + re.escape(sym) + r" = \((.*?)\)\$", line)
        if m:
            out.append([float(v) for v in m.group(1).replace(r"\allowbreak", "").split(",")])
            continue
        m = re.search(r"\$" + re.escape(sym) + r"\^k = ([^$]+)\$ for every (?:other )?\$k \\le (\d+)\$", line)
        vec = [float(m.group(1))] * int(m.group(2))
        for k, x in re.findall(r"(?<![\w\\])\$" + re.escape(sym) + r"\^\{(\d+)\} = ([^$]+)\$", line):
            vec[int(k) - 1] = float(x)
        out.append(vec)
    return out[0], out[1]


def motion_equations(tex: str) -> dict[int, tuple[str, str]]:
    """The equations of motion as the document writes them out, one display per joint after the
    comment "% the equation of motion of joint k": k → (left side, right side) of its "=" (the
    lines of its split joined)."""
    out = {}
    for k, body in re.findall(r"^% the equation of motion of joint (\d+)\n\\begin\{equation\*\}\n\\begin\{split\}\n(.*?)\\end\{split\}",
                              tex, flags=re.S | re.M):
        text = " ".join(line.strip().lstrip("&").removesuffix(r"\\").replace(r"\quad", " ") for line in body.splitlines())
        # a long chain's row, Σ_r M_kr φ̈ʳ, as its n terms
        text = re.sub(r"\\sum_\{r=1\}\^\{(\d+)\} M_\{(\d+),?r\} \\, \\ddot\\varphi\^\{r\}",
                      lambda m: " + ".join(f"M_{{{m.group(2)}{',' if int(m.group(1)) > 9 else ''}{r}}} \\, \\ddot\\varphi^{{{r}}}"
                                     for r in range(1, int(m.group(1)) + 1)), text)
        left, eq, right = text.partition(" = ")
        if not eq or " = " in right:
            raise TexSyntaxError(f"the equation of joint {k} has not one '=': {text[:80]!r}")
        out[int(k)] = (left.strip(), right.strip())
    return out


def check_at_one_state(tex: str) -> dict | None:
    """The document's check at one state: the columns' heads, the rows (k, φ, φ̇, the groups, φ̈) as
    numbers, M (a matrix, or its diagonal), and the stated asymmetry, eigenvalues and residual."""
    if "% the check at one state" not in tex:
        return None
    part = tex.split("% the check at one state", 1)[1].split(r"\section*", 1)[0]
    table = part.split(r"\begin{longtable}", 1)[1].split(r"\end{longtable}", 1)[0]
    heads = re.findall(r"\$([^$]+)\$", table.split(r"\midrule", 1)[0])
    rows = []
    for line in table.split(r"\endfoot", 1)[1].splitlines():
        cells = re.findall(r"\$([^$]*)\$", line)
        if cells and cells[0] != r"\vdots":
            rows.append([_number(c) for c in cells])
    out = dict(heads=heads, rows=rows, M=None, entries={}, state=None)
    st = re.search(r"\$\\varphi = \((.*?)\)\$, \$\\dot\\varphi = \((.*?)\)\$", part.split("\n\n", 1)[0])
    if st:
        out["state"] = [[_number(v) for v in g.replace(r"\allowbreak", "").split(",")] for g in st.groups()]
    for k, r, v in re.findall(r"\$M_\{(\d)(\d)\} = ([^$]+)\$", part):
        out["entries"][(int(k), int(r))] = _number(v)
    m = re.search(r"M = \\begin\{pmatrix\}\n(.*?)\n\\end\{pmatrix\}", part, flags=re.S)
    if m:
        out["M"] = [[_number(c) for c in row.split("&")] for row in m.group(1).split(r"\\")]
    facts = re.search(r"M_\{rk\}\|\$ is \$(.*?)\$.*?between \$(.*?)\$ and \$(.*?)\$.*?\|f_k\|\) = (.*?)\$", part, flags=re.S)
    out.update(asymmetry=_number(facts.group(1)), eig=(_number(facts.group(2)), _number(facts.group(3))),
               residual=_number(facts.group(4)))
    return out


SHARE_VALUES = "At the check's state:"


def share_values(tex: str) -> list[tuple[str, float]]:
    """The values the body-by-body section states for its quantities at the check's state, in
    order: (name, value), from each body's line "At the check's state: $x = v$, …"."""
    out = []
    for line in re.findall(rf"^{{\\raggedright {re.escape(SHARE_VALUES)}(.*)$", tex, flags=re.M):
        for lhs, v in re.findall(r"\$([^$=]+?) = ([^$]+)\$", line):
            out.append((lhs.strip(), _number(v)))
    return out


def _number(text: str) -> float:
    """A printed number: -0.25, 4.3 \\cdot 10^{-5}, 2.0 \\times 10^{-16}, 0."""
    text = text.strip().replace(" ", "")
    m = re.fullmatch(r"(-?[\d.]+)(?:\\(?:cdot|times)10\^\{(-?\d+)\})?", text)
    if not m:
        raise TexSyntaxError(f"not a number: {text!r}")
    return float(m.group(1)) * (10.0 ** int(m.group(2)) if m.group(2) else 1.0)
