"""One call to judge a state (sleighsim.ops.judge, sleighsim judge): the block it builds from the config, its
refusals before any work, a run on the smoke horizons through the command line, and the same numbers as the
workflow's chaos verdict for the same state."""

import numpy as np
import pytest
import xarray as xr
from conftest import SMOKE, SMOKE_RESULTS

from sleighsim import cli
from sleighsim.model.params import Params
from sleighsim.model.symmetries import energy_label
from sleighsim.ops.judge import STATE, block_for, judge_state
from sleighsim.precision import Precision

STATE0 = [0.0, 0.1, 1.0, 0.0]


def test_the_block_is_the_configs_with_the_state_in_the_decisive_stage():
    b = block_for({"eps": 0.05, "b": 1.0, "K2": 1.1}, STATE0, 2e5, precision="quad", realizations=2)
    assert b["states"] == {STATE: STATE0} and b["decisive"]["states"] == [STATE] and b["n_chunks"] == 2
    assert b["params"] == {"eps": 0.05, "b": 1.0, "K2": 1.1} and b["decisive"]["T"] == 2e5
    assert b["decisive"]["precision"] is Precision.QUAD and b["decisive"]["tol"] == Precision.QUAD.epsilon
    assert b["energy_label"] == pytest.approx(float(energy_label(STATE0, Params.paper(eps=0.05, K2=1.1))))
    paper = block_for(None, STATE0, label=0.2)
    assert paper["energy_label"] == 0.2 and paper["decisive"]["precision"] is Precision.DOUBLE_DOUBLE
    assert paper["decisive"]["tol"] == 1e-34 and paper["n_chunks"] == 3 and paper["params"]["eps"] == 0.1
    by_type = block_for(Params.paper(eps=0.05, K2=1.1), STATE0, precision=Precision.DOUBLE_DOUBLE)
    assert by_type["decisive"]["tol"] == 1e-34 and Params.from_config(by_type["params"]).eps == pytest.approx(0.05)


@pytest.mark.parametrize("params, state, kw, words", [
    ({"eps": 0.05, "bee": 1.0}, STATE0, {}, "bee is not a key"),
    (None, [0.0, 0.1, 1.0], {}, "give (u, Omega, omega, delta)"),
    (None, [0.0, 0.0, 0.0, 0.3], {}, "energy label must be positive"),
    (None, STATE0, {"horizon": -1.0}, "horizon must be positive"),
    (None, STATE0, {"realizations": 0}, "realizations = 0 is outside"),
    (None, STATE0, {"precision": "quadruple"}, "precision 'quadruple': choose one of"),
])
def test_bad_inputs_are_refused_before_any_work_naming_them(params, state, kw, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        block_for(params, state, **kw)


def test_the_command_judges_a_state_and_says_what_would_decide_it(tmp_path, capsys):
    out = tmp_path / "verdict.nc"
    assert cli.main(["judge", "--params", "eps=0.05", "b=1", "K2=1.1", "--state", "0", "0.1", "1", "0",
                     "--realizations", "1", "--configfile", str(SMOKE), "--out", str(out)]) == 0
    printed = capsys.readouterr()
    lines = dict(line.split(": ", 1) for line in printed.out.splitlines())
    ds = xr.open_dataset(out)
    assert lines["verdict"].startswith(str(ds.verdict.values[0])) and ds.state.values.tolist() == [STATE]
    assert lines["decided in"].startswith("double-double") and "why" in lines
    assert ds.verdict.values[0] in ("chaotic", "regular") or "to decide it" in lines
    assert "judge: job 2 of 2 (decisive stage, every realization a lane)" in printed.err  # progress, per job
    assert ds.attrs["decisive_T"] == 300.0 and ds.attrs["param_eps"] == pytest.approx(0.05)
    assert cli.main(["judge", "--state", "0", "0", "0", "0.3"]) == 2 and "energy label" in capsys.readouterr().err


@pytest.mark.workflow
def test_a_judged_state_gets_the_workflows_numbers_for_the_same_state(smoke_run):
    """The paper's reference state judged alone equals the smoke run's chaos verdict of state main: the
    same jobs, the same rule."""
    from sleighsim.io.netcdf import read_dataset

    run = read_dataset(smoke_run / SMOKE_RESULTS / "data" / "chaos_verdict.nc")
    block = block_for(None, STATE0, configfiles=[SMOKE], label=run.attrs["energy_label"])
    assert run.state.values[0] == "main" and block["n_chunks"] == run.sizes["realization"]
    ds = judge_state(None, STATE0, configfiles=[SMOKE], label=run.attrs["energy_label"])
    main = run.isel(state=[0])
    compared = [v for v in main.data_vars if "state" in main[v].dims and not v.endswith("wall_time_s")]
    assert len(compared) > 50 and "verdict" in compared and "decisive_verdict" in compared
    for var in compared:
        a, b = np.asarray(ds[var].values), np.asarray(main[var].values)
        assert a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), var
