"""What a config's full run would cost, before it is launched: :func:`estimate` scales a measured
full-run summary (:mod:`sleighsim.ops.summary`) to the run another config would launch, with a
linear work model per scene kind (:func:`sleighsim.ops.workmodel.work`), and checks the chunk jobs
against their ``chunk_runtime_min``; :func:`format_estimate` gives the text the command line prints
(``python -m sleighsim.ops.costs estimate``)."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

from sleighsim.io import layout
from sleighsim.io.benchmark_files import CHUNK_RULES
from sleighsim.ops import rowprices
from sleighsim.ops.config import BASE_CONFIG, REPO
from sleighsim.ops.workmodel import chunk_work, is_modelled, work
from sleighsim.precision import Precision
from sleighsim.report.figures import catalog as figure_catalog
from sleighsim.scenes import catalog


def changed_keys(a, b, prefix="") -> list[str]:
    """Dotted paths of the values that differ between two blocks (added and removed keys included)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b), key=str):
            out += changed_keys(a.get(k), b.get(k), f"{prefix}{k}.")
        return out
    return [] if a == b else [prefix.rstrip(".")]


def _value(cfg, dotted, width: int = 40) -> str:
    """The value at a dotted path, its repr cut to ``width`` characters."""
    for k in dotted.split("."):
        cfg = cfg.get(k) if isinstance(cfg, dict) else None
    text = repr(cfg) if not isinstance(cfg, float) else f"{cfg:g}"
    return text if len(text) <= width else text[: width - 3] + "..."


def _job_cpu(j: dict) -> float:
    """CPU seconds of a measured job; its wall seconds where Snakemake sampled no CPU."""
    return j["cpu_s"] if j.get("cpu_s") is not None else j["wall_s"]


def startup_s(summary: dict) -> float:
    """The fixed CPU cost of a job (interpreter, imports): the smallest sampled CPU seconds of any
    measured job, i.e. of a job that does next to nothing. It does not scale with the work."""
    cpus = [j["cpu_s"] for j in summary["jobs"] if j.get("cpu_s") is not None]
    return min(cpus) if cpus else 0.0


def _scaled(cpu: float, ratio: float, base: float) -> float:
    """A job's CPU seconds with its part above the startup ``base`` scaled by ``ratio``."""
    fixed = min(base, cpu)
    return fixed + (cpu - fixed) * ratio


def _scene_ratio(scene: str, kind: str, mcfg: dict, tcfg: dict, est: dict) -> float:
    """The work ratio target / measured of a scene; records it under ``scaled``, or the scene under
    ``changed_not_scaled`` when it changed but no key of its work model did."""
    changed = changed_keys(mcfg, tcfg)
    modelled = [k for k in changed if is_modelled(kind, k)]
    not_modelled = [k for k in changed if not is_modelled(kind, k)]
    ratio, w_m, w_t = 1.0, None, None
    if modelled:
        w_m, w_t = work(kind, mcfg), work(kind, tcfg)
        if w_m > 0 and w_t > 0:
            ratio = w_t / w_m
        else:
            est["warnings"].append(f"{scene}: work measure is zero ({w_m} measured, {w_t} target): not scaled")
    if modelled and ratio != 1.0:
        est["scaled"].append({"scene": scene, "kind": kind, "ratio": ratio, "work_measured": w_m, "work_target": w_t,
                              "modelled": [f"{k}: {_value(mcfg, k)} -> {_value(tcfg, k)}" for k in modelled],
                              "not_modelled": [f"{k}: {_value(mcfg, k)} -> {_value(tcfg, k)}" for k in not_modelled]})
    elif changed:
        est["changed_not_scaled"].append({"scene": scene, "kind": kind, "changed": changed})
    return ratio


def _measured_chunks(have: list) -> dict:
    """{chunk index: CPU seconds} of the measured chunk jobs."""
    return {int(j["wildcards"].get("chunk", j["job"].rsplit("/", 1)[-1])): _job_cpu(j) for j in have
            if j["rule"] in CHUNK_RULES}


