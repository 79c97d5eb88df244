"""Plan-time checks of scene blocks whose failure would otherwise surface only inside a job:

- a labelled start state (a block's ``energy_label`` or ``reference_label`` with its ``y0``,
  ``states`` or ``references``) has finite, non-zero kinetic energy that does not overflow, and
  something that turns (Omega = omega = 0 is a straight-line motion, an equilibrium: no spikes);
- the eps values a sweep lists (a key ``eps`` or ``*_eps`` holding a list) are distinct;
- a pre-run judged by the transient rules (sleighsim.engine.transient.settle) holds two of the
  spike rule's blocks (sleighsim.scenes.checks.SPIKE_BLOCK time units each);
- a ladder's gauge over a whole window (``gain.window``) covers the window its data span;
- every integer of the config is at most :data:`MAX_INT` in magnitude (a 400-digit count overflowed
  the float conversions of the checks), and the states of each energy level (``levels``) rescale
  to its label as labelled start states do.

Each error (:class:`sleighsim.scenes.checks.ConfigError`) names the key.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.model.params import Params
from sleighsim.model.symmetries import energy_label
from sleighsim.scenes.catalog import KINDS
from sleighsim.scenes.checks import SPIKE_BLOCK, ConfigError

#: Keys of a block holding the label its start states are rescaled to.
LABEL_KEYS = ("energy_label", "reference_label")
#: Keys of a block holding start states: one state, or a list or mapping of states.
STATE_KEYS = ("y0", "states", "references")
#: The largest integer magnitude a config may hold (every integer below it is exact as a float).
MAX_INT = 2**53


def _states(cfg: dict):
    """(dotted key, state) of every start state of a block."""
    for key in STATE_KEYS:
        value = cfg.get(key)
        if isinstance(value, dict):
            yield from ((f"{key}.{k}", v) for k, v in value.items())
        elif isinstance(value, list) and value and isinstance(value[0], list):
            yield from ((f"{key}[{i}]", v) for i, v in enumerate(value))
        elif isinstance(value, list):
            yield key, value


def _params(cfg: dict) -> Params:
    """The block's parameters, else the paper's at eps = 0.1 (the reference state's)."""
    return Params.from_config(cfg["params"]) if isinstance(cfg.get("params"), dict) else Params.paper(eps=0.1)


def check_state(where: str, y, label_key: str, label: float, params: Params) -> None:
    """The state ``y`` at ``where`` can be rescaled to ``label``: finite, non-zero kinetic energy
    that does not overflow, a rescaled state that neither overflows nor vanishes, and Omega or omega
    non-zero."""
    y = np.asarray(y, dtype=float)
    if y.shape[-1] < 4 or not np.all(np.isfinite(y[:4])):
        return  # the schema and the kind's own checks report these
    if y[1] == 0 and y[2] == 0:
        raise ConfigError(f"{where} = {y.tolist()}: Omega = omega = 0 is a straight-line motion (an equilibrium), "
                          f"nothing to rescale to {label_key} = {label}")
    with np.errstate(all="ignore"):
        current = float(energy_label(y[:4], params))
        scaled = y[:3] * math.sqrt(label / current) if math.isfinite(current) and current > 0 else None
    if scaled is None:
        what = "zero" if current == 0 else "non-finite (it overflows)"
        raise ConfigError(f"{where} = {y.tolist()}: its kinetic energy is {what}; cannot rescale it to "
                          f"{label_key} = {label}")
    if not np.all(np.isfinite(scaled)) or not np.any(scaled):
        fault = "overflow" if not np.all(np.isfinite(scaled)) else "vanish"
        raise ConfigError(f"{where} = {y.tolist()}: rescaled to {label_key} = {label} its velocities {fault}; "
                          "use a state of ordinary size")


def check_labelled_states(w: str, cfg: dict) -> None:
    """Every start state of the block ``w`` (``scenes.<name>``) with a positive label, and every
    state of each of its energy ``levels`` (a list of {label, states}) (:func:`check_state`)."""
    labels = [(k, cfg[k]) for k in LABEL_KEYS if isinstance(cfg.get(k), (int, float)) and cfg[k] > 0]
    levels = cfg.get("levels") if isinstance(cfg.get("levels"), list) else []
    if not labels and not levels:
        return
    try:
        params = _params(cfg)
    except (TypeError, ValueError):
        return  # the params check names the key
    for key, y in _states(cfg):
        for label_key, label in labels:
            check_state(f"{w}.{key}", y, label_key, float(label), params)
    for i, level in enumerate(levels):
        label = level.get("label") if isinstance(level, dict) else None
        if isinstance(label, (int, float)) and not isinstance(label, bool) and label > 0:
            for key, y in _states(level):
                check_state(f"{w}.levels[{i}].{key}", y, f"{w}.levels[{i}].label", float(label), params)


def check_magnitudes(node, path: str = "") -> None:
    """Every integer in the config ``node`` at most :data:`MAX_INT` in magnitude, naming its key."""
    if isinstance(node, dict):
        for k, v in node.items():
            check_magnitudes(v, f"{path}.{k}" if path else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            check_magnitudes(v, f"{path}[{i}]")
    elif isinstance(node, int) and not isinstance(node, bool) and abs(node) > MAX_INT:
        digits = int(node.bit_length() * math.log10(2)) + 1  # str() of a huge int is itself refused (4300 digits)
        raise ConfigError(f"{path} = an integer of about {digits} digits: larger than any this config can use (at "
                          f"most 2**53 = {MAX_INT})")


def check_distinct_eps(w: str, node, path: str = "") -> None:
    """No list under a key ``eps`` or ``*_eps`` in the block ``w`` repeats a value (a sweep would
    fit a slope through the same point twice)."""
    if isinstance(node, dict):
        for k, v in node.items():
            key = f"{path}.{k}" if path else str(k)
            if (k == "eps" or str(k).endswith("_eps")) and isinstance(v, list):
                seen = [x for i, x in enumerate(v) if x in v[:i]]
                if seen:
                    raise ConfigError(f"{w}.{key} = {v} lists eps = {seen[0]} more than once; list each eps once")
            check_distinct_eps(w, v, key)


def check_pre_run(w: str, cfg: dict) -> None:
    """A pre-run judged by the transient rules (the kind's ``pre_run`` key, with a ``transient``
    block) holds two spike-rule blocks of ``SPIKE_BLOCK`` time units."""
    key = KINDS[cfg["kind"]].pre_run
    length = cfg.get(key, 0) if key and "transient" in cfg else 0
    if 0 < length < 2 * SPIKE_BLOCK:
        raise ConfigError(f"{w}.{key} = {length} is shorter than the two blocks of {SPIKE_BLOCK:g} time units the "
                          f"transient check cuts it into; make it at least {2 * SPIKE_BLOCK:g}")


#: The keys of a block giving the spans its data cover from the settled point.
DATA_SPANS = ("t_map", "attractor_span", "duration")


def check_window_gain(w: str, cfg: dict) -> None:
    """A gauge over a whole window (``gain.window``) bounds the error only within [0, T]: T must cover every
    span the block's data cover from the settled point (:data:`DATA_SPANS`)."""
    gain = cfg.get("gain", {})
    spans = {k: cfg[k] for k in DATA_SPANS if k in cfg}
    if gain.get("window") and spans and gain["T"] < max(spans.values()):
        key = max(spans, key=spans.get)
        raise ConfigError(f"{w}.gain.T = {gain['T']:g} is shorter than {key} = {spans[key]:g}: a gauge over the "
                          f"window must cover every span the data cover")
