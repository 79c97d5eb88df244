"""Physical parameters of the sleigh and the paper's (eps, b, K2) form (docs/model.md: m = 1).

Physical: sleigh mass m_c, rotor mass m_r, inertias I_c (sleigh, about C) and I_r
(rotor), rotor offset a [length] and runner distance b [length]. The paper's form:
m_r / m = a / b = eps, m = 1, I_c = (K2 - 1) b^2, I_r = eps^3 b^2 (K2 - 1 + eps).
"""

from __future__ import annotations

import math
import operator
from dataclasses import dataclass, field

PARAM_NAMES = ("m_c", "m_r", "I_c", "I_r", "a", "b")
#: The keys of the paper form (a config's parameter block holds one form's keys only).
PAPER_NAMES = ("eps", "b", "K2")


def finite(name, value) -> float:
    """``value`` as a float; TypeError naming ``name`` when it is not a real number (a string, a
    bool, None, a sequence), ValueError when it is NaN or infinite."""
    try:
        if isinstance(value, (str, bytes, bool)):
            raise TypeError
        value = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} = {value!r} must be a real number") from None
    if not math.isfinite(value):
        raise ValueError(f"{name} = {value} is not a finite number")
    return value


def integer(name, value, lo: int, hi: int) -> int:
    """``value`` as an int in [``lo``, ``hi``]; TypeError naming ``name`` when it is not an integer (a
    float, a bool, a string), ValueError when it is out of that range."""
    if isinstance(value, bool):
        raise TypeError(f"{name} = {value!r} must be an integer")
    try:
        value = operator.index(value)
    except TypeError:
        raise TypeError(f"{name} = {value!r} must be an integer") from None
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {value} is outside the admissible range [{lo}, {hi}]")
    return value


def largest(values: dict) -> str:
    """``name = value`` of the entry of ``values`` largest in magnitude (the one to blame for an overflow)."""
    name = max(values, key=lambda k: abs(values[k]))
    return f"{name} = {values[name]:g}"


