"""Is an orbit chaotic? Chaos indicators, their judges and the decision rule, in one place.

Import from the submodules (nothing is re-exported here):

* ``tangent``: tangent-based indicators: finite-time exponents (``finite_time_exponents``,
  ``judge_ftle``), the replicas' Benettin lambda_1 (``judge_benettin``) and the long-double
  precision check (``growth_confirmed``).
* ``megno``: MEGNO (``megno`` on ``engine.integrators.megno_integrator``, ``megno_rate``,
  ``judge_megno``, ``judge_megno_run``, ``megno_in_long_double``).
* ``benettin``: Lyapunov exponents by Benettin's method (``benettin``, ``batch_benettin``,
  ``replica_exponents``, ``scipy_benettin``, ``mean_divergence``); ``zero_one``: the 0-1 test
  (``zero_one_test``).
* indicators without tangent dynamics built on pairs of orbits: ``two_trajectory``, two nearby
  trajectories (``two_trajectory``, ``judge_two_trajectory``, ``d0_independent``,
  ``two_trajectory_indicator``), and ``loschmidt``, the Loschmidt return error (``loschmidt``,
  ``loschmidt_fit``, ``judge_loschmidt``, ``judge_loschmidt_run``, ``loschmidt_indicator``,
  ``LOSCHMIDT_GAIN_ROUNDING_MAX``).
* ``frequency``: frequency analysis without tangent dynamics: the analysis (``leading_frequency``,
  ``window_frequencies``, ``drift``), on an orbit (``frequency_drift``) and its judge
  (``judge_frequency``, ``frequency_log_ratio``, ``judged_run``).
* ``faithfulness``: the faithfulness gauge: how much one spike cycle amplifies rounding
  (``spike_cycle_gains``, ``cycle_gains``; over a whole window without a cycle, ``window_gains``), the
  rounding it injects (``injected_rounding``) and whether an
  arithmetic follows the orbit (``follows``, ``FAITHFUL_MAX``).
* ``indicators``: the registry of indicators (stage, tangent-based or not, estimator, settings, judged);
  ``decisive``: the decisive stage's estimators on one sampled orbit; ``decision``: the sequence gauge,
  vote, decide, consistency, realizations; ``bounds``: what a regular verdict bounds.
* ``power``: the judges' rates, their Clopper-Pearson bounds and the vote by a record (``stage_vote``);
  ``known_orbits``, ``audit_orbits``, ``power_audit``: the judge-power audit's systems, its independent
  confirmed realizations and its runs.
* ``rule``: the decision rule (``DECISION_RULE``, ``decide``, ``consistent``, ``precision_gate``,
  ``faithful_gate``), the indicator names (``INDICATORS``, ``TANGENT_BASED``), the state's class
  (``classify``) and the realizations' agreement (``agree``).
* ``verdicts``: the verdicts (``CHAOTIC``, ``REGULAR``, ``UNDECIDED``) and the judges' shared helpers
  (``polynomial_rate_bound``); ``common``: argument checks and ``linfit``; ``propagate``: the
  engines' propagation legs and their conventions.

Times are in the flow's own time unit, exponents in 1/time, logs natural. The sleigh's chaos
verdict (``scenes.verdict``) runs the integrations and assembles the dataset.
"""
