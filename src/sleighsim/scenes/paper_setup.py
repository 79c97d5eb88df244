"""The paper's unstated setup inferred jointly from all its numbers (scene kind ``paper_setup``): which
K2, integrator, psd convention, energy normalisation and Lyapunov integration, taken together, best
explain the values of paper/CLAIMS.md. No integration: the candidates' predictions are read from the
datasets the ledger's cause tests read (:mod:`sleighsim.scenes.setup_predictions`, which states the
separability assumption).

Score: :data:`SCORE_RULE` (written into the dataset). A setup under
which a scored number is not determined (NaN: no spike in the run, outside a sweep) is not ranked."""

from __future__ import annotations

import itertools
import logging
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from sleighsim.io.claims_table import parse_claims
from sleighsim.io.netcdf import read_dataset
from sleighsim.scenes import setup_predictions as sp
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger(__name__)

#: The setup elements; each scored number's dims are a subset of one block's.
ELEMENTS = ("K2", "integrator", "psd", "energy", "lyapunov")
BLOCKS = (("K2", "integrator"), ("K2", "psd"), ("energy",), ("lyapunov",))
#: The roles of the datasets it reads (the config's ``inputs`` names each role's scene): the K2 sweep, the
#: RK45 solver's sweep, the model audit (energy normalisations), the spectra at eps 0.1 and 0.01, the paper's
#: Lyapunov protocol, the converged spectrum, the hierarchy's closed forms.
ROLES = ("k2", "solver", "model", "psd_ref", "psd_small", "protocol", "spectrum", "hierarchy")
#: How setups are scored (attribute ``score_rule``).
SCORE_RULE = (
    "the deviance -2 ln L = sum over the scored numbers of ((pred - paper) / sigma)^2 + 2 ln sigma + ln 2 pi "
    "(lower is better), sigma^2 = sigma_paper^2 + sigma_measured^2: sigma_paper half a unit of the paper's last"
    " significant printed digit (:func:`spelling_sigma`), sigma_measured the standard error (or scatter) the "
    "dataset carries for that prediction, 0 where it carries none."
)


@dataclass
class Term:
    """One number of the paper: its claim, name, value and spelling, and its prediction ``pred`` (and
    measured uncertainty ``sd``) over the setup elements it depends on; ``scored``: in the deviance."""

    claim: str
    name: str
    paper: float
    text: str
    pred: xr.DataArray
    sd: xr.DataArray
    scored: bool = True


def spelling_sigma(text: str) -> float:
    """Half a unit of the last significant digit of a printed number: "0.241" -> 5e-4, "2.9e-4" ->
    5e-6, "8700" -> 50 (an integer's trailing zeros are not significant), "1" -> 0.5."""
    mant, _, exp = text.strip().lower().partition("e")
    mant = mant.lstrip("+-")
    if "." in mant:
        unit = 10.0 ** -len(mant.split(".")[1])
    else:
        digits = mant.lstrip("0") or "0"
        unit = 10.0 ** (len(digits) - len(digits.rstrip("0"))) if digits != "0" else 1.0
    return 0.5 * unit * 10.0 ** int(exp or 0)


def _da(values, dims) -> xr.DataArray:
    """A float DataArray over ``dims``."""
    return xr.DataArray(np.asarray(values, float), dims=dims)


