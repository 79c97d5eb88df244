"""Config validation before any job: the schema (bounds, types, kinds), and what it cannot see
(NaN and infinity, tolerances, cross-field constraints, inputs, memory), on the smoke config
with one value broken at a time. The end-to-end check that Snakemake stops before any job is
in test_workflow.py."""

import copy
import json
import math

import jsonschema
import pytest
import yaml
from conftest import PAPER, ROOT, smoke_config

from sleighsim.io import layout
from sleighsim.ops import configcheck
from sleighsim.ops.configcheck import ConfigError
from sleighsim.scenes import catalog

SCHEMA_PATH = ROOT / "workflow" / "schemas" / "config.schema.yaml"
SCHEMA = yaml.safe_load(SCHEMA_PATH.read_text())
SMOKE = smoke_config()  # config/smoke.yaml is an overlay: merged onto config/config.yaml
VALIDATOR = jsonschema.validators.validator_for(SCHEMA)(SCHEMA)
PLENTY = 1e15  # bytes: memory is not the question in most tests


def refused(cfg) -> str:
    """The error message of the schema or of the config checks, or '' when the config passes."""
    errors = list(VALIDATOR.iter_errors(cfg))
    if errors:
        return " ".join(e.message + " " + ".".join(map(str, e.absolute_path)) for e in errors)
    try:
        configcheck.check(cfg, available_memory=PLENTY)
    except ConfigError as err:
        return str(err)
    return ""


