"""Text as text: the spec's description and the sentences the LaTeX writes from the facts, set by
one typesetter that knows three kinds of words.

- **Code**: a span in backquotes, a command-line option with its arguments (``steady --vary
  w=150:300:16``), a file name (``ur5_robot.urdf``), a name with underscores or brackets
  (``wrist_3_link``, ``body[2].force[1]``): typewriter type, as typed.
- **Mathematics**: a run of words that makes an ASCII formula (``a^2 w^2 > 2 g A11 / (m l)``,
  ``phi = pi``, ``Omega_c = sqrt(m g l / (A22 - A33))``) and a lone symbol (``Omega``, ``J0``,
  ``O2``): inline math in the document's notation — Greek names as letters, ``sqrt`` as a root,
  powers raised, a letter's digits as its index (A11 → A₁₁; the paper's Oᵏ, Sᵏ, lᵏ upper), a
  spec parameter as the document prints it (sans serif), ``!=`` as ≠, ``-+`` as ∓.
- **Words**: everything else, escaped.

Nothing of the user's text is evaluated: it is split into tokens and each token printed.
"""
from __future__ import annotations

import re

from .common import tex_escape

GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa", "lambda", "mu", "nu",
         "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi", "omega", "Gamma", "Delta", "Theta", "Lambda",
         "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega"}
_VAR = {"phi": "varphi", "epsilon": "varepsilon"}  # the paper's letters
FUNCTIONS = {"cos", "sin", "tan", "exp", "log", "sinh", "cosh", "tanh"}
COMMANDS = {"generate", "check", "simulate", "steady", "orbits", "sweep", "plot", "animate", "import", "export", "fmu",
            "identify", "excite", "examples", "new", "gyrochain"}
UNITS = {"rad/s", "rad/s^2", "m/s", "m/s^2", "rad", "kg", "m", "s", "N", "Nm", "cm", "mm", "Hz", "kg m^2", "m^2/s^2"}
UPPER_INDEX = {"O", "S", "l"}  # the paper's points, bodies and axes carry the body's number up: O², S¹, l¹
_WORDS = {"a", "an", "as", "at", "be", "by", "in", "is", "it", "of", "on", "or", "the", "to", "and", "its", "if", "from",
          "with", "when", "for", "not", "no", "say", "says", "are", "this", "that", "than", "then", "holds", "above",
          "below", "between", "over", "under"}
_SYMBOLS = {"\u2248": r"\approx", "\u2264": r"\le", "\u2265": r"\ge", "\u2260": r"\ne", "\u00b1": r"\pm", "\u00d7": r"\times",
            "\u00b7": r"\cdot", "\u2212": "-", "\u2192": r"\to", "\u221e": r"\infty", "\u2202": r"\partial", "\u00b0": r"^\circ"}
_GREEK_CHARS = {chr(0x3B1 + i): n for i, n in enumerate(
    "alpha beta gamma delta epsilon zeta eta theta iota kappa lambda mu nu xi omicron pi rho varsigma sigma tau upsilon "
    "phi chi psi omega".split())}
_MATH_LETTERS = {"ê": r"\hat{e}", "ℓ": r"\ell"}  # letters of the paper's notation a formula may hold as written
_SUPER = dict(zip("⁰¹²³⁴⁵⁶⁷⁸⁹", "0123456789"))
_SUB = dict(zip("₀₁₂₃₄₅₆₇₈₉", "0123456789"))

_CODE = re.compile(r"^(?:--?[A-Za-z][\w-]*(?:=\S*)?|[\w.-]+\.(?:toml|urdf|xml|mjcf|csv|json|zarr|c|h|py|tex|fmu|gif|mp4|html)"
                   r"|\w+\[\d+\](?:\.\w+(?:\[\d+\])?)*|[A-Za-z_]\w{2,}\.[A-Za-z_]\w{2,}|\w+=[\w.:,-]+)$")
_OPERATORS = set("^*/=<>_")
_TOKEN = re.compile(r"\d+(?:\.\d+)?|[A-Za-z][A-Za-z0-9_]*|!=|<=|>=|-\+|\+-|\S")