def _sweep_terms(paper, d, grid) -> list[Term]:
    """C04, C05, C11 (K2 and integrator) and C09, C10's simulated numbers (K2 only)."""
    k2, err = d["k2"], d["solver"]
    out = []
    for cid, key, var in (("C04", "first_spike", "first_spike"), ("C05", "spike_interval", "spike_interval"),
                          ("C11", "omega_rel_error", "omega_rel_error")):
        out.append(Term(cid, key, paper[cid][key], paper[cid]["_text"][key], sp.spike_observable(k2, err, var, grid),
                        sp.spike_stderr(k2, err, var, grid)))
    for cid, key, var in (("C09", "Omega2_amplitude", "Omega2_amplitude"), ("C09", "phi1_over_pi", "phi1_over_pi"),
                          ("C10", "T2", "T2"), ("C10", "B", "B"), ("C10", "growth", "omega2_growth")):
        out.append(Term(cid, key, paper[cid][key], paper[cid]["_text"][key], sp.k2_observable(k2, var, grid),
                        _da(0.0, ())))
    theory = d["hierarchy"].attrs
    for key, attr in (("T2_theory", "theory_T2"), ("B_theory", "theory_B"), ("growth_theory", "theory_omega2_growth")):
        out.append(Term("C10", key, paper["C10"][key], paper["C10"]["_text"][key], _da(theory[attr], ()),
                        _da(0.0, ()), scored=False))
    return out


def _psd_terms(paper, d, grid, convs) -> list[Term]:
    """C23 (K2 and psd convention: the k2_sweep's band mapped) and C24 (psd convention only); the
    measured uncertainty of an edge is one frequency bin of its spectrum, in the convention's unit."""
    k2, p01, p001 = d["k2"], d["psd_ref"], d["psd_small"]
    factor = np.array([fa for _, fa, _ in convs])
    cases = (("C23", sp.interp_inside(k2.K2, k2.band_low, grid), sp.interp_inside(k2.K2, k2.band_high, grid),
              ("K2", "psd"), p01),
             ("C24", p001.attrs["Omega_band_low"], p001.attrs["Omega_band_high"], ("psd",), p001))
    out = []
    for cid, lo, hi, dims, psd in cases:
        edges = sp.band_edges(lo, hi, convs)
        bin_sd = _da(factor / psd.attrs["psd_segment"], ("psd",))
        for k, edge in enumerate(("band_low", "band_high")):
            out.append(Term(cid, edge, paper[cid]["band"][k], paper[cid]["_text"]["band"][k], _da(edges[k], dims),
                            bin_sd))
    return out


def _other_terms(paper, d) -> list[Term]:
    """D5 (energy normalisation) and C19 (Lyapunov candidates)."""
    a = d["model"].attrs
    out = [Term("D5", "label", paper["D5"]["label"], paper["D5"]["_text"]["label"],
                _da(a["d5_normalisation_values"], ("energy",)), _da(0.0, ()))]
    _, values, sd = sp.lyapunov_candidates(d["solver"], d["protocol"], d["spectrum"])
    want = sorted(zip(paper["C19"]["exponents"], paper["C19"]["_text"]["exponents"]), key=lambda p: -p[0])
    for i, (w, text) in enumerate(want):
        out.append(Term("C19", f"lambda_{i + 1}", w, text, _da(values[:, i], ("lyapunov",)),
                        _da(sd[:, i], ("lyapunov",))))
    return out


def deviance(term: Term) -> xr.DataArray:
    """((pred - paper) / sigma)^2 + 2 ln sigma + ln 2 pi of one number (NaN where not determined)."""
    sigma = np.sqrt(spelling_sigma(term.text) ** 2 + term.sd ** 2)
    return ((term.pred - term.paper) / sigma) ** 2 + 2 * np.log(sigma) + math.log(2 * math.pi)


def blocks(terms, coords: dict) -> list[np.ndarray]:
    """The summed deviance of each block of :data:`BLOCKS` as an array over its dims (the first
    block whose dims hold a scored number's); +inf where some number is not determined."""
    out = []
    for dims in BLOCKS:
        total = xr.DataArray(np.zeros([len(coords[k]) for k in dims]), dims=dims)
        for t in terms:
            home = next(b for b in BLOCKS if set(t.pred.dims) <= set(b))
            if t.scored and home == dims:
                total = total + deviance(t)
        v = total.transpose(*dims).values
        out.append(np.where(np.isfinite(v), v, np.inf))
    return out