def numeric_leaves(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from numeric_leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from numeric_leaves(v, path + (i,))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path


def with_value(path, value, cfg=SMOKE):
    cfg = json.loads(json.dumps(cfg))  # a copy without YAML aliases (blocks shared by anchors), so only path changes
    node = cfg
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return cfg


def dotted(path):
    return ".".join(str(p) if not isinstance(p, int) else f"[{p}]" for p in path).replace(".[", "[")


def test_the_smoke_config_passes():  # the schema's kinds: tests/scenes/test_catalog.py
    assert refused(copy.deepcopy(SMOKE)) == ""


@pytest.mark.parametrize("bad", [float("nan"), math.inf, -math.inf])
def test_every_number_that_is_not_finite_is_refused_naming_its_key(bad):
    """The checks refuse NaN and infinity at every number of the config, naming the key."""
    leaves = list(numeric_leaves(SMOKE))
    assert len(leaves) > 200
    for p in leaves:
        with pytest.raises(ConfigError) as err:
            configcheck.check(with_value(p, bad), available_memory=PLENTY)
        assert str(err.value).startswith(f"{dotted(p)} = {bad}"), str(err.value)


def test_the_schema_alone_lets_nan_through():
    """Why the check above exists: every comparison with NaN is false, so bounds pass it."""
    for p in [("scenes", "fig3", "t_end"), ("defaults", "tol"), ("scenes", "fig11_grid", "eps_range", 0)]:
        assert not list(VALIDATOR.iter_errors(with_value(p, float("nan")))), p


@pytest.mark.parametrize("bad", [0.0, 1.0, 1.5, -1e-3])
def test_every_tolerance_outside_0_1_is_refused(bad):
    tols = [p for p in numeric_leaves(SMOKE) if configcheck._is_tolerance(dotted(p))]
    names = {str(p[-1]) if not isinstance(p[-1], int) else str(p[-2]) for p in tols}
    assert {"tol", "scipy_rtol", "DOP853", "heyoka_tols", "rtol"} <= names
    for p in tols:
        with pytest.raises(ConfigError, match=r"is a tolerance and must lie in \(0, 1\)"):
            configcheck.check_numbers(with_value(p, bad))


CROSS_FIELD = [
    (("scenes", "fig7", "t_sample_start"), 20000.0, r"scenes.fig7.t_sample_start = 20000.0 must lie in"),
    (("scenes", "fig3", "dt"), 1e6, r"scenes.fig3.dt = 1000000.0 must lie in"),
    (("scenes", "fig6", "fit_window"), [50.0, 500.0], r"scenes.fig6.fit_window = \[50.0, 500.0\] must be increasing"),
    (("scenes", "fig4", "compare_window"), 1e9, r"scenes.fig4.compare_window = 1000000000.0 must lie in"),
    (("scenes", "fig4", "smooth"), 900.0, r"scenes.fig4.smooth = 900.0 must lie in"),
    (("scenes", "psd_eps01", "check_duration"), 1e6, r"scenes.psd_eps01.check_duration = 1000000.0 must lie in"),
    (("scenes", "psd_eps01", "welch", "segment"), 1e6, r"scenes.psd_eps01.welch.segment = 1000000.0 must lie"),
    (("scenes", "fig9_ref", "transient", "window"), 200.0, r"scenes.fig9_ref.transient.window = 200.0 must lie in"),
    (("scenes", "fig11_grid", "n_chunks"), 9, r"scenes.fig11_grid.n_chunks = 9 must lie in \[1, n_eps = 3\]"),
    (("scenes", "fig11_grid", "reference_eps"), 0.1, r"scenes.fig11_grid.reference_eps = 0.1 must lie in eps_range"),
    (("scenes", "fig11_grid", "eps_range"), [0.5, 0.2],
     r"scenes.fig11_grid.eps_range = \[0.5, 0.2\] must be increasing"),
    (("scenes", "fig11_grid", "elsewhere"), {"eps": [0.02]},
     r"scenes.fig11_grid.elsewhere.eps: 0.02 is not a row of the grid \(\[0.2, 0.3162, 0.5\]\)"),
    (("scenes", "fig11_grid", "elsewhere"), {"eps": [0.5]}, None),  # a row of the smoke grid, not the reference: passes
    (("scenes", "formal_exponents", "elsewhere"), {"eps": [50.0, 2.0]},
     r"scenes.formal_exponents.elsewhere.eps: \[2.0\] also in scenes.formal_exponents.eps"),
    (("scenes", "fig2", "portrait", "u_range"), [1.0, -1.0], r"scenes.fig2.portrait.u_range = \[1.0, -1.0\] must be"),
    (("scenes", "fig3", "params", "K2"), 1e-9 + 1.0, None),  # admissible: passes
    (("scenes", "fig9_ref", "params"), {"m_c": 1.0, "m_r": 0.1, "I_c": 0.1, "I_r": 0.0, "a": 0.0, "b": 1.0},
     r"scenes.fig9_ref.params: inertia is not positive definite"),
    (("scenes", "fig9_scaling", "inputs", "reference"), "fig9_nowhere",
     r"scenes.fig9_scaling.inputs.reference = 'fig9_nowhere' is not a scene"),
    (("scenes", "chaos_verdict", "transient", "window"), 1000.0,
     r"scenes.chaos_verdict.transient.window = 1000.0 must lie in"),
    (("scenes", "fig9_scaling", "inputs", "scaled"), "fig1",
     r"scenes.fig9_scaling.inputs.scaled = 'fig1' is not a scene"),
]


@pytest.mark.parametrize("path, value, message", CROSS_FIELD, ids=[dotted(c[0]) for c in CROSS_FIELD])
def test_cross_field_constraints(path, value, message):
    cfg = with_value(path, value)
    assert not list(VALIDATOR.iter_errors(cfg)), "the schema alone cannot see this case"
    if message is None:
        configcheck.check(cfg, available_memory=PLENTY)
    else:
        with pytest.raises(ConfigError, match=message):
            configcheck.check(cfg, available_memory=PLENTY)


def test_records_that_would_not_fit_in_memory_are_refused_with_the_size():
    cfg = with_value(("scenes", "fig3", "t_end"), 1e11)
    with pytest.raises(ConfigError, match=r"scenes.fig3: \(t_end - t_sample_start\) / dt = 2e\+11 samples of 7 "
                                          r"variables would need about 4.17e\+04 GiB in memory; this machine has"):
        configcheck.check(cfg)
    configcheck.check(copy.deepcopy(SMOKE))  # the real machine holds the smoke config
    with pytest.raises(ConfigError, match=r"scenes.fig11_grid: t_pre / transient.dt"):
        configcheck.check_memory("fig11_grid", "lyapunov_grid", SMOKE["scenes"]["fig11_grid"], available=100.0)
    kinds_estimated = {k for k in catalog.KINDS if catalog.KINDS[k].records(_block_of_kind(k))}
    assert kinds_estimated >= {"trajectory", "poincare", "psd", "attractor_levels", "lyapunov_grid", "bench"}


def _block_of_kind(kind):
    return next(catalog.scene_config(SMOKE, n) for n, b in SMOKE["scenes"].items() if b["kind"] == kind)


@pytest.mark.parametrize("path, value, why", [
    (("scenes", "fig3", "kind"), "trajectroy", "'trajectroy' is not one of"),
    (("scenes", "fig3", "colour"), "red", "Additional properties are not allowed"),
    (("scenes", "fig9"), {"y0": [0, 0, 0, 0]}, "'kind' is a required property"),
    (("scenes", "fig8", "t_end"), -5.0, "less than or equal to the minimum"),
    (("scenes", "fig3", "dt"), "fast", "'fast' is not of type 'number'"),
    (("scenes", "fig5", "order"), 7, "greater than the maximum"),
    (("defaults", "tol"), 0.0, "less than the minimum of 2.220446049250313e-16"),
])
def test_the_schema_refuses_unknown_kinds_keys_types_and_bounds(path, value, why):
    assert why in refused(with_value(path, value))


@pytest.mark.parametrize("name", ["config.yaml", "smoke.yaml", "cluster.yaml"])
def test_shipped_configs_are_valid_merged_as_snakemake_merges_them(name):
    from snakemake.common.configfile import load_configfile
    from snakemake.utils import update_config

    cfg = load_configfile(str(ROOT / "config" / "config.yaml"))
    update_config(cfg, load_configfile(str(ROOT / "config" / name)))
    assert refused(cfg) == ""
    configcheck.check(cfg)


def strict_differences(a, b, path="") -> list[str]:
    """Where ``a`` and ``b`` differ, type included (1 is not 1.0, True is not 1), lists in order."""
    if type(a) is not type(b):
        return [f"{path or '.'}: {a!r} ({type(a).__name__}) != {b!r} ({type(b).__name__})"]
    if isinstance(a, dict):
        out = [f"{path}.{k}: only in the {'first' if k in a else 'second'}" for k in sorted(a.keys() ^ b.keys())]
        return out + [d for k in a.keys() & b.keys() for d in strict_differences(a[k], b[k], f"{path}.{k}")]
    if isinstance(a, list):
        if len(a) != len(b):
            return [f"{path}: {len(a)} items != {len(b)} items"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in strict_differences(x, y, f"{path}[{i}]")]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def test_the_smoke_overlay_repeats_no_paper_value():
    """Minimal overlay: no value in config/smoke.yaml equals (type included) the one config/config.yaml
    sets at the same key; a mapping only descends into the keys it changes."""
    from snakemake.common.configfile import load_configfile

    def repeated(overlay, paper, path=""):
        for key, value in overlay.items():
            if key not in paper:
                continue
            if isinstance(value, dict) and isinstance(paper[key], dict):
                yield from repeated(value, paper[key], f"{path}.{key}")
            elif not strict_differences(value, paper[key]):
                yield f"{path}.{key}"

    overlay = load_configfile(str(ROOT / "config" / "smoke.yaml"))
    assert list(repeated(overlay, load_configfile(str(PAPER)))) == []


def test_config_readme_is_generated_from_the_schema_and_documents_every_key():
    from sleighsim.ops import configdoc

    assert configdoc.main(["--schema", str(SCHEMA_PATH), "--out", str(ROOT / "config" / "README.md"), "--check"]) == 0
    undocumented = []

    def visit(node, path):
        node = configdoc._resolve(SCHEMA, node)
        for key, sub in node.get("properties", {}).items():
            full = configdoc._resolve(SCHEMA, sub)
            if key not in ("kind",) and not full.get("description"):
                undocumented.append(f"{path}{key}")
            visit(sub, f"{path}{key}.")
        if isinstance(node.get("items"), dict):
            visit(node["items"], f"{path}[].")

    for name in ["scene", *catalog.KINDS, "transient", "params"]:
        visit(SCHEMA["$defs"][name], f"{name}.")
    visit({k: v for k, v in SCHEMA.items() if k != "$defs"}, "")
    assert not undocumented, undocumented
    for key in ("scenes.fig11_grid.n_chunks", "defaults.tol", "transient.spike_factor"):  # spot checks
        assert f"`{key.split('.')[-1]}`" in (ROOT / "config" / "README.md").read_text()


@pytest.mark.parametrize("bad", [["long double", "double"], ["double", "quad", "long double"], ["double"],
                                 ["double", "double"], ["double", "single"]])
def test_a_precision_ladder_out_of_order_or_unknown_is_refused(bad):
    assert "precisions" in refused(with_value(("scenes", "fig9_ref", "precisions"), bad))


def test_double_double_is_refused_in_the_ladder_of_a_kind_whose_engine_lacks_it():
    """Only the poincare and psd kinds run their steady state in double-double (the path and tangent vectors are
    not in that engine): a trajectory's ladder naming it is refused before any job, naming the key."""
    assert refused(with_value(("scenes", "fig9_ref", "precisions"), ["double", "double-double"])) == ""
    assert "precisions" in refused(with_value(("scenes", "fig7", "precisions"), ["double", "double-double"]))


def test_a_gauge_without_a_ladder_is_refused():
    cfg = with_value(("scenes", "fig7", "gain"), {"T": 400.0, "tau": 2.0})
    assert refused(cfg) == ""
    del cfg["scenes"]["fig7"]["precisions"]
    assert "'precisions' is a dependency of 'gain'" in refused(cfg)


def test_laddered_scenes_and_their_datasets_are_named_by_the_registry():
    ladders = catalog.laddered(SMOKE)
    assert ladders["fig9_ref"] == ["double", "double-double"]
    assert "precision_ladder" not in ladders  # its own precisions are a parameter, not a ladder of the scene
    assert layout.variant("fig9_ref", "long double") == "precision/long_double/fig9_ref"
    assert layout.variant("fig9_ref", "double") == "fig9_ref" and layout.ladder("x") == "ladder/x"
    cfg = catalog.scene_config(SMOKE, "fig9_ref")
    assert "precisions" not in cfg  # the double dataset does not depend on its ladder
    assert catalog.scene_config(SMOKE, "precision_ladder")["precisions"]
