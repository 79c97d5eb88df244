"""Figures a journal accepts: PDFs embed TrueType fonts (never Type 3), dense point clouds and curves are
rasterised (the text and axes stay vector), and the legibility rule refuses long titles, NaN, empty panels,
insets over the data and text cut at the figure's edge."""

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
from conftest import SMOKE_RESULTS, smoke_config

from sleighsim.report.figures import catalog as figure_catalog
from sleighsim.report.figures.common import DENSE, DENSE_LINE, legibility, rasterise_dense, save_figure

FONT_TYPE = re.compile(rb"/Subtype\s*/(Type3|Type1|TrueType|Type0|CIDFontType0|CIDFontType2)\b")


def font_types(pdf: bytes) -> set[str]:
    """The font subtypes a PDF written by matplotlib declares (its font dictionaries are not compressed)."""
    return {m.decode() for m in FONT_TYPE.findall(pdf)}


def test_a_saved_pdf_embeds_truetype_fonts_and_rasterises_only_its_dense_artists(tmp_path):
    rng = np.random.default_rng(1)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(8, 3), layout="constrained")
    cloud = ax.scatter(*rng.normal(size=(2, DENSE + 1)), s=0.5)
    few = ax.scatter(*rng.normal(size=(2, DENSE)), s=0.5)
    long_line, = bx.plot(np.linspace(0, 1, DENSE_LINE + 1))
    short_line, = bx.plot(np.linspace(0, 1, DENSE_LINE))
    ax.set_title(r"$\lambda_1$ against $\epsilon$ (unitless)")
    path = tmp_path / "f.pdf"
    save_figure(fig, path, tmp_path / "f.png")
    pdf = path.read_bytes()
    assert font_types(pdf) and "Type3" not in font_types(pdf) and b"/FontFile2" in pdf
    assert cloud.get_rasterized() and long_line.get_rasterized()
    assert not few.get_rasterized() and not short_line.get_rasterized()
    assert len(re.findall(rb"/Subtype\s*/Image", pdf)) >= 2  # the cloud and the long line, as images
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    assert rasterise_dense(fig) == 0
    plt.close(fig)


def _problems(build) -> str:
    fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    ax.set_xlabel("t (time units)")
    ax.set_ylabel("u (length units)")
    build(fig, ax)
    found = "\n".join(legibility(fig))
    plt.close(fig)
    return found


@pytest.mark.parametrize("build, problem", [
    (lambda fig, ax: (ax.plot([0, 1]), ax.set_title("one\ntwo\nthree")), "a title of 3 lines"),
    (lambda fig, ax: (ax.plot([0, 1]), ax.set_title("tail ~T^nan")), "NaN in a text"),
    (lambda fig, ax: ax.set_title("nothing here"), "an empty panel: 'nothing here'"),
    (lambda fig, ax: (ax.axhline(0.5), ax.axvspan(0.2, 0.4), ax.set_title("references only")),
     "an empty panel: 'references only'"),
    (lambda fig, ax: (ax.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50)),
                      ax.inset_axes([0.3, 0.3, 0.4, 0.4]).plot([0, 1])), "an inset over the data"),
    (lambda fig, ax: (ax.plot([0, 1]), fig.text(0.8, 0.5, "a note far too long to fit " * 3)),
     "a text cut at the figure's edge"),
])
def test_the_rule_refuses_what_a_journal_would(build, problem):
    assert problem in _problems(build)


@pytest.mark.parametrize("build", [
    lambda fig, ax: (ax.plot([0, 1]), ax.set_title("one\ntwo")),
    lambda fig, ax: (ax.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50)),
                     ax.inset_axes([0.05, 0.6, 0.3, 0.35]).plot([0, 1])),  # an inset off the data
    lambda fig, ax: (ax.plot([0, 1]), ax.set_title("financial nano-scale")),
    lambda fig, ax: ax.barh(["a", "b"], [3.0, 1.0]),  # bars are data (a patch's transform holds its shape)
])
def test_the_rule_passes_a_figure_a_journal_would_take(build):
    assert _problems(build) == ""


@pytest.mark.workflow
def test_every_smoke_pdf_embeds_no_type3_font(smoke_run):
    figures = smoke_run / SMOKE_RESULTS / "figures"
    built = figure_catalog.figures_built(smoke_config())
    found = {name: font_types((figures / f"{name}.pdf").read_bytes()) for name in built}
    assert all(found.values()) and not {n: t for n, t in found.items() if "Type3" in t}, found


@pytest.mark.parametrize("horizon, words", [(float("nan"), "no audited tangent judge votes"),
                                            (4.0, "votes at horizon 4")])
def test_the_chaos_figures_note_names_the_vote_horizon_never_nan(horizon, words):
    """The decisive stage records NaN as its vote horizon when no audited horizon lets a judge vote (the
    smoke run's case): the note says so in words."""
    import xarray as xr

    from sleighsim.report.figures.chaos import _section_note

    note = _section_note(xr.Dataset(attrs={"decisive_vote_horizon": horizon}))
    assert note.endswith(words) and "nan" not in note