def profiles(A, P, E, L) -> dict[str, np.ndarray]:
    """Per element, the least deviance over all setups with that element at each candidate (inf: none ranked)."""
    mA, mP, mE, mL = A.min(axis=1), P.min(axis=1), E.min(), L.min()
    rest = (mA + mP).min()
    return {"K2": mA + mP + mE + mL, "integrator": (A + mP[:, None]).min(axis=0) + mE + mL,
            "psd": (P + mA[:, None]).min(axis=0) + mE + mL, "energy": E + rest + mL, "lyapunov": L + rest + mE}


def top_setups(A, P, E, L, n: int) -> list[tuple[float, tuple[int, ...]]]:
    """The ``n`` lowest-deviance ranked setups as (deviance, (K2, integrator, psd, energy, lyapunov)
    indices), exact: a top-n setup uses, per block, one of that block's n best at its K2."""
    best = lambda v: [int(i) for i in np.argsort(v, kind="stable")[:n] if np.isfinite(v[i])]  # noqa: E731
    found = []
    for k in range(A.shape[0]):
        for i, j, e, m in itertools.product(best(A[k]), best(P[k]), best(E), best(L)):
            found.append((float(A[k, i] + P[k, j] + E[e] + L[m]), (k, i, j, e, m)))
    return sorted(found)[:n]


def n_ranked(A, P, E, L) -> int:
    """How many setups are ranked (every scored number determined)."""
    fin = lambda v: np.isfinite(v).sum(axis=-1)  # noqa: E731
    return int(np.sum(fin(A) * fin(P)) * fin(E) * fin(L))


def candidates(cfg: dict, d: dict) -> dict[str, list]:
    """The candidates of every element (coordinate values) and the psd conventions (label, factor, dt)."""
    err = d["solver"]
    s = cfg["sampling"]
    convs = sp.psd_conventions(np.geomspace(s["dt_min"], s["dt_max"], s["n"]))
    return {"K2": list(sp.k2_grid(d["k2"], cfg["K2_step"], err.attrs["param_K2"])),
            "integrator": sp.integrators(err, d["k2"].attrs["tol"]), "psd": [c[0] for c in convs],
            "energy": d["model"].attrs["d5_normalisation_names"].split(" | "),
            "lyapunov": sp.lyapunov_candidates(err, d["protocol"], d["spectrum"])[0], "_convs": convs}


def all_terms(paper: dict, cfg: dict, d: dict) -> tuple[list[Term], dict]:
    """Every number the setup is scored on (and C10's closed forms, not scored), with the coordinates;
    ``paper``: claim id -> its parsed values."""
    coords = candidates(cfg, d)
    terms = _sweep_terms(paper, d, coords["K2"]) + _psd_terms(paper, d, coords["K2"], coords.pop("_convs"))
    terms += _other_terms(paper, d)
    return terms, coords


def baseline(d: dict, coords: dict) -> dict[str, int]:
    """The run's own setup (indices): K2 of integration_error, heyoka, cycles/time unsampled, the
    mechanics' energy (the audit's first normalisation), the converged spectrum."""
    K2 = np.asarray(coords["K2"])
    return {"K2": int(np.argmin(np.abs(K2 - d["solver"].attrs["param_K2"]))), "integrator": 0,
            "psd": coords["psd"].index("cycles/time"), "energy": 0, "lyapunov": coords["lyapunov"].index(sp.CONVERGED)}


def _at(term: Term, where: dict) -> tuple[float, float]:
    """(prediction, measured sd) of a term at the setup ``where`` (element -> index)."""
    sel = {k: where[k] for k in term.pred.dims}
    sd = term.sd.isel({k: where[k] for k in term.sd.dims})
    return float(term.pred.isel(sel)), float(sd)