def _chunk_rates(have: list, mcfg: dict, base: float) -> list[tuple[float, float]]:
    """(CPU seconds above startup, work) of each measured chunk job with work."""
    mwork = chunk_work(mcfg)
    return [(max(cpu - base, 0.0), mwork[k]) for k, cpu in _measured_chunks(have).items()
            if k < len(mwork) and mwork[k] > 0]


def _chunk_check(scene: str, block: dict, tcfg: dict, cpus: list, rates: list, est: dict) -> None:
    """The largest chunk job of a scene (``cpus``: each target chunk's seconds) against its chunk_runtime_min,
    under ``chunks``; a warning when it exceeds it."""
    holds = catalog.KINDS[tcfg["kind"]].chunk_holds  # a grid's chunk holds eps rows
    k = max(range(len(cpus)), key=lambda i: cpus[i])
    limit = block.get("chunk_runtime_min")
    entry = {"scene": scene, "n_chunks": len(cpus), "largest_s": cpus[k], "largest_chunk": k,
             "eps": holds(tcfg, k) if holds else None,
             "limit_s": None if limit is None else 60.0 * limit,
             "rate_spread": [min(c / w for c, w in rates), max(c / w for c, w in rates)]}
    entry["exceeds"] = limit is not None and entry["largest_s"] > entry["limit_s"]
    est["chunks"].append(entry)
    if entry["exceeds"]:
        est["warnings"].append(f"{scene}: chunk {k} is estimated at {entry['largest_s'] / 60:.4g} min, more than "
                               f"chunk_runtime_min = {limit} min: raise chunk_runtime_min or n_chunks, or lower "
                               "the horizons, before submitting")


def _chunked_scene(scene: str, kind: str, block: dict, mcfg: dict, tcfg: dict, have: list, ratio: float,
                   base: float, est: dict, prices: dict | None = None) -> None:
    """A chunked scene's jobs: its chunks re-cut to the target's, at the measured CPU seconds per
    unit of work of its measured chunks (a grid whose run measured its row verdicts, ``prices``: each row's
    verdict by its steps per cycle instead, ``rowprices.chunk_seconds``); its other jobs as measured."""
    rates = _chunk_rates(have, mcfg, base)
    if not rates:
        est["unmeasured"].append(scene)
        return
    rate = sum(c for c, _ in rates) / sum(w for _, w in rates)
    cpus = (rowprices.chunk_seconds(prices, mcfg, tcfg, _measured_chunks(have), base) if prices
            else [base + rate * w for w in chunk_work(tcfg)])
    for k, cpu in enumerate(cpus):
        est["jobs"].append({"job": f"chunk/{scene}/{k}", "rule": "chunk", "kind": kind, "scene": scene,
                            "cpu_s": cpu, "ratio": ratio})
    for j in have:
        if j["rule"] not in CHUNK_RULES:
            est["jobs"].append({"job": j["job"], "rule": j["rule"], "kind": kind, "scene": scene,
                                "cpu_s": _job_cpu(j), "ratio": 1.0})
    _chunk_check(scene, block, tcfg, cpus, rates, est)


def _scene_jobs(target: dict, measured: dict, mjobs: list, base: float, est: dict, prices: dict) -> None:
    """The jobs of every scene of ``target``, scaled from the measured ones (``prices``: the summary's measured
    row verdicts per grid scene, ``rowprices.SECTION``)."""
    by_scene = defaultdict(list)
    for j in mjobs:
        if j.get("scene"):
            by_scene[j["scene"]].append(j)
    for scene in catalog.datasets(target):
        block = target["scenes"][scene]
        kind = block["kind"]
        tcfg = catalog.scene_config(target, scene)
        have = by_scene.get(scene, [])
        if not have or scene not in measured.get("scenes", {}):
            est["unmeasured"].append(scene)
            continue
        mcfg = catalog.scene_config(measured, scene)
        ratio = _scene_ratio(scene, kind, mcfg, tcfg, est)
        if catalog.KINDS[kind].chunked:
            _chunked_scene(scene, kind, block, mcfg, tcfg, have, ratio, base, est, prices.get(scene))
        else:
            for j in have:
                est["jobs"].append({"job": j["job"], "rule": j["rule"], "kind": kind, "scene": scene,
                                    "cpu_s": _scaled(_job_cpu(j), ratio, base), "ratio": ratio})


