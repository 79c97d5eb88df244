"""The machine facts a cost record carries (sleighsim.ops.facts): the widest vector extension, on which the
double-double engine's block width and so every job's time depend."""

import pytest

from sleighsim.ops import facts, plantimes


@pytest.mark.parametrize("flags, want", [
    (["fpu", "sse2", "avx", "avx2", "fma", "avx512f", "avx512dq"], "AVX-512"),
    (["fpu", "sse2", "avx", "avx2", "fma"], "AVX2"),
    (["fpu", "sse2", "avx"], "AVX"),
    (["fpu", "sse2"], "SSE or none"),
])
def test_the_widest_vector_extension_names_the_widest_flag(flags, want):
    assert facts.widest_vector(flags) == want


def test_this_machines_facts_name_its_vector_extension():
    assert facts.machine_facts()["vector"] in {"AVX-512", "AVX2", "AVX", "SSE or none", "unknown"}


def test_a_records_source_names_its_vector_extension_when_it_has_one():
    record = {"date": "2026-11-29", "git_commit": "0123456789abcdef", "machine": {"nproc": 2, "cpu_model": "AMD EPYC"}}
    assert plantimes._source(record, "r.yaml").endswith("2 cores AMD EPYC")  # an older record: no vector named
    record["machine"]["vector"] = "AVX2"
    assert plantimes._source(record, "r.yaml").endswith("2 cores AMD EPYC (AVX2)")
