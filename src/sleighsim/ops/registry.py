"""What the workflow builds, declared once.

- Scenes live in the config: each block under ``scenes`` names its ``kind``; the dataset is
  ``results/data/<scene>.nc``. :data:`KINDS` says how each kind runs and which other datasets
  (by role, named in the block's ``inputs``) it reads; :mod:`sleighsim.scenes` imports its function.
- :data:`FIGURES`: every figure, the datasets its plot function reads (in order), the paper's
  figure id and the claims it illustrates.
- :data:`EVIDENCE`: the datasets each claim of ``paper/CLAIMS.md`` is judged from (in the order
  its judge takes them).

The Snakefile, the config checks, the claims ledger and the report all derive from these;
nothing else lists scenes, figures or claims. This module imports nothing heavy, so the
workflow can read it while it builds the job graph.
"""

from __future__ import annotations

from dataclasses import dataclass

from sleighsim.engine.precision import Precision


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
    """A precision's name in paths (``Precision.tag``): "long double" -> "long_double"."""
    return Precision.parse(precision).tag


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


@dataclass(frozen=True)
class Figure:
    """A figure: ``data`` are the datasets its plot function reads, in order; ``plot`` names the
    function in :mod:`sleighsim.report.figures` (default: the figure's own name); ``paper`` is
    its id in CLAIMS.md ("" when the paper has no such figure, then ``title`` heads its report
    section); ``claims`` are the claims it illustrates; ``schematic`` names the scene whose
    config block a dataset-free figure draws; ``steady`` are the datasets that show a steady state,
    each of which must carry a passed transient check (``transient_over``) for the figure to count;
    ``beside``: the figure also reads its laddered scenes in their finer precisions (after ``data``)
    and draws them beside the paper's arithmetic."""

    data: tuple[str, ...] = ()
    paper: str = ""
    claims: tuple[str, ...] = ()
    title: str = ""
    plot: str = ""
    schematic: str = ""
    steady: tuple[str, ...] = ()
    beside: bool = False


FIGURES: dict[str, Figure] = {
    "fig1": Figure(paper="F1", schematic="fig1"),
    "fig2": Figure(("fig2",), "F2", ("C01",)),
    "fig3": Figure(("fig3",), "F3", ("C03", "C04", "C05"), beside=True),
    "fig4": Figure(("fig4",), "F4", ("C06",)),
    "fig5": Figure(("fig5",), "F5", ("C11",)),
    "fig6": Figure(("fig6",), "F6", ("C07", "C08", "C09", "C10")),
    "transients": Figure(("transients", "fig3"), title="Transient length against eps (C03-C05)"),
    "perturbation": Figure(("fig5", "pert_audit"),
                           title="Perturbation hierarchy: convergence as eps -> 0 and secular growth (C12)"),
    "fig7": Figure(("fig7",), "F7", ("C13",), steady=("fig7",)),
    "fig8": Figure(("fig8",), "F8", ("C14",), steady=("fig8",), beside=True),
    "fig9": Figure(("fig9_ref", "fig9_highE", "fig9_eps001", "fig9_scaling"), "F9", ("C15", "C16", "C17"),
                   steady=("fig9_ref", "fig9_highE", "fig9_eps001")),
    "fig12": Figure(("fig9_ref", "fig9_eps001"), "F12", ("C22",), steady=("fig9_ref", "fig9_eps001"), beside=True),
    "fig13": Figure(("psd_eps01",), "F13", ("C23",), plot="psd", steady=("psd_eps01",), beside=True),
    "fig14": Figure(("psd_eps001",), "F14", ("C24",), plot="psd", steady=("psd_eps001",), beside=True),
    "fig10": Figure(("lyap_energy",), "F10", ("C20",), steady=("lyap_energy",), beside=True),
    "fig11": Figure(("fig11_grid",), "F11", ("C21",), steady=("fig11_grid",), beside=True),
    "lyapunov": Figure(("lyap_spectrum", "lyap_protocol"), title="Lyapunov spectrum and the paper's protocol"),
    "chaos": Figure(("chaos_verdict",), title="Is the steady state chaotic? Indicators per state",
                    steady=("chaos_verdict",)),
    "regimes": Figure(("regimes",), title="Regime diagram: lambda_1, spike interval and P_2pi rotation number "
                                         "against eps (C27)"),
    "basins": Figure(("basins",), title="Basin fractions on the energy level (C06 made quantitative)"),
    "precision": Figure(("precision_ladder",), title="Does the arithmetic decide the steady state? Spike intervals "
                                                     "per precision from one settled point, and the orbits' separation",
                        steady=("precision_ladder",)),
    "trigger": Figure(("trigger_law",), title="What triggers the steady state? The first spike against the size of "
                                              "the injected error (C04)"),
    "drift": Figure(("main_drift",), title="Does the main state's slow drift end? Spike interval and lambda_1 per "
                                          "window"),
    "audit": Figure(("audit",), title="The model as printed: energy drift of the printed udot"),
    "bench": Figure(("bench",), title="Speed against error"),
}