def _precision_cost() -> dict:
    """CPU seconds per time unit of integrators.flow in each precision (its own compact mode: on in quad
    only), from benchmarks/precision_cost.yaml; {} when that file is absent."""
    import yaml

    path = REPO / "benchmarks" / "precision_cost.yaml"
    if not path.exists():
        return {}
    rows = [(Precision.parse(r["precision"]), r) for r in yaml.safe_load(path.read_text())["rows"]]
    return {p: r["cost_s_per_tu"] for p, r in rows
            if r["system"] == "flow" and not r["high_accuracy"] and r["compact_mode"] == (p is Precision.QUAD)}


def _variant_cpu(cpu: dict, name: str) -> float | None:
    """CPU seconds of the measured jobs of a scene's variant ``name`` (precision/<tag>/<scene>): its
    scene job, or its chunk jobs and their gather; None when it was not measured."""
    if f"scene/{name}" in cpu:
        return cpu[f"scene/{name}"]
    if f"gather/{name}" in cpu:
        return sum(c for j, c in cpu.items() if j == f"gather/{name}" or j.startswith(f"chunk/{name}/"))
    return None


def _new_jobs(target: dict, mjobs: list, est: dict) -> None:
    """Jobs of the target that the measured run did not have: a realization costs what its scene's
    own job cost; a scene in a finer precision what it cost in long double (its one job, or its chunks
    and their gather), or without that in double (its own job), times the ratio of the flow's cost per time
    unit (benchmarks/precision_cost.yaml; the variant's double transient is counted at that rate too, so this
    errs high), as one job named scene/<variant> for a variant that runs as chunks too. Anything else:
    unmeasured."""
    cpu = {j["job"]: _job_cpu(j) for j in mjobs}
    cost = _precision_cost()
    for scene, n in catalog.realized(target).items():
        for k in range(1, n):
            name = f"scene/{layout.realization(scene, k)}"
            if name not in cpu and f"scene/{scene}" in cpu:
                est["jobs"].append({"job": name, "rule": "scene_realization", "kind": target["scenes"][scene]["kind"],
                                    "scene": scene, "cpu_s": cpu[f"scene/{scene}"], "ratio": 1.0})
    for scene, precisions in catalog.laddered(target).items():
        base = _base_variant(cpu, scene, cost)
        for p in precisions[1:]:
            if _variant_cpu(cpu, layout.variant(scene, p)) is not None:
                continue
            name = f"scene/{layout.variant(scene, p)}"
            if base is not None and p in cost:
                ratio = cost[p] / cost[base[0]]
                est["jobs"].append({"job": name, "rule": "scene_in_precision", "kind": target["scenes"][scene]["kind"],
                                    "scene": scene, "cpu_s": base[1] * ratio, "ratio": ratio})
            else:
                est["unmeasured"].append(name)


def _base_variant(cpu: dict, scene: str, cost: dict) -> tuple[Precision, float] | None:
    """The measured run a scene's unmeasured finer precisions are priced from: its long-double variant (its one
    job, or its chunks and their gather), else its own job in double (the whole scene, transient included, so
    this errs high too), with that precision; None when neither was measured or priced per time unit."""
    for p, measured in ((Precision.LONG_DOUBLE, _variant_cpu(cpu, layout.variant(scene, Precision.LONG_DOUBLE))),
                        (Precision.DOUBLE, cpu.get(f"scene/{scene}"))):
        if measured is not None and p in cost:
            return p, measured
    return None


def _other_jobs(target: dict, mjobs: list, est: dict) -> None:
    """Jobs that are not scenes (figures of the target, claims, report), as measured."""
    figures = set(figure_catalog.figures_built(target))
    for j in mjobs:
        if j.get("scene"):
            continue
        parts = j["job"].split("/")
        if parts[0] == "figure" and parts[-1] not in figures:
            continue
        est["jobs"].append({"job": j["job"], "rule": j["rule"], "kind": f"({j['rule']})", "scene": None,
                            "cpu_s": _job_cpu(j), "ratio": 1.0})
    measured_figs = {j["job"].split("/", 1)[1] for j in mjobs if j["job"].startswith("figure/")}
    est["unmeasured"] += [f"figure {f}" for f in figures if f not in measured_figs]


