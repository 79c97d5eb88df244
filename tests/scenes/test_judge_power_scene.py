"""The judge_power scene (sleighsim.scenes.judge_power): its config agrees with the sleigh's chaos_verdict,
its chunks cover every task once, its checks refuse what they must, and the smoke config's chunks gather
into a dataset whose counts, rates and vote agree with the run table."""

from pathlib import Path

import numpy as np
import pytest
from snakemake.common.configfile import load_configfile
from snakemake.utils import update_config

from sleighsim.chaos import power
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset, write_dataset
from sleighsim.scenes import catalog, judge_power
from sleighsim.scenes.checks import ConfigError

ROOT = Path(__file__).resolve().parents[2]
PAPER = load_configfile(str(ROOT / "config" / "config.yaml"))


def _block(smoke: bool) -> dict:
    cfg = load_configfile(str(ROOT / "config" / "config.yaml"))
    if smoke:
        update_config(cfg, load_configfile(str(ROOT / "config" / "smoke.yaml")))
    return catalog.scene_config(cfg, "judge_power")


def test_the_sleigh_settings_are_chaos_verdicts():
    verdict, mine = PAPER["scenes"]["chaos_verdict"], PAPER["scenes"]["judge_power"]["sleigh"]
    shared = [k for k in mine if k in verdict and k not in ("frequency", "decisive")]
    assert len(shared) >= 13
    assert {k: mine[k] for k in shared} == {k: verdict[k] for k in shared}
    for nested in ("frequency", "decisive"):
        assert mine[nested] == {k: verdict[nested][k] for k in mine[nested]}


@pytest.mark.parametrize("smoke", [False, True])
def test_the_chunks_hold_every_task_once_and_mix_the_systems(smoke):
    block = _block(smoke)
    tasks = judge_power.tasks(block)
    per = [tasks[k::block["n_chunks"]] for k in range(block["n_chunks"])]
    assert sorted(map(str, sum(per, []))) == sorted(map(str, tasks))
    judged = [t for t in tasks if t[0] == "judge"]
    assert len(judged) == len(block["systems"]) * len(block["horizons"]) * block["samples"]
    assert all(any(t[0] == "judge" for t in p) for p in per)
    if not smoke:  # coprime chunking: no chunk holds one system only
        assert all(len({t[1] for t in p if t[0] == "judge"}) > 1 for p in per)
    assert sum(judge_power.chunk_work(block)) == pytest.approx(judge_power.work(block))


@pytest.mark.parametrize("change, message", [
    ({"systems": ["pendulum"]}, "unknown"), ({"judges": ["tarot"]}, "unknown"), ({"n_chunks": 1000}, "n_chunks"),
])
def test_the_checks_refuse_bad_blocks(change, message):
    judge_power._checks("judge_power", _block(True))  # the smoke block passes
    with pytest.raises(ConfigError, match=message):
        judge_power._checks("judge_power", {**_block(True), **change})


def test_the_smoke_chunks_gather_into_counts_rates_and_a_vote(hy, tmp_path):
    block = _block(True)
    paths = [write_dataset(catalog.chunk("judge_power", block, k), tmp_path / "chunks" / "judge_power" / f"{k}.nc")
             for k in range(block["n_chunks"])]
    ds = catalog.gather("judge_power", block, paths)
    n_runs = ds.sizes["run"]
    assert n_runs == sum(len([j for j in power.JUDGES if power.applies(j, power.SYSTEMS[s])]) for s in block["systems"])
    assert int(ds.counts.sum()) == n_runs and int(ds.rate_N.sum()) == n_runs
    for j in ds.judge.values:  # the table of runs and the counts agree
        mine = ds.run_verdict.values[ds.run_judge.values == j]
        assert [int(ds.counts.sel(judge=j).sum(["orbit_class", "system", "horizon"]).sel(verdict=v)) for v in
                ds.verdict.values] == [int(np.sum(mine == v)) for v in ds.verdict.values]
    assert {str(j) for j, v in zip(ds.judge.values, ds.votes.values) if v} == power.voting(ds)
    assert list(ds.chaotic_system.values) == ["henon-heiles E=1/6"] and ds.confirm_confirmed.values[0] == 1
    assert cf.missing(read_dataset(write_dataset(ds, tmp_path / "data" / "judge_power.nc"))) == []
