"""Every scene kind is declared once, beside its function (sleighsim.scenes.kind.SceneKind), and the
catalog collects them: each has what the workflow, the config checks and the cost estimate need."""

import inspect
import subprocess
import sys

import pytest
import yaml
from conftest import ROOT

from sleighsim.scenes import catalog
from sleighsim.scenes.kind import SceneKind

SCHEMA = yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())


@pytest.mark.parametrize("kind", [k for k, v in catalog.KINDS.items() if v.dataset and not v.chunked])
def test_every_kind_with_a_dataset_has_its_function(kind):
    declared = catalog.KINDS[kind]
    params = inspect.signature(declared.compute).parameters
    assert callable(declared.compute) and "scene" in params
    assert ("inputs" in params or len(params) == 3) if declared.inputs else len(params) == 2
    assert (declared.gather is None) == (declared.chunk is None) == (not declared.variants_chunked)


@pytest.mark.parametrize("kind", [k for k, v in catalog.KINDS.items() if v.variants_chunked and not v.chunked])
def test_a_kind_chunked_in_finer_precisions_only_is_laddered_with_its_chunks_beside_its_function(kind):
    """One job in double (its SIMD lanes), chunk jobs in a finer precision (lanes one after another)."""
    declared = catalog.KINDS[kind]
    assert declared.observables
    assert declared.chunk.__module__ == declared.gather.__module__ == declared.compute.__module__


@pytest.mark.parametrize("kind", [k for k, v in catalog.KINDS.items() if v.chunked])
def test_chunked_kinds_have_chunk_gather_and_a_count(kind):
    declared = catalog.KINDS[kind]
    assert declared.chunk.__name__ == "chunk" and declared.gather.__name__ == "gather"
    assert declared.chunk.__module__ == declared.gather.__module__
    assert declared.compute is None and declared.chunk_count({"kind": kind, "n_chunks": 2, "states": {"a": []},
                                                                        "decisive": {"states": []}}) >= 2


@pytest.mark.parametrize("kind", list(catalog.KINDS))
def test_every_kind_has_a_memory_estimate_a_work_model_and_checks(kind):
    declared = catalog.KINDS[kind]
    assert isinstance(declared, SceneKind) and declared.name == kind
    for fn in (declared.records, declared.work, declared.chunk_work, declared.modelled, declared.checks):
        assert callable(fn)


def test_a_kind_without_dataset_has_no_function():
    assert not catalog.KINDS["schematic"].dataset and catalog.KINDS["schematic"].compute is None


def test_the_schema_names_exactly_the_catalog_kinds():
    """The schema's enum of kinds and its per-kind blocks follow the catalog: a kind forgotten in either fails."""
    assert sorted(SCHEMA["$defs"]["scene"]["properties"]["kind"]["enum"]) == sorted(catalog.KINDS)
    assert {kind for kind in catalog.KINDS if kind in SCHEMA["$defs"]} == set(catalog.KINDS)


def test_only_laddered_kinds_declare_observables():
    assert {k for k, v in catalog.KINDS.items() if v.observables} == {
        "poincare", "trajectory", "lyapunov_spectrum", "lyapunov_protocol", "lyapunov_energy", "lyapunov_grid", "psd"}


def test_importing_the_catalog_leaves_scipy_signal_stats_and_optimize_to_the_scenes_that_use_them():
    """Every job imports the catalog, so every scene module: these packages (0.8 CPU-s of a job's
    start-up, measured with farm-bench) are imported inside the functions that use them."""
    heavy = ("scipy.signal", "scipy.stats", "scipy.optimize")
    code = f"import sys, sleighsim.scenes.catalog; print([m for m in {heavy!r} if m in sys.modules])"
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60)
    assert res.stdout.strip() == "[]"


#: Where a kind's name may stand as a string besides its own module, each a homonym with its reason: the
#: paper config's scenes that share a kind's name, named in the places that declare which datasets a claim,
#: figure or table reads (docs/layout.md), rule and folder names, and words that mean something else there.
HOMONYMS = {
    "claims/evidence.py": "the datasets each claim reads, by the paper config's scene names",
    "report/tables.py": "the dataset each table reads, by scene name",
    "report/figures/*.py": "the datasets each figure reads, by scene name; figure names; a dimension 'trajectory'",
    "ops/names.py": "the workflow's rule names (rule schematic)",
    "engine/peer_lyapunov.py": "lyapax's function lyapunov_spectrum",
    "scenes/paper_setup.py": "the power-spectrum convention, a setup element named psd",
    "scenes/causes.py": "the setup element psd",
    "report/findings.py": "the setup element psd",
}


def test_a_kind_is_named_as_a_string_only_in_its_own_module():
    """Adding a kind touches only the places docs/layout.md's recipe names: its module (the declaration), the
    catalog (an import), the schema and the configs. Its name as a string literal anywhere else in the package
    or the workflow is a kind compared with a literal or listed by hand, except the homonyms above."""
    import fnmatch
    import re
    import sys
    from pathlib import Path

    root = Path(__file__).parents[2]
    pkg = root / "src" / "sleighsim"
    places = [root / "workflow" / "Snakefile", *(root / "workflow").rglob("*.smk"), *(root / "workflow").rglob("*.py"),
              *pkg.rglob("*.py")]
    found = []
    for kind in catalog.KINDS.values():
        fn = next(f for f in (kind.compute, kind.chunk, kind.gather, kind.records) if f is not None)
        own = Path(sys.modules[fn.__module__].__file__).resolve()
        for p in places:
            rel = p.relative_to(pkg).as_posix() if p.is_relative_to(pkg) else p.relative_to(root).as_posix()
            if p.resolve() == own or any(fnmatch.fnmatch(rel, pattern) for pattern in HOMONYMS):
                continue
            if re.search(rf"""["']{kind.name}["']""", p.read_text()):
                found.append((rel, kind.name))
    assert found == []


def test_every_kind_is_exercised_by_the_smoke_run_or_tests_of_its_own():
    """Each kind has a scene in the smoke configuration; one the smoke run does not build (on request) is
    run by a test module that imports its scene module (the smoke run's datasets are checked end to end by
    tests/workflow and tests/io/test_cf.py)."""
    import re
    import sys
    from pathlib import Path

    from conftest import smoke_config

    cfg = smoke_config()
    built = set(catalog.datasets(cfg))
    tests = [p.read_text() for p in (Path(__file__).parents[1]).rglob("test_*.py")]
    for kind in catalog.KINDS.values():
        scenes = [n for n, b in cfg["scenes"].items() if b["kind"] == kind.name]
        assert scenes, f"no scene of kind {kind.name} in the smoke configuration"
        if kind.dataset and not set(scenes) & built:
            fn = next(f for f in (kind.compute, kind.chunk, kind.gather) if f is not None)
            module = sys.modules[fn.__module__].__name__
            short = module.rsplit(".", 1)[-1]
            assert any(re.search(rf"{module}|scenes import (\w+, )*{short}\b", t) for t in tests), kind.name
