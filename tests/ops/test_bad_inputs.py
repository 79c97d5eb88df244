"""Issue 31: every bad input a new user tried is refused before any work, naming the key (or the
argument) and its admissible range: config values through the schema and sleighsim.ops.configcheck,
library calls through their own argument checks."""

import math
import re
import subprocess
import sys

import numpy as np
import pytest
import yaml
from test_config import PLENTY, ROOT, SCHEMA, SMOKE, refused, with_value

from sleighsim.engine.ddbatch import MAX_WIDTH
from sleighsim.model.params import Params
from sleighsim.ops import configcheck
from sleighsim.ops.configcheck import ConfigError
from sleighsim.ops.configdoc import _resolve
from sleighsim.precision import Precision
from sleighsim.scenes import catalog

REF = [0.0, 0.1, 1.0, 0.0]
P = Params.paper(eps=0.1)

CONFIG_ROWS = [
    (("results",), "", r"'' does not match '\[\^/\]' results"),
    (("results",), "/", r"'/' does not match '\[\^/\]' results"),
    (("defaults", "tol"), 1e-300, r"1e-300 is less than the minimum of 2.220446049250313e-16 defaults.tol"),
    (("scenes", "fig3", "tol"), 1e-17, r"less than the minimum of 2.220446049250313e-16 scenes.fig3.tol"),
    (("scenes", "trigger_law", "tols", "quad"), [1e-35], r"less than the minimum of 1.925929944387236e-34"),
    (("scenes", "main_drift", "precision"), "long_double",
     r"'long_double' is not one of \['double', 'long double', 'quad'\]"),
    (("scenes", "chaos_verdict", "decisive", "precision"), "double double",
     r"'double double' is not one of \['double', 'long double', 'double-double', 'quad'\]"),
    (("scenes", "trigger_law", "tols", "long double"), [1e-12, 1e-20], r"less than the minimum of 1.08"),
    (("scenes", "integration_error", "rtols"), [1e-3, 1e-15], r"less than the minimum of 2.220446049250313e-14"),
    (("scenes", "fig3", "params"), {"eps": 0.1, "m_c": 5}, r"'m_c' is not one of \['eps', 'b', 'K2'\]"),
    (("scenes", "fig3", "params"), {"m_c": 0.9, "m_r": 0.1, "I_c": 0.1, "I_r": 0.01, "a": 0.1, "b": 1.0, "K2": 1.1},
     r"'K2' is not one of \['m_c', 'm_r', 'I_c', 'I_r', 'a', 'b'\]"),
    (("scenes", "fig3", "params"), {"m_c": 1.0, "m_r": 0.0, "I_c": 0.1, "I_r": 0.01, "a": 0.1, "b": 1.0},
     r"0.0 is less than or equal to the minimum of 0 scenes.fig3.params.m_r"),
    (("scenes", "fig11_grid", "n_chunks"), 3.0,
     r"scenes.fig11_grid.n_chunks = 3.0 must be an integer \(write 3, without a decimal point\)"),
    (("scenes", "basins", "n_samples"), 101.0, r"scenes.basins.n_samples = 101.0 must be an integer"),
    (("scenes", "fig3", "dt"), 400.0,
     r"scenes.fig3.dt = 400.0 must lie in \(0, \(t_end - t_sample_start\) = 300\)"),
    (("scenes", "fig7", "t_sample_start"), 300.0,
     r"scenes.fig7.t_sample_start = 300.0 must lie in \[0, t_end = 300.0\)"),
    (("scenes", "k2_sweep", "hierarchy", "dt"), 70.0,
     r"scenes.k2_sweep.hierarchy.dt = 70.0 must lie in \(0, hierarchy.t_end"),
    (("scenes", "lyap_protocol", "tau_check"), 1.0,
     r"scenes.lyap_protocol.tau_check = 1.0 must be at least n_blocks x tau"),
    (("scenes", "main_drift", "window"), 200.2,
     r"scenes.main_drift.window = 200.2 must be a multiple \(at least 2\) of tau"),
    (("scenes", "trigger_law", "price_record"), "benchmarks/ddbatch.yaml",
     r"scenes.trigger_law.price_record = 'benchmarks/ddbatch.yaml': not a sleighsim.multiprec/1 record"),
    (("scenes", "trigger_law", "fate", "dt"), 2.0, r"2.0 is greater than the maximum of 1.0"),
]


