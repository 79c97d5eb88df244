"""Figures legible at the size the report shows them: no text under 8 pt on a figure at most 11 in
wide, no numpy repr in a text, units on every labelled axis, no additive offset on an axis; every
figure also as PDF; F11 checks the b symmetry from its data."""

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from conftest import SMOKE_RESULTS, smoke_config

from sleighsim.io import layout
from sleighsim.io.netcdf import write_dataset
from sleighsim.report import figures
from sleighsim.report.figures import catalog as figure_catalog
from sleighsim.report.figures.common import finish, legibility
from sleighsim.scenes import catalog

SMOKE_CFG = smoke_config()


def test_the_rule_finds_each_kind_of_illegible_text():
    fig, ax = plt.subplots(figsize=(14, 4))
    ax.plot([0, 1], [1000.001, 1000.002])
    ax.ticklabel_format(useOffset=True)
    ax.set_xlabel("t")
    ax.set_title(f"exponents {np.array([0.02, -0.01, -0.1])}", fontsize=6)
    found = "\n".join(legibility(fig))
    plt.close(fig)
    for problem in ("14 in wide", "6 pt", "numpy repr", "axis label without units: 't'", "offset"):
        assert problem in found, (problem, found)


def test_the_rule_finds_overlapping_tick_labels_and_finish_removes_them():
    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.loglog([2.5, 60], [1, 2])  # matplotlib labels the minor ticks of a short log axis
    ax.set_xlabel("t (time units)")
    ax.set_ylabel("ratio (unitless)")
    assert legibility(fig) == ["overlapping tick labels on the axis 't (time units)'"]
    assert legibility(finish(fig, {})) == []
    plt.close(fig)


def test_a_legible_figure_passes():
    fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
    ax.plot([0, 1], [1000.001, 1000.002])
    ax.set_xlabel("t (time units)")
    ax.set_ylabel("ratio (unitless)")
    ax.set_title("range [1.5, 2.5]")
    assert legibility(fig) == []
    plt.close(fig)


def grid_dataset(path, spread):
    """A small F11 grid: three eps rows, three b columns differing by ``spread`` x the row's stderr."""
    eps, b = np.array([0.1, 0.2, 0.4]), np.array([0.5, 1.0, 2.0])
    lam, err = np.array([0.05, 0.03, 0.04]), np.array([0.004, 0.002, 0.003])
    grid = lam[:, None] + spread * err[:, None] * np.array([0.0, 0.5, 1.0])
    ds = xr.Dataset({"lambda_1": ("eps", lam), "stderr": ("eps", err), "status": ("eps", ["converged"] * 3),
                     "flagged": ("eps", np.array([0, 1, 0], "int8")),
                     "b_check_max_diff": ("eps", [np.nan, 0.001, np.nan]),
                     "b_check_bound": ("eps", [np.nan, 0.01, np.nan]),
                     "lambda_1_grid": (("eps", "b"), grid, {"long_name": "lambda_1 on the grid"})},
                    coords={"eps": eps, "b": b},
                    attrs={"energy_label": 0.1127, "n_rows": 3, "fraction_flagged": 1 / 3, "reference_eps": 0.2,
                           "reference_rel_err": 0.07, "b_check": np.array([0.5, 2.0]), "scene": "grid",
                           "precision": "double"})
    ds["row_settled_state"] = (("eps", "component"), np.arange(12.0).reshape(3, 4) + 1.0)
    return write_dataset(ds, path)


def verdict_dataset(path, state=(5.0, 6.0, 7.0, 8.0), verdict="regular", eps=0.2):
    """A chaos verdict deciding one state, main, at ``eps`` (K2 = 1 + eps, b = 1), settled at ``state``."""
    one = lambda v: ("state", [v])  # noqa: E731
    ds = xr.Dataset(
        {"verdict": one(verdict), "n_realizations_agreeing": one(3), "decisive_lambda_max": one(8e-6),
         "decisive_bound_T": one(5e5), "decisive_bound_text": one("lambda_1 <= 8e-06 over T = 5e5"),
         "decisive_log10_gain_rounding": one(-11.8), "decisive_wall_time_s": one(125.0),
         "settled_state": (("state", "component"), [list(state)])},
        coords={"state": ["main"]},
        attrs={"n_realizations": 3, "decisive_precision": "double-double", "decisive_T": 5e5, "energy_label": 0.1127,
               "param_eps": eps, "param_K2": 1 + eps, "param_b": 1.0})
    return write_dataset(ds, path)


