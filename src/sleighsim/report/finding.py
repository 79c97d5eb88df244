"""The finding in one paragraph, composed from the ledger and the chaos verdicts (never typed by hand): how
many of the paper's items the ledger reproduces, what it says of the claims that the steady state is chaotic
(:data:`sleighsim.claims.judges.lyapunov.CHAOS_CLAIMS`), each steady state's chaos verdict here and in a
verdict measured with another config, and what that means for the paper's claim. :func:`facts` gathers the
numbers (the report job writes them as ``report/finding.yaml``); :func:`paragraph` words them, the same
way for the report's top and the README's copy (``sleighsim finding``)."""

from __future__ import annotations

from sleighsim.claims import fidelity
from sleighsim.claims.judges.lyapunov import CHAOS_CLAIMS
from sleighsim.claims.rules import REPRODUCED, VERDICTS
from sleighsim.io.netcdf import read_dataset

#: The format of the facts (report/finding.yaml).
SCHEMA = "sleighsim.finding/1"
#: The chaos verdicts that decide a state.
DECIDED = ("chaotic", "regular")


def provenance(datasets: dict) -> dict:
    """The commit and date of the run's chaos verdicts (the datasets with a per-state ``verdict``):
    {git_commit, date} (the newest date; commits joined when several), or empty strings without one."""
    commits, dates = set(), []
    for path in datasets.values():
        ds = read_dataset(path, verified=False)
        if "verdict" in ds.data_vars and "state" in ds.dims:
            commits.add(str(ds.attrs.get("git_commit", "unknown")))
            dates.append(str(ds.attrs.get("created_utc", ""))[:10])
    return {"git_commit": ", ".join(sorted(commits)), "date": max(dates, default="")}


def _elsewhere(cluster: dict | None) -> list[dict]:
    """Per state of a verdict measured with another config: how many realizations gave each verdict, the
    arithmetic, horizon and newest date."""
    out = []
    for state in dict.fromkeys(r["state"] for r in (cluster or {}).get("realizations", [])):
        rs = [r for r in cluster["realizations"] if r["state"] == state]
        out.append({"state": state, "config": cluster["config"], "n": len(rs),
                    "counts": {v: sum(r["verdict"] == v for r in rs) for v in dict.fromkeys(r["verdict"] for r in rs)},
                    "precision": rs[0]["precision"], "T": float(rs[0]["T"]),
                    "date": max(str(r["created_utc"])[:10] for r in rs)})
    return out


def facts(rows: list, chaos: list, cluster: dict | None, identity: dict, run: dict, orbit: str = "") -> dict:
    """What the paragraph states, from the ledger's ``rows``, the chaos answers ``chaos``
    (:func:`sleighsim.report.chaos_answers.chaos_answers`), a verdict measured with another config
    (``cluster``, its record; None without one), the run's ``identity`` (label and config hash) and ``run``
    ({git_commit, date}: :func:`provenance`) and what the paper's own orbit does (``orbit``, a sentence of
    :mod:`sleighsim.report.paper_orbit`; empty without one). A run not at the paper's fidelity counts its own
    data's verdicts."""
    reproduction = fidelity.at_paper_fidelity(identity["config_label"])

    def verdict(r):
        return r.verdict if reproduction else (r.run_verdict or r.verdict)

    return {"schema": SCHEMA, "config_label": identity["config_label"], "config_sha256": identity["config_sha256"],
            "reproduction": reproduction, "git_commit": run["git_commit"], "date": run["date"], "n_rows": len(rows),
            "counts": {v: n for v in VERDICTS if (n := sum(verdict(r) == v for r in rows))},
            "chaos_claims": {r.id: verdict(r) for r in rows if r.id in CHAOS_CLAIMS},
            "faithful_claims": {r.id: r.faithful_verdict for r in faithful_claims(rows)},
            "states": {c.state: c.verdict for c in chaos},
            "elsewhere": _elsewhere(cluster) if reproduction else [], "paper_orbit": orbit}


def faithful_claims(rows: list) -> list:
    """The ledger's claim rows (C..) with a faithful verdict (:mod:`sleighsim.claims.faithful`), in order."""
    return [r for r in rows if r.faithful_verdict and r.id.startswith("C")]


def _listed(words: list[str]) -> str:
    """'a', 'a and b', 'a, b and c'."""
    return " and ".join(words) if len(words) < 3 else ", ".join(words[:-1]) + " and " + words[-1]


def _by_verdict(verdict_of: dict, verb: bool = False) -> str:
    """'C19 and C20 "differs"; C21 "cannot be reproduced"' (``verb``: 'main is "regular"; a and b are ...'):
    the names grouped by their verdict, in order."""
    groups = {}
    for name, v in verdict_of.items():
        groups.setdefault(v, []).append(name)
    return "; ".join(f'{_listed(names)}{(" is" if len(names) == 1 else " are") if verb else ""} "{v}"'
                     for v, names in groups.items())


