"""benchmarks/precision_cost.py --quick writes a complete table: every (system, precision, compact mode) row,
high_accuracy rows in double, positive finite costs, and the high_accuracy separations. No timing thresholds:
speed targets live in the benchmarks, not in the tests."""

import math
import subprocess
import sys
from itertools import product
from pathlib import Path

import yaml

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "precision_cost.py"


def _positive(x) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x) and x > 0


def test_quick_run_writes_every_row(tmp_path, hy):
    out = tmp_path / "precision_cost.yaml"
    # about 5 s with heyoka's disk cache warm; about 40 s on one core when it must compile the full-mode
    # tangent integrators (long double, quad) from scratch
    res = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--out", str(out)], capture_output=True, text=True,
                         timeout=900, check=False)
    assert res.returncode == 0, res.stderr[-3000:]
    doc = yaml.safe_load(out.read_text())
    assert doc["schema"] == "sleighsim.precision_cost/1" and doc["quick"] is True
    assert doc["git_commit"] and doc["machine"]["cpu_count"] >= 1 and doc["loadavg"]["start"]

    rows = {(r["system"], r["precision"], r["compact_mode"], r["high_accuracy"]): r for r in doc["rows"]}
    want = {(s, p, c, False) for s, p, c in product(("flow", "tangent"), ("double", "long double", "quad"),
                                                      (True, False))}
    want |= {(s, "double", c, True) for s, c in product(("flow", "tangent"), (True, False))}
    assert set(rows) == want
    for key, r in rows.items():
        assert _positive(r["compile_cpu_s"]) and _positive(r["compile_wall_s"]), key
        assert _positive(r["cost_s_per_tu"]) and _positive(r["steps_per_tu"]) and _positive(r["ratio_to_double"]), key
        assert r["window"] == ("short" if key[1] == "quad" else "long"), key
        assert set(r["windows"]) == ({"short"} if key[1] == "quad" else {"short", "long"}), key
        for name, w in r["windows"].items():
            assert w["repeats"] >= 3 and len(w["cpu_s"]) == w["repeats"], (key, name)
            for field in ("cpu_s_per_tu", "wall_s_per_tu", "steps_per_tu", "ratio_to_double"):
                assert _positive(w[field]), (key, name, field)
        if key[1] == "double" and not key[3]:
            assert r["ratio_to_double"] == 1.0

    acc = doc["high_accuracy"]
    assert len(acc["spike_times"]) == 2 and acc["spike_times"][0] < acc["spike_times"][1]
    for name in ("double", "double_high_accuracy"):
        seps = acc["vs_long_double"][name]
        assert {"half_way_to_first_spike", "after_first_spike", "after_second_spike"} <= set(seps)
        assert all(_positive(v) for v in seps.values()), (name, seps)
    assert acc["vs_quad"] is None  # --quick has no quad reference
    assert len(acc["cost_ratio_high_accuracy_over_plain"]) == 4
    assert all(_positive(v) for w in acc["cost_ratio_high_accuracy_over_plain"].values() for v in w.values())