def term_table(terms, coords, best: dict, base: dict) -> xr.Dataset:
    """Per number (dim ``paper_number``): paper value and sigmas, prediction and residual under the best
    setup and the baseline, the elements that move it and those of them the best setup changes."""
    rows = []
    for t in terms:
        (b, sd_b), (r, sd_r) = _at(t, best), _at(t, base)
        s_p = spelling_sigma(t.text)
        changed = [f"{k} = {_label(coords, k, best[k])}" for k in t.pred.dims if best[k] != base[k]]
        rows.append((t.claim, t.name, t.paper, t.text, s_p, sd_b, b, (b - t.paper) / math.hypot(s_p, sd_b),
                     sd_r, r, (r - t.paper) / math.hypot(s_p, sd_r), ", ".join(t.pred.dims), "; ".join(changed),
                     int(t.scored)))
    cols = list(zip(*rows))
    spec = [("claim", "claim id of paper/CLAIMS.md", None), ("name", "name of the paper's number", None),
            ("paper", "the paper's value", "1"), ("paper_text", "the paper's spelling of the value", None),
            ("sigma_paper", "half a unit of the paper's last significant digit", "1"),
            ("best_sd", "measured uncertainty of the prediction under the best setup", "1"),
            ("best", "the number under the best setup", "1"),
            ("best_residual", "(best - paper) / sigma", "1"),
            ("baseline_sd", "measured uncertainty of the prediction under the run's setup", "1"),
            ("baseline", "the number under the run's own setup (converged physics)", "1"),
            ("baseline_residual", "(baseline - paper) / sigma", "1"),
            ("moved_by", "the setup elements its prediction depends on", None),
            ("changed_by", "the elements the best setup sets away from the run's", None),
            ("scored", "1: in the deviance; 0: reported only", "1")]
    data = {n: ("paper_number", np.array(c, dtype=object if unit is None else float),
                {"long_name": f"{ln} (model units of the number)" if unit else ln, **({"units": unit} if unit else {})})
            for (n, ln, unit), c in zip(spec, cols)}
    ids = ("paper_number", [f"{t.claim}:{t.name}" for t in terms], {"long_name": "claim id : name of the number"})
    return xr.Dataset(data, coords={"paper_number": ids})


def _label(coords, element: str, index: int) -> str:
    """Candidate ``index`` of ``element`` as text (K2 to 6 significant digits)."""
    v = coords[element][index]
    return f"{v:.6g}" if element == "K2" else str(v)


ELEMENT_NAMES = {"K2": None, "integrator": "integrator and tolerance of the paper's runs",
                 "psd": "frequency unit and sampling interval of the paper's spectra",
                 "energy": "energy normalisation behind the paper's E values",
                 "lyapunov": "integration of the paper's Lyapunov protocol"}


def ranking(top, coords, base_dev: float) -> xr.Dataset:
    """The top setups (dim ``rank``, 1 = best): each element's candidate, the deviance and its excess
    over the best."""
    data = {f"rank_{e}": ("rank", np.array([coords[e][idx[k]] for _, idx in top], dtype=float if e == "K2" else str),
                          {"long_name": f"candidate of element {e} at this rank"} if e != "K2" else
                          {"long_name": "K2 at this rank", "units": "1"})
            for k, e in enumerate(ELEMENTS)}
    dev = np.array([v for v, _ in top])
    data["deviance"] = ("rank", dev, {"long_name": "-2 ln L of the setup", "units": "1"})
    data["delta_deviance"] = ("rank", dev - dev[0] if dev.size else dev,
                              {"long_name": "deviance above the best setup's", "units": "1"})
    ds = xr.Dataset(data, coords={"rank": ("rank", np.arange(1, len(top) + 1), {"long_name": "rank", "units": "1"})})
    ds.attrs["deviance_baseline"] = base_dev
    return ds


