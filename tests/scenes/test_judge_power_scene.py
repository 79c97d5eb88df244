"""The judge_power scene (sleighsim.scenes.judge_power): the audited settings are the chaos verdict's decisive
stage's (paper config at factor 1, the cluster overlay at factor 5), the smoke config votes by nothing, its
work units cover every realization once, its checks refuse what they must, and the smoke config's chunks
gather into a dataset whose counts, votes and rule agree with its run table."""

from pathlib import Path

import numpy as np
import pytest
from snakemake.common.configfile import load_configfile
from snakemake.utils import update_config

from sleighsim.chaos import indicators, power
from sleighsim.chaos.audit_orbits import WINDOWS_PER_BASE
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, SYSTEMS
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset, write_dataset
from sleighsim.scenes import catalog, judge_power
from sleighsim.scenes.checks import ConfigError

ROOT = Path(__file__).resolve().parents[2]


def _config(*overlays) -> dict:
    cfg = load_configfile(str(ROOT / "config" / "config.yaml"))
    for o in overlays:
        update_config(cfg, load_configfile(str(ROOT / o)))
    return cfg


def _record_of(block: dict) -> dict:
    """A record of the block's audit in which every judge is right on 300 orbits per class."""
    d = block["decisive"]
    judges = [i.name for i in indicators.audited(indicators.DECISIVE)]
    clean = {c: {"N": 300, "correct": 300, "wrong": 0, "undecided": 0} for c in power.CLASSES}
    return {"schema": power.SCHEMA, "stage": "decisive", "spike_period": block["spike_period"],
            "settings": {k: d[k] for k in ("T", "dt", "splits", "min_cycles", "sigma")},
            "horizons": {float(e["factor"]): {"megno_samples": e["megno_samples"]} for e in d["horizons"]},
            "counts": {float(e["factor"]): dict.fromkeys(judges, clean) for e in d["horizons"]}}


@pytest.mark.parametrize("overlays, factor", [((), 5.0), (("config/cluster.yaml",), 5.0)])
def test_the_audit_covers_the_decisive_stage_of_the_paper_and_cluster_configs(overlays, factor):
    """Every decisive judge votes at the audited horizon equal to the config's own; its settings are the
    chaos verdict's (T, dt, splits, MEGNO samples, min_cycles, sigma)."""
    cfg = _config(*overlays)
    verdict, audit = catalog.scene_config(cfg, "chaos_verdict"), catalog.scene_config(cfg, "judge_power")
    v = power.stage_vote(_record_of(audit), verdict, "decisive", 2337.6)
    assert v["voters"] == {"megno", "section_megno", "frequency", "birkhoff"}
    assert set(v["factor"].values()) == {factor}


def test_the_smoke_config_votes_by_nothing():
    cfg = _config("config/smoke.yaml")
    verdict = catalog.scene_config(cfg, "chaos_verdict")
    paper_audit = catalog.scene_config(_config(), "judge_power")
    assert power.stage_vote(_record_of(paper_audit), verdict, "decisive")["voters"] == set()
    assert power.stage_vote(_record_of(paper_audit), verdict, "first")["voters"] == set()


@pytest.mark.parametrize("overlays", [(), ("config/smoke.yaml",)])
def test_the_work_units_hold_every_realization_once_and_mix_the_systems(overlays):
    block = catalog.scene_config(_config(*overlays), "judge_power")
    units = judge_power.units(block)
    realizations = sorted((s, k) for s, first, n in units for k in range(first, first + n))
    assert realizations == sorted((s, k) for s in block["systems"] for k in range(block["samples"]))
    assert all(n <= (WINDOWS_PER_BASE if SYSTEMS[s].cls == CHAOTIC_ORBITS else 1) for s, _, n in units)
    per = [units[k::block["n_chunks"]] for k in range(block["n_chunks"])]
    assert all(per)
    if not overlays:  # no chunk holds one system only
        assert all(len({u[0] for u in p}) > 1 for p in per)
    assert sum(judge_power.chunk_work(block)) == pytest.approx(judge_power.work(block))


@pytest.mark.parametrize("change, message", [
    ({"systems": ["pendulum"]}, "unknown"), ({"systems": ["lorenz"]}, "chaotic systems and tori"),
    ({"n_chunks": 1000}, "n_chunks"),
])
def test_the_checks_refuse_bad_blocks(change, message):
    block = catalog.scene_config(_config("config/smoke.yaml"), "judge_power")
    judge_power._checks("judge_power", block)  # the smoke block passes
    with pytest.raises(ConfigError, match=message):
        judge_power._checks("judge_power", {**block, **change})
    twice = {**block, "decisive": {**block["decisive"], "horizons": block["decisive"]["horizons"] * 2}}
    with pytest.raises(ConfigError, match="distinct"):
        judge_power._checks("judge_power", twice)


def test_the_smoke_chunks_gather_into_counts_votes_and_a_rule(hy, tmp_path):
    block = catalog.scene_config(_config("config/smoke.yaml"), "judge_power")
    paths = [write_dataset(catalog.chunk("judge_power", block, k), tmp_path / "chunks" / "judge_power" / f"{k}.nc")
             for k in range(block["n_chunks"])]
    ds = catalog.gather("judge_power", block, paths)
    judges = [i.name for i in indicators.audited(indicators.DECISIVE)]
    assert ds.sizes["run"] == len(block["systems"]) * block["samples"] * len(judges)
    assert int(ds.counts.sum()) == ds.sizes["run"] and int(ds.rule_counts.sum()) == len(block["systems"])
    for j in judges:  # the run table and the counts agree
        mine = ds.run_verdict.values[ds.run_judge.values == j]
        assert [int(ds.counts.sel(judge=j).sum(["orbit_class", "system", "horizon"]).sel(verdict=v)) for v in
                ds.verdict.values] == [int(np.sum(mine == v)) for v in ds.verdict.values]
    assert not ds.votes.values.any()  # one realization per class bounds nothing: nobody votes
    assert cf.missing(read_dataset(write_dataset(ds, tmp_path / "data" / "judge_power.nc"))) == []