def _ident(name: str, params: dict) -> str:
    """An identifier of an ASCII formula in the document's notation."""
    if name in params:
        return params[name]
    head, _, sub = name.partition("_")
    if head in GREEK:
        tex = "\\" + _VAR.get(head, head)
    else:
        m = re.fullmatch(r"([A-Za-z])(\d+)", head)
        if m and not sub:
            return f"{m.group(1)}^{{{m.group(2)}}}" if m.group(1) in UPPER_INDEX and len(m.group(2)) == 1 \
                else f"{m.group(1)}_{{{m.group(2)}}}"
        if m:  # j0_i: the index's parts together
            return f"{m.group(1)}_{{{m.group(2)},{_sub_tex(sub)}}}"
        tex = head if len(head) == 1 else rf"\mathrm{{{head}}}"
    return tex + (f"_{{{_sub_tex(sub)}}}" if sub else "")


def _sub_tex(sub: str) -> str:
    return sub if len(sub) == 1 or sub.isdigit() else rf"\mathrm{{{sub}}}"


def formula(text: str, params: dict) -> str:
    """An ASCII formula as TeX math (without the dollars)."""
    toks = _TOKEN.findall(text)
    out, i = [], 0

    def atom(j: int) -> tuple[str, int]:
        """The TeX of the atom at token j (a number, a name, a bracket's whole content) and the next index."""
        if j >= len(toks):
            return "", j
        if toks[j] == "(":
            depth, k = 0, j
            while k < len(toks):
                depth += {"(": 1, ")": -1}.get(toks[k], 0)
                if depth == 0:
                    break
                k += 1
            # a bracket the run does not close is closed by the text after it, not here
            return "(" + formula(" ".join(toks[j + 1:k]), params) + (")" if k < len(toks) else ""), k + 1
        return piece(toks[j]), j + 1

    def piece(tok: str) -> str:
        if re.fullmatch(r"\d+(?:\.\d+)?", tok):
            return tok
        if re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", tok):
            return ("\\" + tok) if tok in FUNCTIONS else _ident(tok, params)
        if len(tok) == 1 and (tok in _MATH_LETTERS or _unicode(tok) is not None):  # λ, ², ₃, ≈, ê as written
            return _MATH_LETTERS.get(tok) or _unicode(tok)
        return {"!=": r"\ne", "<=": r"\le", ">=": r"\ge", "-+": r"\mp", "+-": r"\pm", "*": r"\,", "<": "<", ">": ">"}.get(
            tok, tex_escape(tok) if tok not in "+-=/()[],;:." else tok)

    while i < len(toks):
        tok = toks[i]
        if tok == "sqrt":
            inner, i = atom(i + 1)
            if inner.startswith("(") and inner.endswith(")"):
                inner = inner[1:-1]
            out.append(rf"\sqrt{{{inner}}}")
            continue
        if tok == "^":
            power, i = atom(i + 1)
            out.append(f"^{{{power}}}")
            continue
        if tok == "(":
            text_atom, i = atom(i)
            out.append(text_atom)
            continue
        out.append(piece(tok))
        i += 1
    text_out = " ".join(out)
    return re.sub(r" ([\^_])\{", r"\1{", text_out).replace(" ,", ",")


def _unicode(ch: str) -> str | None:
    """A character of the text that is mathematics (φ, ², ₃, ≈) as TeX math, else None."""
    if ch in _SYMBOLS:
        return _SYMBOLS[ch]
    if ch in _GREEK_CHARS:
        return "\\" + _VAR.get(_GREEK_CHARS[ch], _GREEK_CHARS[ch])
    if ch in _SUPER:
        return f"^{{{_SUPER[ch]}}}"
    if ch in _SUB:
        return f"_{{{_SUB[ch]}}}"
    return None


def _word_text(word: str) -> str:
    """A plain word, escaped; a run of characters that are mathematics in it as inline math."""
    out, math = [], []
    for ch in word:
        m = _unicode(ch)
        if m is not None:
            math.append(m)
            continue
        if math:
            out.append("$" + "".join(math) + "$")
            math = []
        out.append(tex_escape(ch) if ch.isascii() else ch)
    if math:
        out.append("$" + "".join(math) + "$")
    return "".join(out)


