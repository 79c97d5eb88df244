# ruff: noqa: D100 (a notebook: its first cell, the markdown below, says what it is)
# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # sleighsim as a library: one state of your own, from the model to the chaos verdict
#
# This tutorial calls the functions the workflow's jobs call (no copies): the model and its energy,
# one orbit in double and in long double from one settled point with their separation, the spike
# times, the faithfulness gauge (does an arithmetic follow the exact orbit?) and, in one call, the
# chaos verdict with its reasons and what would decide it. Run it as a script from the repository's
# root (`python docs/tutorial.py`) or open it as a notebook (`jupytext --to notebook docs/tutorial.py`;
# jupytext is not a dependency).
#
# The horizons are the workflow's own: the blocks `precision_ladder` and `chaos_verdict` of
# `config/config.yaml` (the paper's fidelity). Set `SLEIGHSIM_TUTORIAL_OVERLAY=config/smoke.yaml` to
# merge the smoke overlay onto it, as `snakemake --configfile` does: the same code on tiny horizons
# (the test suite runs it so, tests/test_tutorial.py, which states its run time). Figures are
# written to `SLEIGHSIM_TUTORIAL_OUT` (default `results/tutorial/`, beside a run's results; git ignores both).

# %%
import logging
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import sleighsim
from sleighsim.analysis.observables import gauge
from sleighsim.engine.transient import settle, spike_train
from sleighsim.ops.config import REPO, merged_config
from sleighsim.ops.judge import answer, judge_state
from sleighsim.precision import Precision
from sleighsim.scenes import ladder
from sleighsim.scenes.catalog import scene_config

overlay = os.environ.get("SLEIGHSIM_TUTORIAL_OVERLAY")
config = merged_config([REPO / overlay] if overlay else [])
out = Path(os.environ.get("SLEIGHSIM_TUTORIAL_OUT", "results/tutorial"))
out.mkdir(parents=True, exist_ok=True)
ladder_block = {**scene_config(config, "precision_ladder"), "precisions": ["double", "long double"]}
verdict_block = scene_config(config, "chaos_verdict")
print("horizons from", "config/config.yaml" + (f" + {overlay}" if overlay else ""))

# %% [markdown]
# ## The model and its energy
#
# `Params.paper` takes the paper's form (eps = m_r/m = a/b, K2 = 1 + I_c/(m b^2)); the equations are
# derived from the mechanics with SymPy (`sleighsim.derive`, once per process). A state is
# (u, Omega, omega, delta): the sleigh's forward speed, its turning rate, the rotor's rate and angle.
# The energy is conserved exactly; the paper labels a state by its energy, and the time-scaling
# symmetry moves a state to any label (`state_at_label`).

# %%
params = sleighsim.Params.from_config(verdict_block["params"])
label = verdict_block["energy_label"]
mine = [0.0, 0.05, 1.0, 1.0]  # a start state of our own: sleigh nearly at rest, the rotor spinning
y0 = sleighsim.state_at_label(mine, params, label)
print(params)
print("start state at label", label, ":", y0)
print("energy", float(sleighsim.energy(y0, params)), "label", float(sleighsim.energy_label(y0, params)))
print("vector field there:", sleighsim.rhs(y0, params))

# %% [markdown]
# ## One orbit in double and in long double
#
# The precision ladder's steps (`sleighsim.scenes.ladder`): settle the transient in double
# (`sleighsim.engine.transient.settle`, which judges when omega's block means have settled), then run
# the orbit from that one settled point in each arithmetic, each at its own machine epsilon as
# tolerance (`ladder.run_in`), and measure how far apart they drift (`ladder.separation`: max
# |velocity difference| over max |velocity|).

# %%
settled, pre = settle(params, y0, ladder_block["t_transient"], **ladder_block["transient"],
                      tol=Precision.DOUBLE.epsilon, label="tutorial")
print("transient over:", bool(pre["transient_over"]), "| settling time", pre["transient_settling_time"])
runs = {p: ladder.run_in(params, settled, Precision.parse(p), T=ladder_block["T"], dt=ladder_block["dt"],
                         spike_factor=ladder_block["transient"]["spike_factor"]) for p in ladder_block["precisions"]}
double, long_double = runs["double"], runs["long double"]
separation = ladder.separation(double, long_double)
t = ladder_block["dt"] * np.arange(1, separation.size + 1)
for name, run in runs.items():
    print(f"{name}: max relative energy drift {run['energy_max_rel_drift']:.2g}, wall {run['wall_s']:.3g} s")
print("largest separation", separation.max(), "at t =", t[np.argmax(separation)])