def _faithful_sentence(verdict_of: dict) -> str:
    """How many of the chaos claims hold in an arithmetic that follows each orbit, and the others by verdict."""
    if not verdict_of:
        return "No chaos claim is judged in an arithmetic that follows its orbit."
    hold = sum(v == REPRODUCED for v in verdict_of.values())
    return (f"Judged in an arithmetic that follows each claim's orbit (the ledger's faithful columns), {hold} of the "
            f"paper's {len(verdict_of)} chaos claims hold: {_by_verdict(verdict_of)}.")


def _head(f: dict) -> str:
    ident = fidelity.describe(f)
    at = f"commit {f['git_commit'][:12]} of {f['date']}" if f["git_commit"] else "its commit unrecorded"
    if f["reproduction"]:
        return f"The finding of the run of {ident} at {at}:"
    return (f"This {f['config_label']} run ({ident}, {at}) is NOT a reproduction and finds nothing about the "
            "paper; on its own short horizons its data give:")


def _states_sentence(f: dict) -> str:
    """Each steady state's chaos verdict here, and the verdicts measured with another config."""
    if not f["states"]:
        return "This run computed no chaos verdict."
    text = ("Judged by independent indicators in an arithmetic that follows each orbit (the chaos verdict), "
            f"here {_by_verdict(f['states'], verb=True)}.")
    for e in f["elsewhere"]:
        counts = _listed([f'"{v}" in {n} of {e["n"]} realizations' for v, n in e["counts"].items()])
        text += (f" Measured beyond this run with {e['config']} ({e['precision']} over T = {e['T']:g}, {e['date']}), "
                 f"{e['state']} is {counts}.")
    return text


def decided(f: dict) -> dict:
    """{state: (chaotic or regular, where)}: this run's verdict where it decides ('here'), else one every
    realization measured with another config agrees on (that config)."""
    out = {s: (v, "here") for s, v in f["states"].items() if v in DECIDED}
    for e in f["elsewhere"]:
        if e["state"] not in out and len(e["counts"]) == 1 and (v := next(iter(e["counts"]))) in DECIDED:
            out[e["state"]] = (v, e["config"])
    return out


def _named(d: dict, verdict: str) -> list[str]:
    """The states ``d`` (:func:`decided`) decides as ``verdict``, each with the config that decided it
    when that is not this run."""
    return [s if where == "here" else f"{s}, with {where}" for s, (v, where) in d.items() if v == verdict]


def _conclusion(f: dict) -> str:
    """What the verdicts mean for the paper's claim that the steady state is chaotic."""
    d = decided(f)
    chaotic, regular = _named(d, "chaotic"), _named(d, "regular")
    open_ = [s for s in f["states"] if s not in d]
    rest = f"; {_listed(open_)} {'remains' if len(open_) == 1 else 'remain'} undecided" if open_ else ""
    if not d:
        return ("So the data neither confirm nor refute the paper's claim that the steady state is chaotic: no "
                "steady state is decided.")
    if chaotic and regular:
        return (f"So the paper's claim that the steady state is chaotic holds for {'; '.join(chaotic)} and not for "
                f"{'; '.join(regular)}, found regular{rest}.")
    if chaotic:
        return f"So the data support the paper's claim that the steady state is chaotic for {'; '.join(chaotic)}{rest}."
    return (f"So where a steady state is decided ({'; '.join(regular)}) it is regular, against the paper's claim "
            f"that it is chaotic{rest}.")


def paragraph(f: dict) -> str:
    """The finding in words, from :func:`facts`."""
    counts = _listed([f'{n} "{v}"' for v, n in f["counts"].items()])
    out = [_head(f), f"of the paper's {f['n_rows']} figures, claims and model items the ledger finds {counts}."]
    if f["reproduction"]:
        out.append(f"Its claims that the rotor's steady state is chaotic ({', '.join(CHAOS_CLAIMS)}: positive "
                   f"Lyapunov exponents, chaos down to eps = 1e-5, the route to chaos) read: "
                   f"{_by_verdict(f['chaos_claims']) or 'nothing, not in the ledger'}.")
        out.append(_faithful_sentence(f.get("faithful_claims", {})))
    out.append(_states_sentence(f))
    if f["reproduction"] and f.get("paper_orbit"):
        out.append(f["paper_orbit"])
    out.append(_conclusion(f) if f["reproduction"] else
               "None of this bears on the paper's claims: run at the paper's fidelity (config/config.yaml) for them.")
    return " ".join(out)