def _tally(jobs: list) -> tuple[dict, dict]:
    """Jobs and CPU seconds per rule and per job kind, largest first."""
    rules, kinds = {}, {}
    for j in jobs:
        for table, key in ((rules, j["rule"]), (kinds, j["kind"])):
            e = table.setdefault(key, {"jobs": 0, "cpu_s": 0.0})
            e["jobs"] += 1
            e["cpu_s"] += j["cpu_s"]

    def order(d):
        return dict(sorted(d.items(), key=lambda kv: (-kv[1]["cpu_s"], kv[0])))

    return order(rules), order(kinds)


def estimate(target: dict, summary: dict) -> dict:
    """Estimated CPU seconds of the full run ``target`` (a merged config) would launch, from the
    measured ``summary``. Linear work model: a job's CPU seconds are a fixed startup
    (:func:`startup_s`) plus a part proportional to its work, so each measured scene job becomes
    startup + (measured - startup) x work(target block) / work(measured block), the ratio 1 when no
    key of the work model changed; chunk jobs are re-cut to the target's chunks at the measured CPU
    seconds per unit of work of the scene's chunks; realizations and finer precisions the measured run
    did not have as :func:`_new_jobs` says; gather, figure, claims and report jobs stay as measured.

    Returns {jobs: [{job, rule, kind, scene, cpu_s, ratio}], rules, kinds: {name: {jobs, cpu_s}},
    total_cpu_s, startup_s, scaled: [{scene, kind, ratio, work_measured, work_target, modelled,
    not_modelled}], changed_not_scaled, unmeasured, chunks: [{scene, n_chunks, largest_s,
    largest_chunk, eps, limit_s, exceeds, rate_spread}], warnings}."""
    measured = summary["config"]["values"]
    if measured is None:
        raise ValueError("the measured summary records no config values: cannot compare configs")
    base = startup_s(summary)
    est = {"jobs": [], "scaled": [], "changed_not_scaled": [], "unmeasured": [], "chunks": [], "warnings": []}
    _scene_jobs(target, measured, summary["jobs"], base, est, summary.get(rowprices.SECTION) or {})
    _new_jobs(target, summary["jobs"], est)
    _other_jobs(target, summary["jobs"], est)
    if est["unmeasured"]:
        est["warnings"].append(f"no measurement for {', '.join(est['unmeasured'])}: left out of the estimate "
                               "(it is low)")
    jobs = est["jobs"]
    rules, kinds = _tally(jobs)
    return {"jobs": sorted(jobs, key=lambda j: -j["cpu_s"]), "rules": rules, "kinds": kinds,
            "total_cpu_s": sum(j["cpu_s"] for j in jobs), "startup_s": base, "scaled": est["scaled"],
            "changed_not_scaled": est["changed_not_scaled"], "unmeasured": est["unmeasured"],
            "chunks": est["chunks"], "warnings": est["warnings"]}


def _header_lines(est: dict, target_label: str, summary: dict, measured_path, base) -> list[str]:
    """What is estimated, from which measurement, and how."""
    m = summary.get("machine") or {}
    base = Path(base).resolve()
    return [
        (f"Estimated cost of the full run of {target_label} (merged onto "
         f"{base.relative_to(REPO) if base.is_relative_to(REPO) else base})"),
        (f"measured: {measured_path} (config {summary['config'].get('label') or 'config/config.yaml'}, "
         f"{summary.get('date')}, commit {str(summary.get('git_commit'))[:12]}, {m.get('nproc')} cores "
         f"{m.get('cpu_model')}; {summary['cpu_s'] / 3600:.3g} core-h measured)"),
        "",
        ("ESTIMATES from a linear work model: a scene job's CPU seconds = startup + (measured - startup) x "
         "(its work in the target config / its work in the measured one),"),
        (f"startup = {est['startup_s']:.3g} s (the cheapest measured job); work = time units integrated "
         "(lyapunov_grid: per eps row pre-run + replica sampling + one tangent"),
        ("batch to the max_rounds cap; other kinds: the block's horizons). Gather, figure, claims and report "
         "jobs as measured; CPU seconds are Snakemake's sampled cpu_time."),
        "",
    ]


