"""What the workflow builds, declared once.

- Scenes live in the config: each block under ``scenes`` names its ``kind``; the dataset is
  ``results/data/<scene>.nc``. :data:`KINDS` says how each kind runs and which other datasets
  (by role, named in the block's ``inputs``) it reads; :mod:`sleighsim.scenes` imports its function.
- Figures are declared beside their plot functions (:mod:`sleighsim.report.figures.catalog`), the
  datasets each claim is judged from in :mod:`sleighsim.claims.evidence`.

The Snakefile, the config checks, the claims ledger and the report all derive from these;
nothing else lists scenes, figures or claims. This module imports nothing heavy, so the
workflow can read it while it builds the job graph.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Kind:
    """How a scene kind is computed: ``dataset`` is False for a kind drawn from its config block
    alone (no dataset); ``inputs`` are the roles of the datasets it reads; a ``chunked`` kind runs as
    independent chunk jobs gathered by one job; a kind that ``integrates`` takes the config's
    ``defaults`` (the tolerance) unless its block sets them; a ``realizable`` kind's claims rest on a
    sensitive quantity, so its block may ask for ``realizations`` (the scene again from start states
    perturbed at ``realization_rel``, each judged by the ledger). The function of each kind is imported
    by :func:`sleighsim.scenes.function` (and :func:`sleighsim.scenes.chunk_functions`)."""

    dataset: bool = True
    inputs: tuple[str, ...] = ()
    chunked: bool = False
    integrates: bool = True
    realizable: bool = False


KINDS: dict[str, Kind] = {
    "schematic": Kind(dataset=False, integrates=False),  # drawn from its config block; no dataset
    "sleigh0": Kind(),
    "trajectory": Kind(),
    "attractor_levels": Kind(),
    "transient_scaling": Kind(),
    "series_vs_exact": Kind(),
    "hierarchy_terms": Kind(),
    "hierarchy_audit": Kind(),
    "poincare": Kind(),
    "psd": Kind(),
    "attractor_scaling": Kind(inputs=("reference", "scaled"), integrates=False),
    "lyapunov_spectrum": Kind(realizable=True),
    "lyapunov_protocol": Kind(realizable=True),
    "lyapunov_energy": Kind(realizable=True),
    "small_eps_cost": Kind(),
    "formal_exponents": Kind(realizable=True),
    "lyapunov_grid": Kind(chunked=True),
    "chaos_verdict": Kind(chunked=True),
    "precision_ladder": Kind(),
    "trigger_law": Kind(),
    "drift_windows": Kind(),
    "basins": Kind(chunked=True),
    "printed_model": Kind(),
    "k2_sweep": Kind(),
    "integration_error": Kind(),
    "hardcases": Kind(),
    "bench": Kind(integrates=False),
}


#: The key observables of each kind whose scenes can run in several precisions (a block's
#: ``precisions``): :mod:`sleighsim.analysis.observables` reads them, with their uncertainties, from each
#: precision's dataset and finds the precision they converge in.
OBSERVABLES: dict[str, tuple[str, ...]] = {
    "poincare": ("rotation_number", "return_time_mean", "n_loops"),
    "trajectory": ("n_spikes", "first_spike_time", "spike_interval_mean", "path_reach"),
    "lyapunov_spectrum": ("lambda_1", "lambda_4"),
    "lyapunov_protocol": ("lambda_1", "lambda_4"),
    "lyapunov_energy": ("lambda_1_reference", "lambda_1_lowest_label"),
    "lyapunov_grid": ("lambda_1_reference", "lambda_1_smallest"),
    "psd": ("Omega_band_low", "Omega_band_high", "Omega_band_peak", "u_band_peak", "Omega_n_peaks_near_zero"),
}


def precision_tag(precision: str) -> str:
    """A precision's name in paths: "long double" -> "long_double"."""
    return precision.replace(" ", "_")


def variant(scene: str, precision: str) -> str:
    """The dataset name (path under data/) of ``scene`` computed in ``precision``: the scene itself
    in double (the paper's arithmetic), else precision/<tag>/<scene>."""
    return scene if precision == "double" else f"precision/{precision_tag(precision)}/{scene}"


def ladder_name(scene: str) -> str:
    """The dataset name (path under data/) of the precision ladder of ``scene``."""
    return f"ladder/{scene}"


def laddered(config: dict, *, on_request: bool = False) -> dict[str, list[str]]:
    """{scene: its precisions, coarse to fine} for the scenes of ``config`` that run in more than
    one precision (among those :func:`datasets` builds)."""
    scenes = config["scenes"]
    return {name: list(scenes[name]["precisions"]) for name in datasets(config, on_request=on_request)
            if scenes[name]["kind"] in OBSERVABLES and len(scenes[name].get("precisions", ())) > 1}


def realization_name(scene: str, k: int) -> str:
    """The dataset name (path under data/) of realization ``k`` of ``scene`` (0: the scene itself)."""
    return scene if k == 0 else f"realization/{k}/{scene}"


def realized(config: dict, *, on_request: bool = False) -> dict[str, int]:
    """{scene: its number of realizations} for the scenes of ``config`` (among those :func:`datasets`
    builds) whose realizable block asks for more than one."""
    scenes = config["scenes"]
    return {name: int(scenes[name]["realizations"]) for name in datasets(config, on_request=on_request)
            if KINDS[scenes[name]["kind"]].realizable and scenes[name].get("realizations", 1) > 1}


def run_datasets(config: dict) -> list[str]:
    """Every dataset the config's default run builds, by name under data/: its scenes, their
    finer-precision variants and precision ladders, and their realizations (on-request scenes not)."""
    lad = laddered(config)
    return (datasets(config) + [variant(s, p) for s, ps in lad.items() for p in ps if p != "double"]
            + [ladder_name(s) for s in lad]
            + [realization_name(s, k) for s, n in realized(config).items() for k in range(1, n)])


#: Keys of a scene block that schedule its jobs and do not change what it computes.
SCHEDULING = ("on_request", "schedule_first", "chunk_runtime_min", "runtime_min")


def scene_config(config: dict, scene: str) -> dict:
    """The block of ``scene`` as its function reads it: the config's ``defaults`` filled in where
    the kind integrates and the block sets no value, the scheduling keys removed (and a laddered
    kind's ``precisions`` and ``gain``: each precision's job adds its own ``precision``, and the
    ladder's job reads the gauge; a realizable kind's ``realizations`` and ``realization_rel``: each
    realization's job perturbs its start states itself)."""
    block = config["scenes"][scene]
    defaults = config.get("defaults", {}) if KINDS[block["kind"]].integrates else {}
    ladder = ("precisions", "gain") if block["kind"] in OBSERVABLES else ()  # the ladder's, by its own jobs
    realized = ("realizations", "realization_rel") if KINDS[block["kind"]].realizable else ()
    return {**defaults, **{k: v for k, v in block.items() if k not in SCHEDULING + ladder + realized}}


def datasets(config: dict, *, on_request: bool = False) -> list[str]:
    """The scenes of ``config`` that make a dataset: those built in the full run, or with
    ``on_request`` also those built only when asked for."""
    return [name for name, block in config["scenes"].items()
            if KINDS[block["kind"]].dataset and (on_request or not block.get("on_request", False))]