@pytest.mark.parametrize("path, value, message", CONFIG_ROWS,
                         ids=[f"{'.'.join(map(str, p))}={v}" for p, v, _ in CONFIG_ROWS])
def test_every_bad_config_value_is_refused_naming_the_key_and_range(path, value, message):
    assert re.search(message, refused(with_value(path, value))), refused(with_value(path, value))


def test_every_kind_has_a_memory_and_sampling_estimate_and_integrating_kinds_hold_records():
    for name, block in SMOKE["scenes"].items():
        cfg = catalog.scene_config(SMOKE, name)
        spans = catalog.KINDS[block["kind"]].records(cfg)
        assert bool(spans) == (block["kind"] not in ("schematic", "attractor_scaling", "paper_setup")), name


MEMORY_ROWS = [
    (("scenes", "k2_sweep", "t_end"), 1e10,
     r"scenes.k2_sweep: t_end / dt = 4e\+10 samples of 4 variables would need about 4.77e\+03 GiB in memory; this "
     r"machine has 16 GiB"),
    (("scenes", "lyap_protocol", "T"), 1e15, r"scenes.lyap_protocol: T / tau = 2e\+15 samples of 4 variables"),
    (("scenes", "lyap_energy", "T"), 1e12, r"scenes.lyap_energy: T / tau x len\(labels\) = 3e\+11 samples of 5"),
    (("scenes", "main_drift", "t_transient"), 1e12, r"scenes.main_drift: t_transient / transient.dt = 2e\+12"),
    (("scenes", "integration_error", "t_end"), 1e12, r"scenes.integration_error: t_end / dt = 4e\+12"),
    (("scenes", "fig11_grid", "n_eps"), 10**9, r"scenes.fig11_grid: n_eps x n_b = 2e\+09 samples of 20 variables"),
]


@pytest.mark.parametrize("path, value, message", MEMORY_ROWS, ids=[".".join(p[1:]) for p, _, _ in MEMORY_ROWS])
def test_records_of_every_kind_that_would_not_fit_in_memory_are_refused(path, value, message):
    with pytest.raises(ConfigError, match=message):
        configcheck.check(with_value(path, value), available_memory=16 * 2**30)


LONG_RUNS = [
    (("scenes", "hardcases", "T_long"), 1e15,  # 100 samples: memory is no question
     r"scenes.hardcases: about 1e\+15 time units .* at least 1.39e\+05 CPU days \(limit 30\); its longest horizon "
     r"T_long = 1e\+15 must be shorter"),
    (("scenes", "main_drift", "T"), 1e12, r"scenes.main_drift: .* 139 CPU days .* horizon T = 1e\+12"),
    (("scenes", "fig11_grid", "T_round"), 1e13,  # chunked: the largest chunk's rows decide
     r"scenes.fig11_grid: .* CPU days \(limit 30\); more chunks \(n_chunks = \d+\) or shorter horizons "
     r"\(the longest: "),
    (("scenes", "chaos_verdict", "n_chunks"), 400,
     # 400 x 3 first-stage jobs, then one decisive job per block of the host's widest vector (ddbatch.MAX_WIDTH)
     rf"scenes.chaos_verdict.n_chunks = 400 would make {1200 + math.ceil(1200 / MAX_WIDTH)} jobs; at most 1000"),
    (("scenes", "lyap_spectrum", "realizations"), 5000, r"scenes.lyap_spectrum.realizations = 5000 would make"),
]