def test_fig10_carries_the_decided_bound_to_every_label_by_the_time_scaling_law(tmp_path):
    """Beside double's lambda_1 against E: the regular state's bound at the verdict's label, times sqrt(E / E0) at
    every label; at other parameters or for a state not regular, a legend entry saying none is drawn."""
    E = np.array([0.01, 0.1127, 1.0])
    energy = write_dataset(xr.Dataset(
        {"lambda_1": ("label", [2e-4, 7e-4, 2e-3]), "stderr": ("label", [2e-5, 7e-5, 2e-4]),
         "law": ("label", 7e-4 * np.sqrt(E / 0.1127))}, coords={"label": E},
        attrs={"reference_label": 0.1127, "param_eps": 0.2, "param_b": 1.0, "param_K2": 1.2, "fitted_exponent": 0.5,
               "fitted_exponent_stderr": 0.01, "T_reference": 1e5, "scene": "lyap_energy", "precision": "double"}),
        tmp_path / "energy.nc")
    fig = figures.build("fig10", [energy, verdict_dataset(tmp_path / "v.nc")])
    ax = fig.axes[0]
    handles, labels = ax.get_legend_handles_labels()
    bound = next(h for h, t in zip(handles, labels) if "main is regular" in t.replace("\n", " "))
    assert np.allclose(bound.get_ydata(), 8e-6 * np.sqrt(E / 0.1127)) and legibility(fig) == []
    plt.close(fig)
    for other in (verdict_dataset(tmp_path / "v1.nc", eps=0.1), verdict_dataset(tmp_path / "v2.nc", verdict="fragile")):
        fig = figures.build("fig10", [energy, other])
        labels = [t.replace("\n", " ") for t in fig.axes[0].get_legend_handles_labels()[1]]
        assert any(t.startswith("decisive stage: no bound drawn") for t in labels) and not any(
            "main is regular" in t for t in labels)
        plt.close(fig)


def test_fig11_draws_the_bound_of_a_row_the_chaos_verdict_decided(tmp_path):
    """The row at eps 0.2 settles to the state the chaos verdict decided regular: its bound is drawn beside
    double's lambda_1; a verdict on another state, or not regular, draws nothing."""
    grid = grid_dataset(tmp_path / "grid.nc", spread=0.0)
    for state, verdict, drawn in (((5.0, 6.0, 7.0, 8.0), "regular", True), ((5.0, 6.0, 7.0, 8.1), "regular", False),
                                  ((5.0, 6.0, 7.0, 8.0), "fragile", False)):
        fig = figures.build("fig11", [grid, verdict_dataset(tmp_path / "v.nc", state, verdict)])
        labels = " ".join(fig.axes[0].get_legend_handles_labels()[1]).replace("\n", " ")
        assert ("main is regular (3 of 3 realizations): lambda_1 <= 8e-06" in labels) is drawn, labels
        assert legibility(fig) == []
        plt.close(fig)


