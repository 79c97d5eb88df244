"""What a "regular" verdict bounds: the largest exponent lambda_1 its tangent-based judges leave room for
over the horizon they ran, and whether a judge that uses the torus' own structure confirmed it.

From the numbers a judge's verdict rests on (``chaos.decisive``'s "numbers", as the records keep them):

* MEGNO (``megno_log_norm``): <Y>(t) grows like lambda t / 2 on a chaotic orbit, so <Y> + sigma resid below
  y_regular_max at T bounds lambda_1 by 2 (<Y> + sigma resid) / T.
* The return map's MEGNO (``section_megno``): the same per return, over N returns of mean length P:
  lambda_1 <= 2 (<Y> + sigma resid) / (N P).

The tightest bound of the tangent-based judges that said regular is the verdict's. Torus-specific judges
(``TORUS_JUDGES``: the weighted Birkhoff averages, the frequency analysis) bound no exponent: they
confirm the quasi-periodic structure. Exponents in 1/time, times in the flow's unit.
"""

from __future__ import annotations

import math

from sleighsim.chaos.verdicts import REGULAR

TORUS_JUDGES = ("birkhoff", "frequency_orbit")
#: The text a dataset keeps for the rule.
BOUND_RULE = ("a regular verdict bounds lambda_1 by the tightest of its tangent-based regular judges: MEGNO "
              "2 (<Y> + sigma resid) / T, the return map's MEGNO 2 (<Y> + sigma resid) / (N P); a torus-specific "
              "judge (weighted Birkhoff averages, frequency analysis) confirms it or not")


def exponent_bound(name: str, numbers: dict, sigma: float) -> tuple[float, float]:
    """(the largest lambda_1 a regular verdict of judge ``name`` leaves room for, the horizon it ran) from
    its numbers; (NaN, NaN) for a judge that bounds no exponent."""
    y = numbers.get("Y_mean", math.nan) + sigma * numbers.get("Y_resid", math.nan)
    if name == "megno_log_norm":
        T = float(numbers["T"])
        return 2.0 * y / T, T
    if name == "section_megno":
        T = float(numbers["returns"]) * float(numbers["mean_return"])
        return 2.0 * y / T, T
    return math.nan, math.nan


def regular_bound(judged: dict, sigma: float) -> dict:
    """What a regular verdict rests on. ``judged``: name -> {"verdict": (verdict, reason), "numbers": ...}
    (the judges that vote, after the gates). Returns lambda_max and T (NaN when no tangent-based judge says
    regular), by (the judge giving the bound), torus (the torus-specific judges that said regular) and
    text."""
    bounds = [(*exponent_bound(k, j["numbers"], sigma), k) for k, j in judged.items() if j["verdict"][0] == REGULAR]
    bounds = [b for b in bounds if math.isfinite(b[0])]
    torus = sorted(k for k, j in judged.items() if k in TORUS_JUDGES and j["verdict"][0] == REGULAR)
    confirm = (f"confirmed by a torus-specific judge ({', '.join(torus)})" if torus
               else "not confirmed by a torus-specific judge")
    if not bounds:
        return {"lambda_max": math.nan, "T": math.nan, "by": "", "torus": torus,
                "text": f"no tangent-based judge bounds lambda_1; {confirm}"}
    lam, T, by = min(bounds)
    return {"lambda_max": lam, "T": T, "by": by, "torus": torus,
            "text": f"lambda_1 <= {lam:.2g} over T = {T:.3g} ({by}); {confirm}"}