def _code(text: str) -> str:
    """Typewriter type, as typed; a long name may break after its _ . / = : (never inside a word)."""
    tt = tex_escape(text).replace("-", "-{}")
    if len(text) > 16:  # one that could overrun a line
        tt = re.sub(r"(\\_|[./=:])(?=\w)", r"\1\\allowbreak{}", tt)
    return r"\texttt{" + tt + "}"


def _is_formula_token(tok: str, params: dict) -> bool:
    bare = tok.strip(",;.")
    if not bare:
        return False
    if bare in _SYMBOLS:
        return True  # ≈, ≠, ≤: a relation between formula words
    if any(ch in _SUPER or ch in _SUB or ch in _GREEK_CHARS for ch in bare) and all(ch.isascii() and ch.isalnum() or _unicode(ch) or ch in _MATH_LETTERS
                                                            or ch in "()" for ch in bare):
        return True  # a²w², λ², m²: written with the characters of mathematics
    if any(ch in _OPERATORS or ch in "()" for ch in bare) or bare in ("-", "+", "-+", "+-", "!="):
        return True
    if bare in params:
        return True
    if bare.lower() in _WORDS:
        return False
    return bool(re.fullmatch(r"\d+(\.\d+)?|[A-Za-z]\d*|[A-Za-z]\w{0,2}|(?:sqrt|" + "|".join(sorted(FUNCTIONS | GREEK)) + r")(?:_\w+)?", bare))


def typeset(text: str, params: dict | None = None) -> str:
    """``text`` (one line of the user's or of the facts) as LaTeX text; ``params``: a spec
    parameter's name → how the document prints it."""
    params = params or {}
    text = " ".join(text.split())
    out: list[str] = []
    for i, part in enumerate(re.split(r"`([^`]*)`", text)):
        if i % 2:
            out.append(_code(part))
        elif part.strip():
            out.append(_plain(part, params))
        elif part:
            out.append(part)
    return "".join(out).strip()


def _split_tail(word: str) -> tuple[str, str]:
    """A word's closing punctuation apart (the run's math ends before it)."""
    m = re.match(r"^(.*?)([,;.:]*)$", word)
    body, tail = m.group(1), m.group(2)
    if body.endswith(")") and body.count("(") < body.count(")"):  # "(steady ... w=1:2:3)": the bracket is the text's
        return body[:-1], ")" + tail
    return body, tail


def _is_code(word: str) -> bool:
    """An option, a file, an argument such as w=150:300:16, a field such as body[2].force[1], or a
    name with underscores that is not a symbol's index (wrist_3_link, base_link; not P_cr, j0_i)."""
    if _CODE.match(word):
        return True
    parts = word.split("_")
    return len(parts) > 1 and all(parts) and (len(parts) > 2 or len(parts[1]) > 3) and re.fullmatch(r"[\w.]+", word) is not None


def _plain(text: str, params: dict) -> str:
    words = text.split(" ")
    out, i = [], 0
    while i < len(words):
        body, tail = _split_tail(words[i])
        lead, bare = ("(", body[1:]) if body.startswith("(") and len(body) > 1 else ("", body)
        command = bare in COMMANDS and i + 1 < len(words) and words[i + 1].startswith("-")
        if command or bare.startswith("-") and _CODE.match(bare) or _is_code(bare) and not _is_formula_run(words, i):
            span, j = [bare], i + 1
            while not tail and j < len(words):
                b, t = _split_tail(words[j])
                if not (_is_code(b) or b.startswith("-")):
                    break
                span.append(b)
                tail, j = t, j + 1
            out.append(lead + _code(" ".join(span)) + tex_escape(tail))
            i = j
            continue
        # mathematics: a run of formula words with an operator in it, or a lone symbol; a unit after
        # its number stays a word
        j = i
        while j < len(words) and _is_formula_token(words[j], params) and not _is_code(_split_tail(words[j])[0]):
            j += 1
            if words[j - 1].rstrip(")").endswith((",", ";", ".")) and not re.fullmatch(r"\d+\.\d+", words[j - 1]):
                break
        run = words[i:j]
        if len(run) <= 1 and words[i].startswith("(") and _lone_symbol(_split_tail(words[i][1:])[0], params):
            body, tail = _split_tail(words[i][1:])  # "(l1 does not ...": the bracket is the sentence's
            out.append("($" + formula(body, params) + "$" + tex_escape(tail))
            i += 1
            continue
        units = []
        while run and _split_tail(run[-1])[0].strip("()") in UNITS and len(run) > 1:
            units.insert(0, run.pop())
        operator = any(any(ch in _OPERATORS for ch in w) or re.search(r"[A-Za-z]\(", w) or w in ("-+", "+-", "!=")
                       or w.strip(",;.") in _SYMBOLS for w in run)
        lone = len(run) == 1 and _lone_symbol(_split_tail(run[0])[0], params)
        if run and (operator or lone) and not _only_units(run):
            body, tail = _split_tail(" ".join(run))
            whole = " ".join(run)
            # a bracket the run opens and the text closes ("(λ² = 0.3 kg m²/s along ê²₃)") stays the text's
            opened = "(" if whole.startswith("(") and whole.count("(") > whole.count(")") else ""
            if units:  # "w = 198.09 rad/s,": the unit and the punctuation after the formula, as words
                out.append(opened + "$" + formula(whole[len(opened):], params) + "$~" + " ".join(_word_text(u) for u in units))
            else:
                out.append(opened + "$" + formula(body[len(opened):], params) + "$" + tex_escape(tail))
            i = j
            continue
        out.append(_word_text(words[i]))
        i += 1
    return " ".join(out)