#: The atlas (on request: snakemake -c2 atlas): the figures of the large chaos surveys.
ATLAS = ("regimes", "basins", "drift")


@dataclass(frozen=True)
class Table:
    """A table of the report: dataset ``data``, one row per value of ``key``, the ``columns`` shown;
    rows coloured by the value of ``colour_by`` (an outcome) when given."""

    data: str
    key: str
    columns: tuple[str, ...]
    colour_by: str = ""


#: Tables the report shows after the figures: section title -> table.
TABLES: dict[str, Table] = {
    "Perturbation hierarchy: terms where the printed equations differ from the derived ones":
        Table("pert_audit", "equation", ("term", "derived", "printed", "derived_with_kappa")),
    "Hard cases": Table("hardcases", "case", ("outcome", "error", "drift", "disagreement", "steps", "wall_s", "detail"),
                        colour_by="outcome"),
}

EVIDENCE: dict[str, tuple[str, ...]] = {
    "C01": ("fig2",),
    "C03": ("fig3",),
    "C04": ("fig3", "transients"),
    "C05": ("fig3",),
    "C06": ("fig4",),
    "C07": ("fig6",),
    "C08": ("fig6",),
    "C09": ("fig6",),
    "C10": ("fig6",),
    "C11": ("fig5",),
    "C12": ("pert_audit",),
    "C13": ("fig7",),
    "C14": ("fig8",),
    "C15": ("fig9_ref",),
    "C16": ("fig9_ref",),
    "C17": ("fig9_ref", "fig9_highE", "fig9_eps001", "fig9_scaling"),
    "C18": ("lyap_spectrum",),
    "C19": ("lyap_protocol", "lyap_spectrum"),
    "C20": ("lyap_energy",),
    "C21": ("fig11_grid",),
    "C22": ("fig9_ref",),
    "C23": ("psd_eps01",),
    "C24": ("psd_eps001",),
    "C25": ("lyap_feasibility",),
    "C26": ("formal_exponents",),
    "C27": ("fig11_grid",),
    "D1": ("audit",),
    "D2": ("audit",),
    "D3": ("audit",),
    "D4": ("audit",),
    "D5": ("audit",),
    "D6": ("audit",),
}

#: The datasets each "differs" of a claim is tested against for its likely causes
#: (sleighsim.claims.causes), in the order its cause test takes them.
CAUSES: dict[str, tuple[str, ...]] = {
    "C04": ("k2_sweep", "integration_error", "audit", "trigger_law"),
    "C05": ("k2_sweep", "integration_error", "audit"),
    "C09": ("k2_sweep",),
    "C10": ("k2_sweep",),
    "C11": ("k2_sweep", "integration_error"),
    "C13": ("k2_sweep",),
    "C18": ("integration_error",),
    "C19": ("integration_error",),
    "C20": ("integration_error",),
    "C21": ("integration_error",),
    "C22": ("fig9_ref",),
    "C23": ("psd_eps01", "k2_sweep"),
    "C24": ("psd_eps001",),
    "D5": ("audit",),
}


