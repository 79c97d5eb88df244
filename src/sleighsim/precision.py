"""The arithmetics an integration can run in: one type, the lowest layer of the package (every
layer, io included, names an arithmetic by it), parsed once where a scene's config is read.

A :class:`Precision` is a string enum whose value is its config name ("double", "long double",
"double-double", "quad"), so a dataset attribute or coordinate written from it holds that name. Each
member carries its path tag, its machine epsilon (its Taylor tolerance when a run is to follow the
exact orbit as far as that arithmetic can), its rounding unit (half the epsilon), heyoka's
floating-point type and the NumPy dtype of its states. Double-double (pairs of doubles, about 106
bits) is not one of heyoka's types: only :mod:`sleighsim.engine.ddtaylor` integrates in it, so it has
no ``fp_type``; its states are (hi, lo) pairs of doubles.
"""

from __future__ import annotations

import enum

import numpy as np


class Precision(enum.StrEnum):
    """An arithmetic: ``tag`` (its name in paths), ``epsilon`` (machine epsilon), ``rounding``
    (unit roundoff), ``fp_type`` (heyoka's type: float, np.longdouble, heyoka.real128) and ``dtype``."""

    DOUBLE = ("double", "double", 2.0**-52, 2.0**-53)
    LONG_DOUBLE = ("long double", "long_double", 2.0**-63, 2.0**-64)  # 80-bit on x86-64
    DOUBLE_DOUBLE = ("double-double", "double_double", 2.0**-105, 2.0**-106)  # sleighsim.engine.ddtaylor
    QUAD = ("quad", "quad", 2.0**-112, 2.0**-113)  # heyoka's real128

    def __new__(cls, name: str, tag: str, epsilon: float, rounding: float):
        """A member: config ``name``, file ``tag``, machine ``epsilon`` and unit ``rounding`` (half of it)."""
        member = str.__new__(cls, name)
        member._value_ = name
        member.tag, member.epsilon, member.rounding = tag, epsilon, rounding
        return member

    def __repr__(self) -> str:
        """Its config name's repr: a config block holding a member reads (and Snakemake compares its
        params) exactly as written."""
        return repr(self.value)

    @classmethod
    def parse(cls, value) -> Precision:
        """The member named ``value`` (its config name, or a member); ValueError naming it otherwise."""
        for member in cls:
            if value is member or (isinstance(value, str) and value == member.value):
                return member
        raise ValueError(f"precision {value!r}: choose one of {[m.value for m in cls]}")

    @property
    def fp_type(self):
        """heyoka's floating-point type of this arithmetic (real128 needs heyoka, imported on use for
        start-up time); ValueError for double-double, which heyoka does not have."""
        if self is Precision.DOUBLE_DOUBLE:
            raise ValueError("double-double is not a heyoka type: it is integrated by sleighsim.engine.ddtaylor")
        if self is Precision.QUAD:
            import heyoka as hy

            return hy.real128
        return np.longdouble if self is Precision.LONG_DOUBLE else float

    @property
    def heyoka(self) -> bool:
        """Whether heyoka integrates in this arithmetic (double-double is sleighsim.engine.ddtaylor's)."""
        return self is not Precision.DOUBLE_DOUBLE

    @property
    def dtype(self) -> np.dtype:
        """The NumPy dtype of states in this arithmetic (double-double: of each of the pair's doubles)."""
        return np.dtype(float) if self is Precision.DOUBLE_DOUBLE else np.dtype(self.fp_type)


def parsed(block):
    """A copy of a config block (nested dicts and lists) with every arithmetic it names parsed into a
    :class:`Precision`: the value of a key ``precision``, the items of ``precisions`` and the keys of
    ``tols``. ValueError naming the value when one is not an arithmetic."""
    if isinstance(block, list):
        return [parsed(v) for v in block]
    if not isinstance(block, dict):
        return block
    out = {}
    for key, value in block.items():
        if key == "precision":
            value = Precision.parse(value)
        elif key == "precisions":
            value = [Precision.parse(p) for p in value]
        elif key == "tols" and isinstance(value, dict):
            value = {Precision.parse(p): v for p, v in value.items()}
        out[key] = parsed(value)
    return out
