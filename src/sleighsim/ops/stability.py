"""Verdict stability: rerun the claim-bearing scenes with the initial states perturbed and with a
looser tolerance, and tabulate which verdicts of the ledger change. Chaotic observables differ in
detail between such runs; the verdicts should not.

Variants: :data:`METHOD` (written into the stability dataset).

Command line (also the on-request Snakemake target ``stability``)::

    python -m sleighsim.ops.stability --base results/claims.nc --out results/stability/verdicts.csv

Why a nested ``snakemake`` inside the ``stability`` rule: a variant is a different config for the
whole DAG, and Snakemake builds one DAG per config. Folding the variants into the calling DAG would
need a variant wildcard on every rule, doubling every rule's signature. So each variant is its own
run, with its own results directory (``<results>/stability/<variant>``, disjoint from the calling
run's outputs) and ``--nolock``, since the calling run holds the working directory's lock.
"""

from __future__ import annotations

import argparse
import copy
import subprocess
import sys
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from sleighsim.claims import ledger as claims
from sleighsim.io.netcdf import write_dataset, write_text

#: The variants, as the stability dataset records them (attribute ``method``).
METHOD = (
    "Variants (each a whole config, its results under ``<results>/stability/<variant>``): - ``perturbed``: "
    "every initial state (``y0`` and the ``states`` of a scene) times (1 + rel s_i), s_i = +1, -1, +1, -1 by "
    "component (zero components stay zero); - ``tol_<tol>``: every integration at ``tol`` where it used the "
    "default tolerance."
)

STATE_KEYS = ("y0", "states")
REL = 1e-12
TOL = 1e-15


def _perturb_state(x, rel):
    signs = np.resize([1.0, -1.0], len(x))
    return [float(v * (1.0 + rel * s)) for v, s in zip(x, signs)]


def _is_state(x) -> bool:
    return isinstance(x, list) and len(x) == 4 and all(isinstance(v, (int, float)) for v in x)


def _walk(node, rel, under_state: bool):
    if under_state and _is_state(node):
        return _perturb_state(node, rel)
    if isinstance(node, dict):
        return {k: _walk(v, rel, under_state or k in STATE_KEYS) for k, v in node.items()}
    if isinstance(node, list):
        return [_walk(v, rel, under_state) for v in node]
    return node


def perturbed(config: dict, rel: float = REL) -> dict:
    """The config with every initial state of every scene perturbed by ``rel`` (relative)."""
    out = copy.deepcopy(config)
    out["scenes"] = {name: _walk(block, rel, False) for name, block in config["scenes"].items()}
    return out


def loosened(config: dict, tol: float = TOL) -> dict:
    """The config integrating at ``tol`` wherever it used the default tolerance."""
    out = copy.deepcopy(config)
    default = config.get("defaults", {}).get("tol")
    out.setdefault("defaults", {})["tol"] = tol
    for block in out["scenes"].values():
        if "tol" in block and block["tol"] == default:
            block["tol"] = tol
    return out


def variants(config: dict) -> dict[str, dict]:
    """{variant: config} with each variant's results under <results>/stability/<variant>."""
    base = config["results"]
    out = {"perturbed": perturbed(config), f"tol_{TOL:g}": loosened(config)}
    for name, cfg in out.items():
        cfg["results"] = f"{base}/stability/{name}"
    return out


def table(base_nc, variant_ncs: dict) -> xr.Dataset:
    """Verdicts per claim id: the base run's and each variant's, and whether any changed."""
    base = {r.id: r.verdict for r in claims.read(base_nc)}
    ids = list(base)
    cols = {name: {r.id: r.verdict for r in claims.read(nc)} for name, nc in variant_ncs.items()}
    data = {"base": ("id", np.array([base[i] for i in ids], dtype=object))}
    for name, v in cols.items():
        data[name] = ("id", np.array([v.get(i, "missing") for i in ids], dtype=object))
    changed = np.array([any(cols[n].get(i) != base[i] for n in cols) for i in ids], dtype=np.int8)
    data["changed"] = ("id", changed)
    ds = xr.Dataset(data, coords={"id": ids})
    ds.attrs.update(n_changed=int(changed.sum()), variants=", ".join(cols), rel=REL, tol=TOL,
                    method=METHOD)
    return ds


#: What the verdict stability table's dataset is (its CF title).
TITLE = "verdict stability: the ledger's verdicts with perturbed start states and at a looser tolerance"


def write_table(ds: xr.Dataset, csv_path) -> None:
    """The verdict table ``ds`` (one row per claim id) as CSV at ``csv_path``."""
    names = [k for k in ds.data_vars]
    lines = ["id," + ",".join(names)]
    lines += [",".join([str(i)] + [str(ds[k].values[j]) for k in names]) for j, i in enumerate(ds.id.values)]
    write_text(csv_path, "\n".join(lines) + "\n")
    write_dataset(ds, Path(csv_path).with_suffix(".nc"), what=TITLE)


def run(config: dict, base_nc, out_csv, *, cores: int = 2, snakefile=None) -> xr.Dataset:
    """Run every variant's ledger with Snakemake (its own results directory; no lock, since the
    outputs differ from the calling run's) and write the table."""
    snakefile = snakefile or Path(__file__).resolve().parents[3] / "workflow" / "Snakefile"
    out_csv = Path(out_csv)
    ncs = {}
    for name, cfg in variants(config).items():
        overlay = out_csv.parent / f"{name}.yaml"
        write_text(overlay, yaml.safe_dump(cfg, sort_keys=False))
        target = f"{cfg['results']}/claims.nc"
        cmd = [sys.executable, "-m", "snakemake", "-s", str(snakefile), "--configfile", str(overlay), f"-c{cores}",
               "--nolock", target]
        print("stability:", " ".join(cmd), file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True)
        ncs[name] = target
    ds = table(base_nc, ncs)
    write_table(ds, out_csv)
    return ds


def main(argv=None) -> int:
    """Run the variants and write the table of verdicts that change (``argv``: the command line
    without the program, default sys.argv). Returns the exit status."""
    ap = argparse.ArgumentParser(prog="python -m sleighsim.ops.stability", description=__doc__.split("\n\n")[0])
    ap.add_argument("--configfile", nargs="*", default=["config/config.yaml"],
                    help="config files, merged in order (default config/config.yaml)")
    ap.add_argument("--base", default="results/claims.nc", help="the ledger of the unperturbed run")
    ap.add_argument("--out", default="results/stability/verdicts.csv", help="the table (CSV; netCDF beside it)")
    ap.add_argument("--cores", type=int, default=2)
    a = ap.parse_args(argv)
    if not Path(a.base).exists():
        ap.error(f"{a.base} does not exist: run the workflow first (snakemake -c2)")
    config: dict = {}
    for f in a.configfile:
        config = _merge(config, yaml.safe_load(Path(f).read_text()))
    ds = run(config, a.base, a.out, cores=a.cores)
    print(f"{ds.attrs['n_changed']} of {ds.sizes['id']} verdicts changed -> {a.out}")
    return 0


def _merge(a: dict, b: dict) -> dict:
    """b merged into a, recursively (as Snakemake merges config files)."""
    out = dict(a)
    for k, v in b.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


if __name__ == "__main__":
    raise SystemExit(main())