def _scene_lines(est: dict) -> list[str]:
    """The scaled scenes, the changed ones not scaled, and how many are as measured."""
    lines = []
    if est["scaled"]:
        lines.append("Scaled scenes:")
        for s in est["scaled"]:
            lines.append(f"  {s['scene']} ({s['kind']}): x{s['ratio']:.4g}  [work {s['work_measured']:.4g} -> "
                         f"{s['work_target']:.4g}]")
            lines.append(f"      in the model: {'; '.join(s['modelled'])}")
            if s["not_modelled"]:
                lines.append(f"      changed, not in the model: {'; '.join(s['not_modelled'])}")
    else:
        lines.append("Scaled scenes: none (every scene's work is as measured)")
    for s in est["changed_not_scaled"]:
        lines.append(f"  {s['scene']} ({s['kind']}): changed but not scaled (no modelled key changed): "
                     f"{', '.join(s['changed'])}")
    n_same = len({j['scene'] for j in est['jobs'] if j['scene']}) - len(est["scaled"]) - len(est["changed_not_scaled"])
    lines.append(f"Unchanged scenes, as measured: {n_same}")
    return lines


def _table_lines(est: dict) -> list[str]:
    """Jobs, core-hours and share per rule and per job kind, and the total."""
    ch = 1 / 3600
    lines = ["", f"{'per rule':<24}{'jobs':>6}{'core-h':>12}{'share':>8}"]
    total = est["total_cpu_s"] or 1.0
    for name, e in est["rules"].items():
        lines.append(f"  {name:<22}{e['jobs']:>6}{e['cpu_s'] * ch:>12.4g}{100 * e['cpu_s'] / total:>7.1f}%")
    lines += ["", f"{'per job kind':<24}{'jobs':>6}{'core-h':>12}{'share':>8}"]
    for name, e in est["kinds"].items():
        lines.append(f"  {name:<22}{e['jobs']:>6}{e['cpu_s'] * ch:>12.4g}{100 * e['cpu_s'] / total:>7.1f}%")
    n_jobs = sum(e["jobs"] for e in est["rules"].values())
    lines += ["", f"{'total':<24}{n_jobs:>6}{est['total_cpu_s'] * ch:>12.4g}  core-hours (estimate)", ""]
    return lines


def _chunk_lines(est: dict) -> list[str]:
    """The largest chunk job of each chunked scene against its limit."""
    lines = []
    for c in est["chunks"]:
        rows = "" if c["eps"] is None else ", eps " + ", ".join(f"{e:.4g}" for e in c["eps"])
        limit = "no chunk_runtime_min" if c["limit_s"] is None else f"chunk_runtime_min {c['limit_s'] / 60:g} min"
        lines.append(f"Chunk jobs of {c['scene']}: {c['n_chunks']} jobs; largest estimated runtime "
                     f"{c['largest_s'] / 60:.4g} min (chunk {c['largest_chunk']}{rows}; one core) against "
                     f"{limit}: {'EXCEEDS' if c['exceeds'] else 'within'}")
        lo, hi = c["rate_spread"]
        lines.append(f"  measured CPU seconds per unit work across its chunks: {lo:.3g} to {hi:.3g} "
                     "(the linear model's spread)")
    return lines


def format_estimate(est: dict, target_label: str, summary: dict, measured_path, base=BASE_CONFIG,
                    schedule: list[str] = ()) -> str:
    """The estimate as the text the CLI prints (``schedule``: lines on the wall time, before the warnings)."""
    lines = _header_lines(est, target_label, summary, measured_path, base)
    lines += _scene_lines(est) + _table_lines(est) + _chunk_lines(est) + list(schedule)
    lines += [f"WARNING: {w}" for w in est["warnings"]]
    return "\n".join(lines) + "\n"
