"""Which datasets each claim of paper/CLAIMS.md is judged from (:data:`EVIDENCE`, read by its judge in
:mod:`sleighsim.claims.judges`) and which its likely causes are tested against (:data:`CAUSES`, read
by :mod:`sleighsim.claims.causes`)."""

from __future__ import annotations

#: The datasets each claim is judged from, in the order its judge takes them.
EVIDENCE: dict[str, tuple[str, ...]] = {
    "C01": ("fig2",),
    "C03": ("fig3",),
    "C04": ("fig3", "transients"),
    "C05": ("fig3",),
    "C06": ("fig4", "torus_stability"),
    "C07": ("fig6",),
    "C08": ("fig6",),
    "C09": ("fig6",),
    "C10": ("fig6",),
    "C11": ("fig5",),
    "C12": ("pert_audit",),
    "C13": ("fig7",),
    "C14": ("fig8",),
    "C15": ("fig9_ref",),
    "C16": ("fig9_ref",),
    "C17": ("fig9_ref", "fig9_highE", "fig9_eps001", "fig9_scaling"),
    "C18": ("lyap_spectrum",),
    "C19": ("lyap_protocol", "lyap_spectrum"),
    "C20": ("lyap_energy",),
    "C21": ("fig11_grid",),
    "C22": ("fig9_ref",),
    "C23": ("psd_eps01",),
    "C24": ("psd_eps001",),
    "C25": ("lyap_feasibility",),
    "C26": ("formal_exponents",),
    "C27": ("fig11_grid",),
    "D1": ("audit",),
    "D2": ("audit",),
    "D3": ("audit",),
    "D4": ("audit",),
    "D5": ("audit",),
    "D6": ("audit",),
}

#: The datasets each "differs" of a claim is tested against for its likely causes
#: (sleighsim.claims.causes), in the order its cause test takes them.
CAUSES: dict[str, tuple[str, ...]] = {
    "C04": ("k2_sweep", "integration_error", "audit", "trigger_law"),
    "C05": ("k2_sweep", "integration_error", "audit"),
    "C06": ("torus_stability", "fig4"),
    "C09": ("k2_sweep",),
    "C10": ("k2_sweep",),
    "C11": ("k2_sweep", "integration_error"),
    "C13": ("k2_sweep",),
    "C18": ("integration_error",),
    "C19": ("integration_error",),
    "C20": ("integration_error",),
    "C21": ("integration_error",),
    "C22": ("fig9_ref",),
    "C23": ("psd_eps01", "k2_sweep"),
    "C24": ("psd_eps001",),
    "D5": ("audit",),
}

#: The datasets each chaos claim's faithful columns are judged from (sleighsim.claims.faithful), in the
#: order its faithful judge takes them.
FAITHFUL: dict[str, tuple[str, ...]] = {
    "C13": ("trigger_law",),
    "C14": ("chaos_verdict",),
    "C15": (),  # IN_LADDER: the claim's own datasets in the finest precision of their ladders
    "C16": (),
    "C17": (),
    "C18": ("chaos_verdict",),
    "C19": ("chaos_verdict",),
    "C20": ("lyap_energy", "chaos_verdict"),
    "C21": ("fig11_grid", "chaos_verdict"),
    "C22": (),
    "C23": (),
    "C24": (),
    "C26": ("formal_exponents",),
    "C27": ("fig11_grid", "chaos_verdict"),
}
