"""What each dataset sleighsim writes is, in words: the heart of its CF ``title``
(:func:`sleighsim.io.cf.title`)."""

#: What each dataset is, by the name of its file: every scene of the configs that makes a dataset,
#: the claims ledger and the verdict stability table.
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
    "judge_power": "the chaos judges' power and false rates on orbits of known class (sticky chaos, slow-fast tori, "
                   "textbook orbits) and the judges that vote",
    "trigger_law": "the first spike against the size of the injected error (tolerance and arithmetic) (claim C04)",
    "precision_ladder": "spike times per arithmetic from one settled point and the orbits' separation",
    "main_drift": "the main state's slow drift: spike interval and lambda_1 per window of one long run",
    "basins": "basin fractions of the steady states on one energy level (claim C06 made quantitative)",
    "torus_stability": "what the steady state is: orbits started near the main torus in double-double, each on its "
                       "torus, a neighbouring one, or gone (issue 39 item 4, claim C06)",
    "audit": "the model as printed: energy drift of the printed udot, and the paper's other slips (D1-D6)",
    "k2_sweep": "the observables the unstated K bears on, against K2 (likely causes of C04, C05, C09-C11, C13, "
                "C23)",
    "integration_error": "SciPy's RK45 (standing in for MATLAB's ode45) against its tolerance: spikes, series "
                         "error and the paper's Lyapunov protocol (likely causes of C04, C05, C11, C18-C21)",
    "paper_setup": "the paper's unstated setup (K2, integrator, psd convention, energy normalisation, Lyapunov "
                   "integration) inferred jointly from all its numbers, from the cause datasets",
    "hardcases": "hard cases of the integrator: extreme parameters, energies and horizons, states at rest and on "
                 "a section",
    "bench": "speed against error: heyoka, SciPy and peer engines",
    "claims": "the claims ledger: every claim of the paper judged from the datasets (paper/CLAIMS.md)",
    "stability/verdicts": "verdict stability: the ledger's verdicts with perturbed start states and at a looser "
                          "tolerance",
}