fig, (ax_sep, ax_spikes) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
ax_sep.semilogy(t, np.maximum(separation, 1e-18))
ax_sep.set_ylabel("separation double / long double")
for name, run in runs.items():  # the spike trains (next section): each interval at the spike that ends it
    ax_spikes.plot(run["spikes"][1:], np.diff(run["spikes"]), "o", mfc="none", label=name)
ax_spikes.set_xlabel("time after the settled point")
ax_spikes.set_ylabel("interval between Omega spikes")
ax_spikes.legend()
fig.savefig(out / "tutorial-separation.png", dpi=100)

# %% [markdown]
# ## Spike times
#
# In the steady state Omega spikes at nearly regular intervals (`sleighsim.engine.transient.spike_train`,
# which `spike_times` and the ladder call): isolated block maxima of |Omega| above 1.8 times the typical
# one; then the period's check: a gap of about two median intervals is searched for a low spike the fixed
# threshold missed (one median interval after the previous spike, standing above the gap's envelope), and
# an interval still near twice the median is flagged. Each arithmetic's spike train:

# %%
for name, run in runs.items():
    train = spike_train(t, run["velocities"][:, 1], factor=ladder_block["transient"]["spike_factor"])
    print(f"{name}: {train.times.size} spikes at {np.round(train.times, 1)}; "
          f"mean interval {run['interval_mean']:.6g} +- {run['interval_sd']:.2g}; threshold {train.threshold:.3g}; "
          f"found below it by the period's check: {np.round(train.times[train.rescued], 1)} "
          f"(peaks {np.round(train.heights[train.rescued], 4)}); intervals flagged: {train.doubled.size}")
print("the lowest precision whose spike statistics agree with every finer one (ladder.AGREES_RULE):",
      ladder.converged_precision(list(runs.values()), list(runs), ladder_block["dt"]))

# %% [markdown]
# ## The faithfulness gauge
#
# Over each spike cycle the flow amplifies an error by up to G (the largest singular value of the
# cycle's tangent map). An arithmetic of unit roundoff r follows the exact orbit only where
# G r < 1e-3 (`sleighsim.chaos.faithfulness`). This asks more than the spike statistics above: two
# arithmetics may agree on the mean interval within its spread and still follow different orbits (the
# separation above); the gauge says whether an arithmetic follows the orbit itself. The verdict's own
# gauge, on our settled point:

# %%
faith = gauge(verdict_block["params"], settled,
              T=verdict_block["T_gain"], tau=verdict_block["tau_gain"],
              spike_factor=verdict_block["transient"]["spike_factor"], tol=verdict_block["tol"])
print("ln G per complete spike cycle:", np.round(faith["ln_gain"], 2))
for p in Precision:
    print(f"{p.value}: log10(G r) = {faith['log10_gain_rounding'][p]:.3g}: {faith['follows'][p]}")

# %% [markdown]
# ## The chaos verdict, with its reasons, in one call
#
# `sleighsim.ops.judge.judge_state` is the workflow's chaos verdict for one start state of your own
# (on the command line: `sleighsim judge`), its settings the `chaos_verdict` block's. It runs the
# workflow's jobs for that state in order: the first stage settles the orbit and computes independent
# indicators (Benettin over replicas, finite-time exponents, MEGNO, two nearby orbits, the Loschmidt
# return error, frequency analysis), each gated by the gauge above; the decisive stage runs the orbit
# again in an arithmetic that follows it (double-double) over its horizon and judges it with the
# indicators the judge-power audit lets vote there (`benchmarks/judge_power.yaml`,
# `sleighsim.chaos.power.stage_vote`), combined by `sleighsim.chaos.rule`. Realizations from start
# states perturbed at the rounding level must agree: the workflow runs `n_chunks` of them, this
# tutorial one (`realizations=None` runs the block's). Its progress goes to the log, one line per job.
# `answer` words the verdict as the report does and, for a state left undecided, says what would
# decide it and at what measured cost.

# %%
logging.basicConfig(level=logging.INFO, format="%(asctime)s %(message)s", datefmt="%H:%M:%S")
judged = judge_state(verdict_block["params"], y0, realizations=1, configfiles=[REPO / overlay] if overlay else [])
verdict_of_mine = answer(judged)
print("verdict:", verdict_of_mine.verdict, "| class:", verdict_of_mine.klass)
print("decided in:", verdict_of_mine.arithmetic)
print("decided by:", verdict_of_mine.decided_by or "no judge")
print("why:", verdict_of_mine.why)
if verdict_of_mine.to_decide:
    print("to decide it:", verdict_of_mine.to_decide)
