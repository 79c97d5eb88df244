"""Property-based tests (Hypothesis) of the input checks (issue 31):

- a config the checks accept (schema, then sleighsim.ops.configcheck) dry-runs without a traceback, and
  a config they refuse is refused naming a key of the value changed; the configs are the smoke
  config with one number changed (scaled, written as a float, or replaced);
- whatever state, horizon and arithmetic ``integrate`` accepts it integrates, or it stops with an
  IntegrationError, within a bounded time (``max_steps``); what it refuses it refuses naming the
  argument.
"""

import math
import subprocess
import sys
import time

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from test_config import ROOT, SMOKE, numeric_leaves, refused, with_value

from sleighsim.engine.integrate import IntegrationError, integrate
from sleighsim.model.params import Params
from sleighsim.precision import Precision

LEAVES = sorted(numeric_leaves(SMOKE), key=str)
FACTORS = (0.0, -1.0, 1e-3, 0.5, 2.0, 1e3, 1e9)


def _at(path):
    node = SMOKE
    for k in path:
        node = node[k]
    return node


@st.composite
def one_number_changed(draw):
    """(path, the smoke config with the number at path scaled, written as a float or replaced)."""
    path = draw(st.sampled_from(LEAVES))
    how = draw(st.sampled_from(("scale", "float", "replace")))
    if how == "scale":
        value = _at(path) * draw(st.sampled_from(FACTORS))
    elif how == "float":
        value = float(_at(path))
    else:
        value = draw(st.floats(-1e6, 1e6, allow_nan=False))
    return path, with_value(path, value)


def _dry_run(tmp, cfg):
    """`snakemake -n` with ``cfg`` merged onto the paper config (as the smoke config is)."""
    overlay = tmp / "config.yaml"
    overlay.write_text(yaml.safe_dump(cfg))
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(tmp),
           "--configfile", str(overlay), "-n", "-c1", "--nolock"]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


@settings(max_examples=15, deadline=None, database=None)
@given(case=one_number_changed())
def test_an_accepted_config_dry_runs_and_a_refused_one_names_a_key(case, tmp_path_factory):
    path, cfg = case
    why = refused(cfg)
    if why:
        assert any(str(k) in why for k in path[1:] if isinstance(k, str)), (path, why)
        return
    res = _dry_run(tmp_path_factory.mktemp("dry"), cfg)
    out = res.stdout + res.stderr
    assert res.returncode == 0 and "Traceback" not in out, (path, out[-3000:])


P = Params.paper(eps=0.1)
NUMBERS = st.one_of(st.floats(-10.0, 10.0), st.sampled_from([0.0, 1e300, -1e300, 1e-300, math.nan, math.inf]))
#: The words a refusal of each argument contains.
ARGUMENTS = ("y0", "sample times", "tol", "rtol", "precision", "backend")
#: Steps an integration may take: the bound on its time (microseconds per step in double).
MAX_STEPS = 2000
#: Seconds any call may take, compilation included.
BOUND_S = 60.0


@settings(max_examples=60, deadline=None, database=None)
@given(y0=st.one_of(st.lists(NUMBERS, min_size=0, max_size=8), st.none(), st.text(max_size=4)),
       t_end=st.one_of(st.floats(-10.0, 1e6), st.sampled_from([0.0, 1e300, math.nan, math.inf])),
       tol=st.sampled_from([2.0**-52, 1e-12, 1e-6, 2.0**-63, 2.0**-112, 1e-300, 0.0, 1.0, -1.0, math.nan]),
       precision=st.sampled_from(list(Precision)),
       backend=st.sampled_from(["heyoka", "scipy"]))
def test_integrate_integrates_or_refuses_clearly_in_bounded_time(y0, t_end, tol, precision, backend):
    start = time.perf_counter()
    try:
        ds = integrate(P, y0, [0.0, t_end], tol=tol, precision=precision, backend=backend, rtol=max(tol, 1e-10),
                       max_steps=MAX_STEPS, progress=1)
    except (TypeError, ValueError) as err:
        assert any(a in str(err) for a in ARGUMENTS), str(err)
    except IntegrationError as err:
        assert "integration failed at t = " in str(err)
    else:
        assert ds.time.size == 2 and ds.attrs["steps"] <= MAX_STEPS
    assert time.perf_counter() - start < BOUND_S


@pytest.mark.parametrize("precision, eps", [(Precision.DOUBLE, 2.0**-52), (Precision.LONG_DOUBLE, 2.0**-63)])
def test_the_finest_admissible_tolerance_integrates(precision, eps):
    """The property's boundary: a tolerance at the arithmetic's epsilon is accepted and finishes."""
    ds = integrate(P, [0.0, 0.1, 1.0, 0.0], [0.0, 10.0], tol=eps, precision=precision, max_steps=MAX_STEPS)
    assert ds.attrs["tol"] == eps
