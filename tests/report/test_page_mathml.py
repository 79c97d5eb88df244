"""The report's caption MathML: latex2mathml's output kept to its own elements and attributes."""

import re

from sleighsim.report.page import math_html, mathml


def test_markup_smuggled_in_a_text_command_does_not_reach_the_page():
    out = str(math_html(r"a caption $\text{<svg/onload=alert(1)>}$ and more"))
    assert "<svg" not in out and "onload" not in out and "alert" not in out
    assert out.startswith("a caption <math") and out.endswith("</math> and more")


def test_a_link_command_loses_its_javascript_url():
    out = mathml(r"\href{javascript:alert(1)}{x}")
    assert "href" not in out and "javascript" not in out and "<mi>x</mi>" in out


def test_a_normal_formula_still_renders_as_mathml():
    out = str(math_html(r"rate $\lambda_1 = \frac{a}{b^2}$ per time unit"))
    assert out.startswith('rate <math xmlns="http://www.w3.org/1998/Math/MathML" display="inline">')
    assert "<msub><mi>λ</mi><mn>1</mn></msub>" in out and "<mfrac>" in out
    assert "<msup><mi>b</mi><mn>2</mn></msup>" in out
    tags = set(re.findall(r"<(\w+)", out))
    assert tags == {"math", "mrow", "msub", "mi", "mn", "mo", "mfrac", "msup"}


def test_a_matrix_keeps_its_layout_attributes():
    out = mathml(r"\begin{matrix}a & b\\c & d\end{matrix}")
    assert out.count("<mtr>") == 2 and out.count("<mtd>") == 4
    styled = mathml(r"\displaystyle \sum_{i=1}^n i")
    assert '<mstyle displaystyle="true" scriptlevel="0"><msubsup>' in styled
