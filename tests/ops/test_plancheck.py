"""Plan-time refusals of issue 40 (sleighsim.ops.plancheck through sleighsim.ops.configcheck.check):
each names the key."""

import re

import pytest
from test_config import SMOKE, refused, with_value

from sleighsim.ops.plancheck import check_state
from sleighsim.scenes.checks import SPIKE_BLOCK

CASES = [
    # labelled states: zero kinetic energy, nothing turning, overflowing energy
    (("scenes", "fig9_ref", "y0"), [0.0, 0.0, 0.0, 0.3], r"scenes\.fig9_ref\.y0 = .*Omega = omega = 0"),
    (("scenes", "psd_eps01", "y0"), [0.5, 0.0, 0.0, 0.0], r"scenes\.psd_eps01\.y0 = .*straight-line motion"),
    (("scenes", "fig9_ref", "y0"), [1e155, 0.1, 1.0, 0.0], r"scenes\.fig9_ref\.y0 = .*kinetic energy is non-finite"),
    (("scenes", "lyap_energy", "y0"), [0.0, 1e-170, 1e-170, 0.0],
     r"scenes\.lyap_energy\.y0 = .*kinetic energy is zero"),
    (("scenes", "chaos_verdict", "states", "rotor_a"), [0.0, 0.0, 0.0, 0.0],
     r"scenes\.chaos_verdict\.states\.rotor_a = .*Omega = omega = 0"),
    (("scenes", "basins", "references", "main"), [0.0, 0.0, 0.0, 1.0], r"scenes\.basins\.references\.main = "),
    # a sweep listing one eps twice
    (("scenes", "transients", "eps"), "dup", r"scenes\.transients\.eps = .* lists eps = .* more than once"),
    (("scenes", "hardcases", "small_eps"), "dup", r"scenes\.hardcases\.small_eps = .* more than once"),
    # horizons shorter than the blocks they are cut into
    (("scenes", "fig9_ref", "t_settle"), 60.0, r"scenes\.fig9_ref\.t_settle = 60.0 is shorter than the two blocks"),
    (("scenes", "fig7", "t_end"), 250.0, r"scenes\.fig7\.t_end = 250.0 must be at least t_sample_start \+ 100"),
    # a gauge over a whole window shorter than the data it vouches for
    (("scenes", "fig9_eps001", "gain"), {"T": 4.0, "tau": 1.0, "window": True},
     r"scenes\.fig9_eps001\.gain\.T = 4 is shorter than t_map = 5: a gauge over the window must cover"),
    (("scenes", "psd_eps001", "gain"), {"T": 40.0, "tau": 1.0, "window": True},
     r"scenes\.psd_eps001\.gain\.T = 40 is shorter than duration = 50"),
]


def _value(path, value):
    if value != "dup":
        return value
    node = SMOKE
    for k in path:
        node = node[k]
    return [*node, node[0]]


@pytest.mark.parametrize("path, value, message", CASES, ids=[".".join(map(str, c[0][1:])) for c in CASES])
def test_refused_at_plan_time_naming_the_key(path, value, message):
    out = refused(with_value(path, _value(path, value)))
    assert re.search(message, out), out


def test_the_smoke_config_passes_and_states_of_ordinary_size_rescale():
    from sleighsim.model.params import Params

    assert refused(SMOKE) == ""
    check_state("y0", [1e-3, 1e-3, 0.0, 0.0], "energy_label", 1e3, Params.paper(eps=0.1))


def test_spike_block_is_the_spike_rules_default_block():
    import inspect

    from sleighsim.engine.transient import spike_times

    assert inspect.signature(spike_times).parameters["block"].default == SPIKE_BLOCK


# Issue 55: every bad value refused at plan time naming its key.
HOSTILE = [
    (("scenes", "fig4", "spikes_after"), 10**400, r"^scenes\.fig4\.spikes_after = an integer of about 401 digits"),
    (("scenes", "fig4", "levels", 0, "states", 0), [0.0, 0.0, 0.0, 0.0],
     r"^scenes\.fig4\.levels\[0\]\.states\[0\] = .*Omega = omega = 0"),
    (("scenes", "fig4", "levels", 1, "states", 0), [1e200, 0.1, 1.0, 0.0],
     r"^scenes\.fig4\.levels\[1\]\.states\[0\] = .*kinetic energy is non-finite"),
]


@pytest.mark.parametrize("path, value, message", HOSTILE, ids=["400-digit spikes_after", "all-zero level state",
                                                               "overflowing level state"])
def test_hostile_values_are_refused_at_plan_time_naming_the_key(path, value, message):
    out = refused(with_value(path, value))
    assert re.search(message, out), out
