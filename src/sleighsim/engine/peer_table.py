"""The end-state comparison of the peers (:func:`integration_table`): every SciPy and diffrax peer at every
rtol against one tight reference, with the same error metric and timer."""

from __future__ import annotations

from sleighsim.engine.peer_jax import diffrax_solver
from sleighsim.engine.peer_scipy import compiled_rhs, numpy_rhs, scipy_run
from sleighsim.engine.peers import Y0_REFERENCE, PeerUnavailable, derivation, param_tuple, state_error, timed


def integration_table(param_values, y0=Y0_REFERENCE, t_end: float = 100.0, rtols=(1e-6, 1e-8, 1e-10, 1e-12),
                      atol_factor: float = 1e-3, scipy_methods=("DOP853", "RK45", "LSODA"),
                      rhs_kinds=("numpy", "numba", "heyoka"), diffrax_solvers=("Dopri8", "Tsit5"),
                      repeats: int = 3, warmup: int = 1, reference=None, log=print) -> list[dict]:
    """End-state error against a tight reference (default SciPy DOP853, rtol 1e-13, atol 1e-16,
    compiled heyoka rhs) and median wall time of every peer at every rtol (atol = rtol *
    atol_factor). A peer that is not installed or fails is a row with ``error`` set to None and
    ``note`` saying why. Returns one dict per (engine, rtol)."""
    rows = []
    fns, compile_s = {}, {}
    for kind in rhs_kinds:
        try:
            f = numpy_rhs(param_values) if kind == "numpy" else compiled_rhs(param_values, kind)
            fns[kind], compile_s[kind] = f, f.compile_s
        except PeerUnavailable as exc:
            log(f"skip rhs {kind}: {exc}")
    if reference is None:
        ref_f = fns.get("heyoka") or fns.get("numba") or fns["numpy"]
        reference, _ = scipy_run(ref_f, y0, t_end, "DOP853", 1e-13, 1e-16)
    for rtol in rtols:
        atol = rtol * atol_factor
        for method in scipy_methods:
            for kind, f in fns.items():
                row = dict(engine=f"scipy {method} + {kind} rhs", rtol=rtol, atol=atol, compile_s=compile_s[kind])
                try:
                    (y, nfev), wall, walls = timed(
                        lambda f=f, m=method, r=rtol, a=atol: scipy_run(f, y0, t_end, m, r, a),
                        repeats=repeats, warmup=warmup)
                    row.update(error=state_error(y, reference), wall_s=wall, walls=walls, nfev=nfev, note="")
                except Exception as exc:  # a failed run is a result of the comparison
                    row.update(error=None, wall_s=None, walls=[], nfev=None, note=str(exc))
                rows.append(row)
                log(_row_text(row))
        for solver in diffrax_solvers:
            row = dict(engine=f"diffrax {solver}", rtol=rtol, atol=atol)
            try:
                js = diffrax_solver(float(t_end), float(rtol), float(atol), solver)
                p = param_tuple(param_values, derivation()[3])
                (y, n_acc, n_rej), wall, walls = timed(lambda js=js, p=p: js(y0, p), repeats=repeats, warmup=warmup)
                row.update(compile_s=js.compile_s, error=state_error(y, reference), wall_s=wall, walls=walls,
                           nfev=None, steps=n_acc + n_rej, note=f"{n_acc} accepted + {n_rej} rejected steps")
            except Exception as exc:
                row.update(compile_s=None, error=None, wall_s=None, walls=[], nfev=None, note=str(exc))
            rows.append(row)
            log(_row_text(row))
    return rows


def _row_text(row) -> str:
    err = "-" if row.get("error") is None else f"{row['error']:.2e}"
    wall = "-" if row.get("wall_s") is None else f"{row['wall_s'] * 1e3:.2f} ms"
    return (f"{row['engine']:<34} rtol {row['rtol']:.0e}  error {err:>9}  wall {wall:>11}  nfev {row.get('nfev')}  "
            f"{row.get('note', '')}")