def test_fig11_draws_each_rows_own_verdict(tmp_path):
    """Rows judged by the grid itself (scenes.grid_verdict): a regular row's bound as a triangle, an undecided
    row ringed, a row not judged not drawn; a grid without row verdicts draws neither."""
    from sleighsim.io.netcdf import read_dataset, write_dataset

    ds = read_dataset(grid_dataset(tmp_path / "plain.nc", spread=0.0))
    judged = ds.assign(row_verdict=("eps", ["not judged", "undecided", "regular"]),
                       row_lambda_max=("eps", [np.nan, np.nan, 2e-3]),
                       row_verdict_arithmetic=("eps", ["", "double-double", "double-double"]),
                       row_verdict_reason=("eps", ["below eps_min", "only megno says chaotic", "all agree"]))
    for path, drawn in ((write_dataset(judged, tmp_path / "judged.nc"), True), (tmp_path / "plain.nc", False)):
        fig = figures.build("fig11", [path, verdict_dataset(tmp_path / "v.nc", (0.0, 0.0, 0.0, 0.0))])
        labels = " ".join(fig.axes[0].get_legend_handles_labels()[1]).replace("\n", " ")
        assert ("the row's own verdict: regular in double-double" in labels) is drawn, labels
        assert ("the row's own verdict in double-double: undecided" in labels) is drawn, labels
        assert "not judged" not in labels and legibility(fig) == []
        plt.close(fig)


def test_fig11_states_the_spread_across_b_from_its_data(tmp_path):
    fig = figures.build("fig11", [grid_dataset(tmp_path / "grid.nc", spread=2.5), verdict_dataset(tmp_path / "v.nc")])
    ax = fig.axes[0]
    title = " ".join(t.get_text().replace("\n", " ") for t in (ax.title, ax._left_title, *ax.texts))
    assert "Largest spread across the 3 b values of a row: 2.5 standard errors" in title
    assert "Recomputed at b = 0.5, 2 (eps 0.2): difference 0.5 standard errors (allowed 5)" in title
    assert "lambda_1 on the grid" in title
    labels = ax.get_legend_handles_labels()[1]
    assert {"grid at b = 0.5", "grid at b = 1", "grid at b = 2"} <= set(labels)
    assert legibility(fig) == []
    plt.close(fig)
    ax = figures.build("fig11", [grid_dataset(tmp_path / "copies.nc", spread=0.0),
                                 verdict_dataset(tmp_path / "v2.nc")]).axes[0]
    copies = " ".join(t.get_text().replace("\n", " ") for t in (ax._left_title, *ax.texts))
    assert ("The 3 b columns are copies (filled by the symmetry, not computed)" in copies
            and "largest spread" not in copies)


def figure_source(results, name):
    """What the figure rule gives ``name`` in the smoke run: its datasets (then those of its laddered
    scenes in every finer precision), or a schematic's config block."""
    fig = figure_catalog.FIGURES[name]
    if fig.schematic:
        return catalog.scene_config(SMOKE_CFG, fig.schematic)
    laddered = catalog.laddered(SMOKE_CFG, on_request=True)
    beside = [layout.variant(s, p) for s in (fig.data if fig.beside else ()) for p in laddered.get(s, ())
              if p != "double"]
    return [results / "data" / f"{d}.nc" for d in (*fig.data, *beside)]


@pytest.mark.workflow
def test_every_smoke_figure_is_legible_and_saved_for_a_paper(smoke_run):
    results = smoke_run / SMOKE_RESULTS
    problems = {}
    for name in figure_catalog.figures_built(SMOKE_CFG):
        assert (results / "figures" / f"{name}.pdf").read_bytes()[:5] == b"%PDF-", name
        fig = figures.build(name, figure_source(results, name))
        problems[name] = legibility(fig)
        plt.close(fig)
    assert not any(problems.values()), {k: v for k, v in problems.items() if v}


@pytest.mark.parametrize("word, colour", [("chaotic", "chaotic"), ("strange attractor", "chaotic"),
                                          ("mixed dynamics", "chaotic"), ("regular", "regular"),
                                          ("undecided", "undecided"), ("undetermined", "undecided"),
                                          ("fragile", "fragile"), ("a word it does not know", "undecided")])
def test_the_chaos_table_colours_each_verdict_and_class_as_the_report_does(word, colour):
    from sleighsim.report.figures.chaos import _shade
    from sleighsim.report.page import CHAOS_COLOURS

    assert _shade(word) == CHAOS_COLOURS[colour]
