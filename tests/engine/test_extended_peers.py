"""benchmarks/extended_peers.py --quick writes a complete table: every method present, errors finite and
positive, and heyoka's real128 and its arbitrary-precision real at 113 bits agree (a correctness
cross-check of the two quad arithmetics, not a speed threshold). No timing thresholds: speed targets
live in the benchmarks, not in the tests."""

import math
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "extended_peers.py"
METHODS = {"heyoka long double", "heyoka real128", "heyoka real 113", "mpmath odefun"}


def _positive(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x > 0


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    pytest.importorskip("heyoka")
    pytest.importorskip("mpmath")
    out = tmp_path_factory.mktemp("extended_peers") / "extended_peers.yaml"
    # about 10 s on one core with heyoka's disk cache warm (mpmath's odefun is most of it)
    res = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--out", str(out)], capture_output=True, text=True,
                         timeout=600, check=False)
    assert res.returncode == 0, res.stderr[-3000:]
    return yaml.safe_load(out.read_text())


def test_quick_run_has_every_method_with_finite_positive_errors(quick):
    assert quick["schema"] == "sleighsim.extended_peers/1" and quick["quick"] is True
    assert quick["loadavg"]["start"] and quick["git_commit"]
    rows = quick["rows"]
    assert {r["method"] for r in rows} == METHODS
    for r in rows:
        key = (r["method"], r["tol"])
        for field in ("tol", "error", "wall_s", "setup_s"):
            assert _positive(r[field]), (key, field, r[field])
        assert r["precision"] and r["repeats"] >= 1 and len(r["walls"]) == r["repeats"], key
    # the reference is converged far below every error it measures
    ref = quick["reference"]
    assert ref["prec"] >= 200 and 0 <= ref["check"]["difference"] < 1e-50
    assert ref["check"]["difference"] < 1e-6 * min(r["error"] for r in rows)


def test_real128_and_real_113_agree_at_equal_tol(quick):
    by = {(r["method"], r["tol"]): r for r in quick["rows"]}
    tols = [tol for m, tol in by if m == "heyoka real128"]
    assert tols and sorted(tols) == sorted(tol for m, tol in by if m == "heyoka real 113")
    for tol in tols:
        a, b = by[("heyoka real128", tol)]["error"], by[("heyoka real 113", tol)]["error"]
        assert a / 10 <= b <= 10 * a, (tol, a, b)
    assert len(quick["cross_check_real128_vs_real113"]) == len(tols)


def test_errors_follow_the_tolerance(quick):
    """A sanity check of the error measurement: heyoka's error falls with its tolerance, and the quad
    arithmetics get well past what long double can."""
    for method in ("heyoka long double", "heyoka real128", "heyoka real 113"):
        rows = sorted((r for r in quick["rows"] if r["method"] == method), key=lambda r: r["tol"])
        assert rows[0]["error"] < rows[-1]["error"], method
    best_ld = min(r["error"] for r in quick["rows"] if r["method"] == "heyoka long double")
    best_quad = min(r["error"] for r in quick["rows"] if r["method"] == "heyoka real128")
    assert best_quad < 1e-6 * best_ld