@pytest.mark.parametrize("path, value, message", LONG_RUNS, ids=[".".join(p[1:]) for p, _, _ in LONG_RUNS])
def test_runs_that_cannot_finish_or_plan_are_refused_by_the_runtime_and_job_estimates(path, value, message):
    with pytest.raises(ConfigError, match=message):
        configcheck.check(with_value(path, value), available_memory=PLENTY)


def test_the_integer_keys_are_those_the_schema_types_as_integers():
    found = set()

    def visit(node, name):
        node = _resolve(SCHEMA, node) if isinstance(node, dict) else node
        if isinstance(node, dict):
            if node.get("type") == "integer":
                found.add(name)
            for key, sub in node.get("properties", {}).items():
                visit(sub, key)
            for key in ("items", "additionalProperties", "then", "else"):
                if isinstance(node.get(key), dict):
                    visit(node[key], name)
            for sub in node.get("allOf", []):
                visit(sub, name)

    visit(SCHEMA, "")
    assert found == configcheck.INTEGER_KEYS


@pytest.mark.parametrize("value", ["", "/"])
def test_snakemake_stops_on_an_empty_or_root_results_directory_before_any_job(tmp_path, value):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({"results": value}))
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(tmp_path),
           "--configfile", str(ROOT / "config" / "smoke.yaml"), str(bad), "-n", "-c1", "--nolock"]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    out = res.stdout + res.stderr
    assert res.returncode != 0 and f"results: {value!r} does not match '[^/]'" in out, out[-2000:]
    assert "/data/" not in out and "Traceback" not in out


def test_params_refuse_wrong_types_mixed_forms_and_a_massless_rotor():
    with pytest.raises(TypeError, match=r"eps = '0.1' must be a real number"):
        Params.paper(eps="0.1")
    with pytest.raises(TypeError, match=r"b = None must be a real number"):
        Params.paper(eps=0.1, b=None)
    with pytest.raises(TypeError, match=r"m_c = True must be a real number"):
        Params.physical(m_c=True, m_r=0.1, I_c=0.1, I_r=0.1, a=0.1, b=1.0)
    with pytest.raises(ValueError, match=r"m_c is not a key of the paper form \('eps', 'b', 'K2'\); give one form"):
        Params.from_config({"eps": 0.1, "m_c": 5})
    with pytest.raises(ValueError, match=r"K2 is not a key of the physical form"):
        Params.from_config({"m_c": 0.9, "m_r": 0.1, "I_c": 0.1, "I_r": 0.01, "a": 0.1, "b": 1.0, "K2": 1.1})
    with pytest.raises(ValueError, match=r"m_r = 0 is outside the admissible range \(0, inf\): eps = m_r / m"):
        Params.from_config({"m_c": 1.0, "m_r": 0, "I_c": 0.1, "I_r": 0.01, "a": 0.1, "b": 1.0})
    assert Params.sleigh0().m_r == 0.0  # the rotor-free sleigh stays available to the library


