"""Verdict stability: the variant configs and the table of changed verdicts."""

from pathlib import Path

import numpy as np
import yaml
from conftest import snakemake

from sleighsim.claims import ledger as claims
from sleighsim.ops import stability

ROOT = Path(__file__).resolve().parents[2]


def _config():
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def test_perturbed_moves_every_initial_state_and_nothing_else():
    cfg = _config()
    out = stability.perturbed(cfg, 1e-12)
    a, b = cfg["scenes"]["fig3"], out["scenes"]["fig3"]
    assert b["y0"][1] == a["y0"][1] * (1 - 1e-12) and b["y0"][2] == a["y0"][2] * (1 + 1e-12) and b["y0"][0] == 0.0
    assert b["params"] == a["params"] and b["t_end"] == a["t_end"]
    lv_a, lv_b = cfg["scenes"]["fig4"]["levels"][0], out["scenes"]["fig4"]["levels"][0]
    assert lv_b["label"] == lv_a["label"] and lv_b["states"][1] != lv_a["states"][1]
    st_a, st_b = cfg["scenes"]["chaos_verdict"]["states"], out["scenes"]["chaos_verdict"]["states"]
    assert st_b["main"] != st_a["main"] and np.allclose(st_b["main"], st_a["main"], rtol=1e-11)
    assert cfg["scenes"]["fig3"]["y0"] == a["y0"]  # the input is not modified


def test_loosened_replaces_the_default_tolerance_only():
    cfg = _config()
    out = stability.loosened(cfg, 1e-15)
    assert out["defaults"]["tol"] == 1e-15
    for name, block in cfg["scenes"].items():
        if "tol" in block and block["tol"] != cfg["defaults"]["tol"]:
            assert out["scenes"][name]["tol"] == block["tol"]


def test_variants_write_under_their_own_results():
    vs = stability.variants(_config())
    assert set(vs) == {"perturbed", "tol_1e-15"}
    assert all(v["results"].endswith(f"stability/{k}") for k, v in vs.items())


def _ledger(path, verdicts):
    rows = [claims.Row(id=i, statement="", paper_value="", verdict=v) for i, v in verdicts.items()]
    claims.write(rows, path.with_suffix(".csv"), path)


def test_table_flags_changed_verdicts(tmp_path):
    _ledger(tmp_path / "base.nc", {"C01": "reproduced", "C02": "differs"})
    _ledger(tmp_path / "a.nc", {"C01": "reproduced", "C02": "differs"})
    _ledger(tmp_path / "b.nc", {"C01": "differs", "C02": "differs"})
    ds = stability.table(tmp_path / "base.nc", {"a": tmp_path / "a.nc", "b": tmp_path / "b.nc"})
    assert list(ds.changed.values) == [1, 0] and ds.attrs["n_changed"] == 1
    ds = stability.table(tmp_path / "base.nc", {"a": tmp_path / "a.nc"})
    assert ds.attrs["n_changed"] == 0
    stability.write_table(ds, tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_text().splitlines()[0] == "id,base,a,changed" and (tmp_path / "t.nc").exists()


def test_stability_is_an_on_request_target(tmp_path):
    dry = snakemake(tmp_path, ROOT / "config" / "smoke.yaml", "-n", "stability", timeout=300)
    out = dry.stdout + dry.stderr
    assert dry.returncode == 0, out[-2000:]
    assert "stability" in out and "rule claims:" in out
    dry = snakemake(tmp_path, ROOT / "config" / "smoke.yaml", "-n", timeout=300)
    assert "rule stability" not in dry.stdout + dry.stderr
