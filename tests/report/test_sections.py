"""Snakemake's own report: each figure under its paper section, and the project's page as one file."""

import base64
import re

import pytest
from conftest import ROOT

from sleighsim.report import sections
from sleighsim.report.figures.catalog import FIGURES
from sleighsim.report.standalone import inline_images

TEX = ROOT / "paper" / "fedonyuk-tallapragada-sleigh-rotor.tex"
CLAIMS_MD = ROOT / "paper" / "CLAIMS.md"


def test_sections_are_numbered_in_order_and_hold_the_labels_inside_them(tmp_path):
    tex = tmp_path / "p.tex"
    tex.write_text(r"\section{Intro} \label{fig:a} \section{Model}\label{sec:m} x \label{eq:1} \label{fig:b}")
    names, where = sections.section_of_labels(tex)
    assert names == {"sec:m": "§2 Model"}
    assert where == {"fig:a": "§1 Intro", "sec:m": "§2 Model", "eq:1": "§2 Model", "fig:b": "§2 Model"}


def test_every_figure_lands_in_a_section_of_the_paper_or_the_methods():
    names, where = sections.section_of_labels(TEX)
    entries = sections.figure_entries(TEX, CLAIMS_MD)
    assert set(entries) == set(FIGURES)
    for name, fig in FIGURES.items():
        e = entries[name]
        assert e["category"] in set(names.values()) | {sections.METHODS}, name
        assert e["subcategory"] == (sections.PAPER if fig.paper else sections.ADDED)
        assert e["labels"]["figure"] == name
        assert not fig.section or fig.section in names, f"{name}: {fig.section} is no section label of the paper"
    # the paper places its figures: the schematic with the equations, the Lyapunov figures on the attractor
    assert entries["fig1"]["category"] == "§2 Equations of Motion"
    assert entries["fig10"]["category"] == entries["fig9"]["category"] == names["sec:chaos"]
    assert entries["fig5"]["labels"]["paper"] == "F5 (fig:two_link_short)"


def test_the_standalone_page_inlines_every_image_beside_it(tmp_path):
    png = b"\x89PNG\r\n\x1a\nnot really"
    (tmp_path / "a.png").write_bytes(png)
    page = tmp_path / "index.html"
    page.write_text('<p><img src="a.png" alt="a"> <img alt="x" src="data:image/png;base64,AA=="></p>')
    out = inline_images(page)
    uris = re.findall(r'src="data:image/png;base64,([^"]+)"', out)
    assert [base64.b64decode(u) for u in uris] == [png, b"\x00"]
    (tmp_path / "a.png").unlink()
    with pytest.raises(FileNotFoundError):
        inline_images(page)