LIBRARY_CALLS = [
    ("integrate", dict(backend="scipy", rtol=5), ValueError,
     r"rtol = 5 is outside the admissible range \[2.22e-14, 1\)"),
    ("integrate", dict(backend="scipy", rtol=1e-16), ValueError, r"rtol = 1e-16 is outside"),
    ("integrate", dict(backend="scipy", atol=-1.0), ValueError, r"atol = -1.0 is outside the admissible range"),
    ("integrate", dict(tol=1e-300), ValueError, r"tol = 1e-300 is outside the admissible range \[2.22e-16, 1\) of"),
    ("integrate", dict(tol=1e-20, precision=Precision.LONG_DOUBLE), ValueError, r"\[1.08e-19, 1\) of long double"),
    ("integrate", dict(tol="1e-12"), TypeError, r"tol = '1e-12' must be a real number"),
    ("integrate", dict(t0=math.nan), ValueError, r"t0 = nan is outside the admissible range"),
    ("integrate", dict(y0=None), TypeError, r"y0 = None must be a sequence of numbers"),
    ("integrate", dict(y0="abcd"), TypeError, r"y0 = 'abcd' must be a sequence of numbers"),
    ("integrate", dict(params=None), TypeError, r"params = None must be a Params"),
    ("integrate", dict(y0=np.array([1.0, 0.1j, 0.2, 0.3])), TypeError,
     r"y0 = .*0\.1j.* must be a sequence of numbers .*all real"),
    ("integrate", dict(y0=np.array(["1.0", 0.1, 0.2, 0.3], dtype=object)), TypeError,
     r"y0 = .*'1\.0'.* must be a sequence of numbers .*all real"),
    ("integrate", dict(max_steps=-5), ValueError, r"max_steps = -5 is outside the admissible range \[1, "),
    ("integrate", dict(max_steps=2**64), ValueError, r"max_steps = 18446744073709551616 is outside the admissible"),
    ("integrate", dict(max_steps=1e9), TypeError, r"max_steps = 1000000000.0 must be an integer"),
    ("integrate", dict(progress=True), TypeError, r"progress = True must be an integer"),
    ("integrate", dict(params=Params.physical(m_c=1.0, m_r=0.1, I_c=1.0, I_r=1.0, a=0.1, b=1e110)), ValueError,
     r"b = 1e\+110 is too large: the coefficients of the equations overflow"),
    ("integrate", dict(backend="matlab"), ValueError, r"unknown backend 'matlab'"),
    ("mean_divergence", dict(T=-10.0), ValueError, r"T = -10.0 is outside the admissible range \(0, inf\)"),
    ("mean_divergence", dict(tol=0.0), ValueError, r"tol = 0.0 is outside the admissible range"),
    ("crossings", dict(t_end=-5.0), ValueError, r"t_end = -5.0 is outside the admissible range \(t0 = 0.0, inf\)"),
    ("crossings", dict(t_end=10.0, tol=1e-300), ValueError, r"tol = 1e-300 is outside"),
]


def _call(fn, kw):
    from sleighsim.chaos import benettin
    from sleighsim.engine import poincare
    from sleighsim.engine.integrate import integrate

    if fn == "integrate":
        args = dict(params=P, y0=REF, times=[0.0, 1.0]) | kw
        return integrate(args.pop("params"), args.pop("y0"), args.pop("times"), **args)
    if fn == "mean_divergence":
        return benettin.mean_divergence(P, REF, **(dict(T=1.0, tol=2.0**-52) | kw))
    return poincare.crossings(P, REF, 0.0, **(dict(t_end=1.0) | kw))


@pytest.mark.parametrize("fn, kw, error, message", LIBRARY_CALLS, ids=[f"{c[0]}-{c[1]}" for c in LIBRARY_CALLS])
def test_library_calls_refuse_bad_arguments_naming_them(fn, kw, error, message):
    with pytest.raises(error, match=message):
        _call(fn, kw)


def test_the_runtime_bound_is_the_cheapest_measured_cost_per_time_unit(root):
    """configcheck's runtime refusal is a lower bound: its cost per time unit may not exceed the
    cheapest double-precision flow measured in benchmarks/precision_cost.yaml, nor lie far below it."""
    import yaml

    from sleighsim.ops.configcheck import SECONDS_PER_TIME_UNIT

    rows = yaml.safe_load((root / "benchmarks" / "precision_cost.yaml").read_text())["rows"]
    cheapest = min(r["cost_s_per_tu"] for r in rows if r["system"] == "flow" and r["precision"] == "double")
    assert 0.5 * cheapest <= SECONDS_PER_TIME_UNIT <= cheapest, (SECONDS_PER_TIME_UNIT, cheapest)