def positive(name, value) -> float:
    """``value`` as a float; ValueError naming ``name`` when it is not a number, not finite or not
    above 0 (the engines' and the chaos indicators' argument check)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be positive and finite, got {value!r}")
    return v


@dataclass(frozen=True)
class Params:
    """Physical parameters: masses m_c, m_r, inertias I_c (about C), I_r (rotor),
    rotor offset a and runner distance b. The constructor checks them as :meth:`physical` says
    (``formal=True`` admits m_c <= 0 with m_c + m_r > 0: the formal system of :meth:`paper`).
    Build with :meth:`physical` or :meth:`paper`."""

    m_c: float
    m_r: float
    I_c: float
    I_r: float
    a: float
    b: float
    formal: bool = field(default=False, kw_only=True, repr=False, compare=False)

    def __post_init__(self):
        """Every parameter a finite float in its range, the inertia positive definite (ValueError or
        TypeError naming the parameter)."""
        for k in PARAM_NAMES:
            object.__setattr__(self, k, finite(k, getattr(self, k)))
        for k in ("b",) if self.formal else ("m_c", "b"):
            if getattr(self, k) <= 0:
                raise ValueError(f"{k} = {getattr(self, k)} is outside the admissible range (0, inf)")
        for k in ("m_r", "I_c", "I_r", "a"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)} is outside the admissible range [0, inf)")
        if self.m <= 0:
            raise ValueError(f"m_c = {self.m_c} is outside the admissible range (-m_r, inf): the total mass "
                             "m_c + m_r must be positive")
        self._check_positive_definite()

    @classmethod
    def physical(cls, *, m_c, m_r, I_c, I_r, a, b) -> Params:
        """The physical form: masses m_c > 0, m_r >= 0 [mass], inertias I_c, I_r >= 0 [mass length^2],
        offset a >= 0 and runner distance b > 0 [length]; ValueError when one is out of range or the
        inertia matrix is not positive definite."""
        return cls(m_c=m_c, m_r=m_r, I_c=I_c, I_r=I_r, a=a, b=b)

    @classmethod
    def paper(cls, *, eps, b=1.0, K2=None, formal: bool = False) -> Params:
        """The paper's form: m_r/m = a/b = eps, m = 1, K2 = 1 + I_c/(m b^2) (default 1 + eps).

        ``formal=True`` admits eps >= 1, the formal system with a negative sleigh
        mass m_c = 1 - eps (not a mechanical system; the inertia stays positive definite)."""
        eps = finite("eps", eps)
        b = finite("b", b)
        K2 = 1.0 + eps if K2 is None else finite("K2", K2)
        if not (0.0 < eps < 1.0 or (formal and eps >= 1.0)):
            why = ("eps = m_r/m must be positive" if eps <= 0 else
                   "eps = m_r/m, and eps >= 1 makes m_c <= 0; pass formal=True for the formal system")
            raise ValueError(f"eps = {eps} is outside the admissible range (0, 1): {why}")
        if b <= 0:
            raise ValueError(f"b = {b} is outside the admissible range (0, inf)")
        if K2 <= 1:
            raise ValueError(f"K2 = {K2} is outside the admissible range (1, inf): K2 = 1 + I_c/(m b^2)")
        form = dict(m_c=1.0 - eps, m_r=eps, I_c=(K2 - 1.0) * b * b, I_r=eps * eps * eps * b * b * (K2 - 1.0 + eps),
                    a=eps * b, b=b)
        if not all(map(math.isfinite, form.values())):
            raise ValueError(f"{largest(dict(eps=eps, b=b, K2=K2))} is too large: the physical parameters overflow "
                             "double precision")
        return cls(**form, formal=eps >= 1.0)

    @classmethod
    def sleigh0(cls, *, b=1.0, K2=1.1) -> Params:
        """The rotor-free sleigh (eps = 0) inside the full model: the rotor is massless,
        centred (a = 0) and decoupled (it spins at constant omega)."""
        return cls.physical(m_c=1.0, m_r=0.0, I_c=(K2 - 1.0) * b**2, I_r=1.0, a=0.0, b=b)

    @classmethod
    def from_config(cls, cfg: dict) -> Params:
        """From a config block: either the paper form {eps, b, K2} or the physical form {m_c, m_r,
        I_c, I_r, a, b}, one form only; the physical form's rotor mass m_r > 0 (eps > 0, as the paper
        form requires: the rotor-free sleigh is :meth:`sleigh0`)."""
        form, names = ("paper", PAPER_NAMES) if "eps" in cfg else ("physical", PARAM_NAMES)
        other = [k for k in cfg if k not in names]
        if other:
            raise ValueError(f"{other[0]} is not a key of the {form} form {names}; give one form only")
        if form == "paper":
            return cls.paper(eps=cfg["eps"], b=cfg.get("b", 1.0), K2=cfg.get("K2"))
        missing = [k for k in PARAM_NAMES if k not in cfg]
        if missing:
            raise ValueError(f"parameter block needs eps (paper form) or all of {PARAM_NAMES}; missing {missing}")
        if finite("m_r", cfg["m_r"]) <= 0:
            raise ValueError(f"m_r = {cfg['m_r']} is outside the admissible range (0, inf): eps = m_r / m must be "
                             "positive (the rotor-free sleigh is the sleigh0 kind)")
        return cls.physical(**{k: cfg[k] for k in PARAM_NAMES})

    def _check_positive_definite(self):
        # det M(delta) is linear in cos^2(delta): check both ends.
        m = self.m
        J = self.I_c + m * self.b * self.b
        R = self.I_r + self.m_r * self.a * self.a
        c = self.m_r * self.a
        det_min = min(m * J * R - m * (c * self.b) * (c * self.b), m * J * R - J * c * c)
        if not math.isfinite(m * J * R):
            raise ValueError(f"{largest(dict(zip(PARAM_NAMES, self.values)))} is too large: the inertia matrix "
                             "overflows double precision")
        if not det_min > 1e-14 * m * J * max(R, 1e-300):
            raise ValueError(
                f"inertia is not positive definite (min det M = {det_min:.3g}): "
                "I_r + m_r a^2 must exceed the rotor coupling; increase I_r or reduce m_r a"
            )

    @property
    def m(self) -> float:
        """The total mass m_c + m_r."""
        return self.m_c + self.m_r

    @property
    def eps(self) -> float:
        """m_r / m (the paper's small parameter)."""
        return self.m_r / self.m

    @property
    def K2(self) -> float:
        """1 + I_c / (m b^2), the paper's K^2 (with its typo I_r -> I_c corrected)."""
        return 1.0 + self.I_c / (self.m * self.b**2)

    @property
    def is_paper_form(self) -> bool:
        """True when (m = 1, a = eps b, I_r = eps^3 b^2 (K2 - 1 + eps)) hold, so eps, b, K2 describe it exactly."""
        e, b, K2 = self.eps, self.b, self.K2
        return (
            math.isclose(self.m, 1.0, rel_tol=1e-12)
            and math.isclose(self.a, e * b, rel_tol=1e-12, abs_tol=1e-300)
            and math.isclose(self.I_r, e**3 * b**2 * (K2 - 1 + e), rel_tol=1e-12, abs_tol=1e-300)
        )

    @property
    def values(self) -> tuple:
        """The physical parameters in PARAM_NAMES order (m_c, m_r, I_c, I_r, a, b)."""
        return tuple(getattr(self, k) for k in PARAM_NAMES)

    def attrs(self) -> dict:
        """Flat netCDF-friendly attributes: physical and paper form."""
        out = {f"param_{k}": v for k, v in zip(PARAM_NAMES, self.values)}
        out.update(param_eps=self.eps, param_K2=self.K2, param_is_paper_form=int(self.is_paper_form))
        return out
