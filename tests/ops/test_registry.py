"""Every scene kind of the registry reaches its function by import (sleighsim.scenes.function)."""

import inspect

import pytest

from sleighsim.ops import registry
from sleighsim import scenes


@pytest.mark.parametrize("kind", [k for k, v in registry.KINDS.items() if v.dataset and not v.chunked])
def test_every_kind_imports_its_function(kind):
    fn = scenes.function(kind)
    params = inspect.signature(fn).parameters
    assert callable(fn) and "scene" in params
    assert ("inputs" in params or len(params) == 3) if registry.KINDS[kind].inputs else len(params) == 2
    with pytest.raises(KeyError, match="not chunked"):
        scenes.chunk_functions(kind)


@pytest.mark.parametrize("kind", [k for k, v in registry.KINDS.items() if v.chunked])
def test_chunked_kinds_import_chunk_and_gather(kind):
    chunk, gather = scenes.chunk_functions(kind)
    assert chunk.__name__ == "chunk" and gather.__name__ == "gather"
    assert chunk.__module__ == gather.__module__
    with pytest.raises(KeyError, match="no function here"):
        scenes.function(kind)


def test_a_kind_without_dataset_or_unknown_has_no_function():
    assert not registry.KINDS["schematic"].dataset
    for kind in ("schematic", "no_such_kind"):
        with pytest.raises(KeyError):
            scenes.function(kind)