#: What each dataset is (its CF ``title``, :func:`sleighsim.io.cf.title`): every scene of the configs
#: that makes a dataset, the claims ledger and the verdict stability table, by the name of its file.
TITLES: dict[str, str] = {
    "fig2": "the rotor-free sleigh (eps = 0): phase portrait against the closed form, vector field and a path "
            "(figure F2, claim C01)",
    "fig3": "one run from the reference state (0, 0.1, 1, 0) at eps = 0.1 through the transients into the steady "
            "state (figure F3, claims C03-C05)",
    "fig4": "several start states on two energy levels, each run to its steady state and compared under the "
            "time-scaling law (figure F4, claim C06)",
    "fig5": "the perturbation series to order 2 against the exact flow, and its convergence as eps -> 0 "
            "(figure F5, claim C11)",
    "fig6": "the order-0 and order-2 terms of the perturbation hierarchy with the paper's numbers (figure F6, "
            "claims C07-C10)",
    "pert_audit": "the printed perturbation hierarchy against the derived one, order 3 and the secular terms of "
                  "order 4 (claim C12)",
    "transients": "the transient phases against eps from the reference state (claims C03-C05)",
    "fig7": "the steady state: velocities, heading and path over a window after the transient (figure F7, "
            "claim C13)",
    "fig8": "the path of the sleigh over a long window after the transient (figure F8, claim C14)",
    "fig9_ref": "Poincare maps P_2pi and P_pi/2, return times and loops of the steady state at the reference "
                "label, eps = 0.1 (figures F9, F12, claims C15-C17, C22)",
    "fig9_highE": "Poincare maps of the steady state at a higher energy label, eps = 0.1 (figure F9c, claim C17)",
    "fig9_eps001": "Poincare maps and return times of the steady state at eps = 0.01 (figures F9d, F12, claim C17)",
    "fig9_scaling": "the attractor at a higher energy label mapped by the time-scaling law onto the reference one "
                    "(claim C17)",
    "psd_eps01": "power spectra of u and Omega on the attractor, eps = 0.1 (figure F13, claim C23)",
    "psd_eps001": "power spectra of u and Omega on the attractor, eps = 0.01 (figure F14, claim C24)",
    "lyap_spectrum": "the four Lyapunov exponents of the steady state from independent replicas (claims C18, C19)",
    "lyap_protocol": "the paper's Lyapunov protocol from several start states on one level (claim C19)",
    "lyap_energy": "the largest Lyapunov exponent against the energy label (figure F10, claim C20)",
    "lyap_feasibility": "what small eps costs: transient length and integrator steps extrapolated in eps "
                        "(claim C25)",
    "formal_exponents": "the largest Lyapunov exponent of the formal system, eps >= 1 (claim C26)",
    "fig11_grid": "the largest Lyapunov exponent over (eps, b) at the reference label (figure F11, claims C21, "
                  "C27)",
    "regimes": "the regime diagram: lambda_1, spike interval and P_2pi rotation number against eps (claim C27)",
    "chaos_verdict": "is the steady state chaotic? Indicators, their verdicts and the faithfulness gauge per "
                     "start state",
    "trigger_law": "the first spike against the size of the injected error (tolerance and arithmetic) (claim C04)",
    "precision_ladder": "spike times per arithmetic from one settled point and the orbits' separation",
    "main_drift": "the main state's slow drift: spike interval and lambda_1 per window of one long run",
    "basins": "basin fractions of the steady states on one energy level (claim C06 made quantitative)",
    "audit": "the model as printed: energy drift of the printed udot, and the paper's other slips (D1-D6)",
    "k2_sweep": "the observables the unstated K bears on, against K2 (likely causes of C04, C05, C09-C11, C13, "
                "C23)",
    "integration_error": "SciPy's RK45 (standing in for MATLAB's ode45) against its tolerance: spikes, series "
                         "error and the paper's Lyapunov protocol (likely causes of C04, C05, C11, C18-C21)",
    "hardcases": "hard cases of the integrator: extreme parameters, energies and horizons, states at rest and on "
                 "a section",
    "bench": "speed against error: heyoka, SciPy and peer engines",
    "claims": "the claims ledger: every claim of the paper judged from the datasets (paper/CLAIMS.md)",
    "stability/verdicts": "verdict stability: the ledger's verdicts with perturbed start states and at a looser "
                          "tolerance",
}


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


def figures_built(config: dict, *, on_request: bool = False) -> list[str]:
    """The figures whose datasets (or schematic block) the config builds, in declaration order."""
    built = set(datasets(config, on_request=on_request))
    drawn = {n for n, block in config["scenes"].items() if on_request or not block.get("on_request", False)}
    return [name for name, f in FIGURES.items()
            if set(f.data) <= built and (not f.schematic or f.schematic in drawn)]


def plot_name(figure: str) -> str:
    """The plot function of a figure."""
    return FIGURES[figure].plot or figure
