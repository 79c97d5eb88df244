"""One call to judge a state of one's own: is the steady state it reaches chaotic? :func:`judge_state` runs the
chaos_verdict scene's jobs for that one start state, in this process and in the workflow's order, and gathers
them by the workflow's rule (:mod:`sleighsim.scenes.verdict`): the first stage (settling, indicators, the
faithfulness gauge), then the decisive stage in an arithmetic that follows the orbit, over ``realizations``
start states perturbed at the rounding level that must agree. Only the judges the judge-power record lets
vote at the run's horizon vote (:func:`sleighsim.chaos.power.stage_vote`). Every setting not given is the
config's chaos_verdict block's (the paper's: config/config.yaml). Progress goes to the ``sleighsim`` logger.

    from sleighsim.ops.judge import judge_state, answer
    ds = judge_state({"eps": 0.05, "b": 1.0, "K2": 1.1}, [0.0, 0.1, 1.0, 0.0], horizon=1e5, precision="quad")
    print(answer(ds))   # verdict, why, the arithmetic it was decided in, what would decide it

Times are in the flow's time unit."""

from __future__ import annotations

import logging
import tempfile
import time
from pathlib import Path

import xarray as xr

from sleighsim.claims.fidelity import config_sha256
from sleighsim.io.netcdf import write_dataset
from sleighsim.io.yamlfile import read_yaml
from sleighsim.model.params import PARAM_NAMES, Params, finite, integer, positive
from sleighsim.model.symmetries import energy_label
from sleighsim.ops.config import BASE_CONFIG, REPO, merged_config
from sleighsim.precision import Precision
from sleighsim.report.chaos_answers import ChaosAnswer, dataset_answers
from sleighsim.scenes import catalog
from sleighsim.scenes.common import tolerance
from sleighsim.scenes.verdict import CHAOS_VERDICT

log = logging.getLogger("sleighsim")

#: The name the judged state carries in the dataset.
STATE = "state"


def _params_block(params) -> dict:
    """The config form of ``params``: a block as given ({eps, b, K2} or the physical form), or a Params."""
    if isinstance(params, Params):
        return {k: float(getattr(params, k)) for k in PARAM_NAMES}
    Params.from_config(params)  # refused here, naming the key, before any work
    return dict(params)


def block_for(params, state, horizon=None, *, precision=None, realizations=None, label=None,
              configfiles=(), base=BASE_CONFIG) -> dict:
    """The chaos_verdict block that judges ``state`` (u, Omega, omega, delta) with ``params`` (None: the
    block's): the config's block (``configfiles`` merged onto ``base``, as a run reads them) with these
    params, the one state (at its own energy label unless ``label`` is given) and it in the decisive stage;
    ``horizon``: the decisive stage's T; ``precision``: its arithmetic (the type or its name; another than
    the block's runs at that arithmetic's tolerance, :func:`sleighsim.scenes.common.tolerance`);
    ``realizations``: its n_chunks."""
    config = merged_config(configfiles, base=base)
    block = catalog.scene_config(config, catalog.scenes_of(config, CHAOS_VERDICT)[0])
    pblock = _params_block(params) if params is not None else block["params"]
    y = [finite(f"state[{i}]", v) for i, v in enumerate(state)]
    if len(y) != 4:
        raise ValueError(f"state = {list(state)}: give (u, Omega, omega, delta), 4 numbers")
    label = positive("energy label", label if label is not None else energy_label(y, Params.from_config(pblock)))
    decisive = {**block["decisive"], "states": [STATE]}
    if horizon is not None:
        decisive["T"] = positive("horizon", horizon)
    if precision is not None and Precision.parse(precision) is not decisive["precision"]:
        # another arithmetic than the block's: its tolerance is that arithmetic's (scenes.common.tolerance)
        decisive["precision"] = Precision.parse(precision)
        decisive["tol"] = tolerance(block, decisive["precision"])
    n = block["n_chunks"] if realizations is None else integer("realizations", realizations, 1, 10**4)
    return {**block, "params": pblock, "states": {STATE: y}, "decisive": decisive, "energy_label": label,
            "n_chunks": n}


def run_block(block: dict, workdir, scene: str = "judge") -> xr.Dataset:
    """The verdict of a chaos_verdict block: each of its chunk jobs in order (the decisive-stage job reads the
    first stage's datasets), written under ``workdir``, then gathered; one progress line per job."""
    n, paths, record = catalog.chunk_count(block), [], REPO / block["vote_record"]
    for index in range(n):
        start = time.perf_counter()
        reads = [paths[i] for i in catalog.chunk_reads(block, index)]
        ds = catalog.chunk(scene, block, index, reads, {"power": str(record)})
        paths.append(write_dataset(ds, Path(workdir) / f"{index}.nc", **catalog.writing(block)))
        what = ("decisive stage, every realization a lane" if ds.attrs.get("stage") == "decisive"
                else f"first stage, realization {ds.attrs.get('chunk')}")
        log.info("%s: job %d of %d (%s) done in %.0f s", scene, index + 1, n, what, time.perf_counter() - start)
    ds = catalog.gather(scene, block, paths)
    ds.attrs.update(config_label="sleighsim judge", config_sha256=config_sha256(block))  # the block it ran
    return ds


def judge_state(params, state, horizon=None, *, precision=None, realizations=None, label=None, configfiles=(),
                workdir=None) -> xr.Dataset:
    """The chaos verdict dataset of the steady state ``state`` reaches with ``params`` (:func:`block_for`),
    by the workflow's rule (:func:`run_block`); the jobs' datasets go to ``workdir`` (default: a temporary
    directory, removed)."""
    block = block_for(params, state, horizon, precision=precision, realizations=realizations, label=label,
                      configfiles=configfiles)
    log.info("judge: %d jobs (per realization the first stage, then the decisive stage in %s over T = %g)",
             catalog.chunk_count(block), block["decisive"]["precision"], block["decisive"]["T"])
    if workdir is not None:
        return run_block(block, workdir)
    with tempfile.TemporaryDirectory(prefix="sleighsim-judge-") as tmp:
        return run_block(block, tmp).load()


def write(ds: xr.Dataset, path) -> Path:
    """Write a judged state's dataset as the workflow writes the chaos verdict's (CF names, provenance)."""
    return write_dataset(ds, path, what=CHAOS_VERDICT.title + " (sleighsim judge: one start state)",
                         vocabulary=CHAOS_VERDICT.vocabulary)


def answer(ds: xr.Dataset, record=None) -> ChaosAnswer:
    """The verdict of a judged state's dataset as the report words it: verdict, why, the arithmetic it was
    decided in, its class, the judges that decided it (with their measured power) and, when undecided, what
    would decide it (``record``: the judge-power record's path, by default the paper config's)."""
    if record is None:
        config = merged_config()
        record = REPO / config["scenes"][catalog.scenes_of(config, CHAOS_VERDICT)[0]]["vote_record"]
    (out,) = dataset_answers(ds, read_yaml(record))
    return out