def profile_dataset(prof: dict, coords: dict) -> xr.Dataset:
    """The least deviance at each candidate of each element (NaN: no ranked setup), with the candidates."""
    out = xr.Dataset()
    for e in ELEMENTS:
        v = np.where(np.isfinite(prof[e]), prof[e], np.nan)
        out[f"profile_{e}"] = ((e,), v, {"long_name": f"least deviance with {e} at the candidate", "units": "1"})
        cattrs = {"long_name": ELEMENT_NAMES[e]} if ELEMENT_NAMES[e] else {}
        out = out.assign_coords({e: ((e,), np.array(coords[e], dtype=float if e == "K2" else object), cattrs)})
    return out


def element_gaps(prof: dict, coords: dict, best: dict) -> dict:
    """Attributes per element: the best candidate, the runner-up (least deviance of any other
    candidate) and the deviance gap; K2's interval where its profile is within 1 of the least."""
    out = {}
    for e in ELEMENTS:
        v = prof[e]
        others = np.delete(v, best[e]) if v.size > 1 else np.array([np.inf])
        j = int(np.argmin(others))
        runner = j if j < best[e] else j + 1
        out[f"best_{e}"] = _label(coords, e, best[e]) if e != "K2" else float(coords["K2"][best[e]])
        out[f"runner_up_{e}"] = _label(coords, e, runner) if np.isfinite(others[j]) else "none ranked"
        out[f"gap_{e}"] = float(others[j] - v[best[e]]) if np.isfinite(others[j]) else math.nan
    K2, ok = np.asarray(coords["K2"]), prof["K2"] <= prof["K2"][best["K2"]] + 1.0
    out.update(best_K2_low=float(K2[ok].min()), best_K2_high=float(K2[ok].max()))
    return out


def misfit_interval(profile_K2, K2, residuals) -> dict:
    """K2's interval scaled by the misfit: the chi-square of the best setup's scored residuals (in sigma)
    per degree of freedom (scored numbers minus the 5 elements), at least 1, is the deviance margin over
    the least of K2's profile (the sigmas inflated until the best fit's reduced chi-square is 1)."""
    r = np.asarray(residuals, float)
    dof = max(r.size - len(ELEMENTS), 1)
    scale = max(float(np.sum(r**2)) / dof, 1.0)
    prof, K2 = np.asarray(profile_K2, float), np.asarray(K2, float)
    ok = prof <= np.nanmin(prof) + scale
    return {"misfit_scale": scale, "best_K2_low_scaled": float(K2[ok].min()),
            "best_K2_high_scaled": float(K2[ok].max())}


def infer(paper: dict, cfg: dict, d: dict) -> xr.Dataset:
    """The joint inference from the paper's values (``paper``: claim id -> parsed values) and the datasets
    ``d`` (role -> Dataset)."""
    terms, coords = all_terms(paper, cfg, d)
    A, P, E, L = blocks(terms, coords)
    top = top_setups(A, P, E, L, cfg["n_top"])
    base = baseline(d, coords)
    base_dev = float(A[base["K2"], base["integrator"]] + P[base["K2"], base["psd"]] + E[base["energy"]]
                     + L[base["lyapunov"]])
    prof = profiles(A, P, E, L)
    ds = xr.merge([ranking(top, coords, base_dev), profile_dataset(prof, coords)])
    ds.attrs.update(n_setups=int(np.prod([len(coords[e]) for e in ELEMENTS])), n_ranked=n_ranked(A, P, E, L),
                    deviance_baseline=base_dev if math.isfinite(base_dev) else math.nan)
    if not top:
        ds = xr.merge([ds, term_table(terms, coords, base, base)])
        ds.attrs.update(n_setups_note="no setup determines every scored number: none inferred")
        return ds
    best = dict(zip(ELEMENTS, top[0][1]))
    ds = xr.merge([ds, term_table(terms, coords, best, base)])
    ds.attrs.update(element_gaps(prof, coords, best), deviance_best=top[0][0])
    ds.attrs.update(misfit_interval(ds.profile_K2.values, ds.K2.values, ds.best_residual.values[ds.scored.values == 1]))
    return ds