def _is_formula_run(words, i) -> bool:
    return any(ch in "^*/<>" for ch in words[i]) and not re.search(r"\.\w+$", words[i])


def _lone_symbol(word: str, params: dict) -> bool:
    """A word that is a symbol by itself: a Greek name, a letter with its index (J0, O2, A11), a
    parameter of more than one letter (a one-letter one is an article or a word too often)."""
    if word in GREEK or re.fullmatch(r"(?:" + "|".join(GREEK) + r")_\w+", word):
        return True
    if re.fullmatch(r"[A-Z]\d{1,2}|[OSl]\d", word):
        return True
    return word in params and len(word) > 1


def _only_units(run: list[str]) -> bool:
    """"555 rad/s": a number and its unit are words, not a formula."""
    bare = [w.strip(",;.()") for w in run]
    return all(re.fullmatch(r"\d+(\.\d+)?", w) or w in UNITS for w in bare) and any(w in UNITS for w in bare)


_FIELD_WORDS = [  # the facts' field names (the CLI prints them as the spec's keys) in the document's words
    (r"base \(the platform moves\)", "the platform's motion"),
    (r"base\.rotation \((.*)\)", r"the platform's rotation (\1)"),
    (r"base\.position \((.*)\)", r"the platform's translation (\1)"),
    (r"body\[(\d+)\]\.lambda \(changes in time\)", r"the rotor of body \1, spinning up"),
    (r"body\[(\d+)\]\.damping", r"the damper of joint \1"),
    (r"body\[(\d+)\]\.spring", r"the spring of joint \1"),
    (r"body\[(\d+)\]\.torque", r"the torque expression of joint \1"),
    (r"body\[(\d+)\]\.force\[(\d+)\]", r"force \2 on body \1"),
    (r"body\[(\d+)\]\.moment\[(\d+)\]", r"moment \2 on body \1"),
]


def in_words(reasons: list[str]) -> list[str]:
    """The facts' reasons with their field names said in words ("the damper of joint 3"), and a
    run of the same kind for several joints said once ("the dampers of joints 1, 2, 3")."""
    out: list[str] = []
    runs: dict = {}
    for r in reasons:
        for pattern, words in _FIELD_WORDS:
            if re.fullmatch(pattern + r"(?: \(.*\))?", r) or re.match(pattern, r):
                r = re.sub(pattern, words, r, count=1)
                break
        m = re.fullmatch(r"the (damper|spring|torque expression) of joint (\d+)", r)
        if m:
            if m.group(1) in runs:
                runs[m.group(1)][1].append(m.group(2))
                continue
            runs[m.group(1)] = (len(out), [m.group(2)])
        out.append(r)
    for kind, (i, joints) in runs.items():
        if len(joints) > 1:
            out[i] = f"the {kind}s of joints " + ", ".join(joints)
    return out
