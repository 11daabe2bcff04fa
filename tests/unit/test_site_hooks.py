"""The site's build-time steps (mkdocs_hooks.py), on snippets: no MkDocs run, no browser."""
from __future__ import annotations

import re
import sys

from conftest import ROOT

sys.path.insert(0, str(ROOT))
import mkdocs_hooks as hooks  # noqa: E402


def test_a_power_of_a_function_stays_a_power():
    """sin² x is a power whose base is sin: the thin spaces around a function name go outside the
    msup, which keeps its two children (inside, it typeset as a small "sin 2")."""
    ml = hooks.mathml(r"\cos^2\varphi^2 + \sin x", False)
    for sup in re.findall(r"<msup>(.*?)</msup>", ml):
        assert "<mspace" not in sup, sup
    assert "<msup><mi>cos</mi><mn>2</mn></msup>" in ml
    assert re.search(r'<mspace width="0.167em"></mspace><mi>sin</mi><mspace width="0.167em"></mspace>', ml)


def test_long_code_in_a_table_wraps_and_short_flags_never_break():
    html = ("<table><tr><td><code>{auto,forward,world,world-solve,world-inverse}</code></td>"
            "<td><code>-O3</code></td></tr></table><p>with <code>--base</code> and <code>-Werror</code></p>"
            "<pre><code>--not-touched</code></pre>")
    out = hooks.wrap_long_code(html)
    assert ('<code class="gc-wrap">{auto,<wbr>forward,<wbr>world,<wbr><span class="gc-nobreak">world-solve,</span><wbr>'
            '<span class="gc-nobreak">world-inverse}</span></code>') in out, out
    assert '<code class="gc-whole">--base</code>' in out and '<code class="gc-whole">-Werror</code>' in out
    assert '<code class="gc-whole">-O3</code>' in out
    assert "<pre><code>--not-touched</code></pre>" in out


def test_a_chart_with_a_phone_variant_is_a_picture():
    img = '<p><img alt="a chart" src="img/x.png" /></p>'
    plain = hooks.figures(img)
    assert "<picture>" not in plain and 'href="img/x.png"' in plain
    both = hooks.figures(img, lambda src: src.replace(".png", ".phone.png"))
    assert f'<picture><source media="{hooks.PHONE}" srcset="img/x.phone.png"><img' in both
    assert 'href="img/x.png"' in both and "<figcaption>a chart</figcaption>" in both


def test_a_formula_keeps_its_full_stop():
    out = hooks.keep_punctuation("<p>the angle <math><mi>φ</mi></math>. Then</p>")
    assert out == '<p>the angle <span class="gc-nobreak"><math><mi>φ</mi></math>.</span> Then</p>'
    two = "<p><math><mi>a</mi></math> and a long text <math><mi>b</mi></math>, then</p>"  # one formula at a time
    assert hooks.keep_punctuation(two) == ('<p><math><mi>a</mi></math> and a long text '
                                           '<span class="gc-nobreak"><math><mi>b</mi></math>,</span> then</p>')