RULES = {
    "score_rule": SCORE_RULE,
    "ranking_rule": "a setup under which a scored number is not determined is not ranked; ranks by deviance, "
                    "lowest first; an element's gap: the least deviance with any other candidate minus the best's; "
                    "K2 interval: where K2's profile deviance lies within 1 of its least; its scaled interval "
                    "(best_K2_*_scaled): within misfit_scale of it, the best setup's chi-square per degree of "
                    "freedom (scored numbers minus 5 elements, at least 1): the sigmas inflated until the fit is "
                    "as good as they say",
    "separability": sp.SEPARABILITY,
    "not_scored": "C10's closed-form numbers (T2_theory, B_theory, growth_theory): no sweep moves them; "
                  "reported at the run's value",
}


STATED = "the stated reference state"


def start_test(paper: dict, d: dict) -> dict:
    """Which start the paper's eps = 0.1 numbers came from: its stated reference state, or that state
    rescaled (time-scaling symmetry) until one of the audit's energy normalisations reads the paper's label
    (D5's E = 0.1127). A start rescaled by s = sqrt(label / Q) divides every period by s, so C08's T1 would
    read T1 * sqrt(Q / label) (time units). Returns attributes: each candidate's T1 and its residual in
    sigma (the paper's printed digit and the hierarchy's uncertainty), and the candidate of least |residual|."""
    a, h = d["model"].attrs, d["hierarchy"].attrs
    names = [STATED] + [f"rescaled to E = {paper['D5']['label']:g} under {n}"
                        for n in a["d5_normalisation_names"].split(" | ")]
    q = np.r_[paper["D5"]["label"], np.asarray(a["d5_normalisation_values"], float)]
    T1 = h["T1_u2"] * np.sqrt(q / paper["D5"]["label"])
    sigma = math.hypot(spelling_sigma(paper["C08"]["_text"]["T1"]), h["T1_u2_uncertainty"])
    res = (T1 - paper["C08"]["T1"]) / sigma
    return {"start": names[int(np.nanargmin(np.abs(res)))], "start_candidates": " | ".join(names),
            "start_T1": T1, "start_T1_residual": res,
            "start_rule": "the candidate whose T1 (C08, a period: divided by the rescaling) lies fewest sigma from the "
                          "paper's; the other numbers' periods and rates scale alike, so T1 alone, measured to 1e-6, "
                          "decides"}


def paper_setup(cfg: dict, inputs: dict, scene: str = "") -> xr.Dataset:
    """The ``paper_setup`` scene: reads the datasets of :data:`ROLES` and the paper's values
    (``inputs["claims_md"]``) and infers the setup (:func:`infer`); integrates nothing."""
    d = {role: read_dataset(inputs[role]) for role in ROLES}
    paper = {c.id: c.values for c in parse_claims(inputs["claims_md"])}
    ds = infer(paper, cfg, d)
    ds.attrs.update(RULES, scene=scene, K2_step=cfg["K2_step"], n_top=cfg["n_top"],
                    sources=", ".join(Path(inputs[r]).name for r in ROLES) + ", " + Path(inputs["claims_md"]).name,
                    baseline_K2=float(d["solver"].attrs["param_K2"]))
    ds.attrs.update(start_test(paper, d))
    log.info("paper setup: best %s; deviance %.4g (baseline %.4g)",
             {e: ds.attrs.get(f"best_{e}") for e in ELEMENTS}, ds.attrs.get("deviance_best", math.nan),
             ds.attrs["deviance_baseline"])
    return ds


#: Reads datasets and the claims table and integrates nothing: it holds no records.
PAPER_SETUP = SceneKind(
    name="paper_setup",
    title=("the paper's unstated setup (K2, integrator, psd convention, energy normalisation, Lyapunov "
           "integration) inferred jointly from all its numbers, from the cause datasets"),
    compute=paper_setup, inputs=ROLES, reads_paper=True, integrates=False,
                        records=lambda c: [])
