"""The arithmetic type: parsed from its config name, refused otherwise, each member's numbers."""

import numpy as np
import pytest

from sleighsim.precision import Precision


@pytest.mark.parametrize("name, member", [("double", Precision.DOUBLE), ("long double", Precision.LONG_DOUBLE),
                                          ("double-double", Precision.DOUBLE_DOUBLE), ("quad", Precision.QUAD)])
def test_parse_takes_the_config_name_or_a_member(name, member):
    assert Precision.parse(name) is member and Precision.parse(member) is member
    assert member == name and str(member) == name and f"{member}" == name  # written to datasets as its name


@pytest.mark.parametrize("bad", ["long_double", "single", "Double", "", None, 64])
def test_parse_refuses_anything_else_naming_it(bad):
    with pytest.raises(ValueError, match=f"precision {bad!r}"):
        Precision.parse(bad)


def test_each_member_carries_its_tag_epsilon_rounding_and_types():
    hy = pytest.importorskip("heyoka")
    assert [p.tag for p in Precision] == ["double", "long_double", "double_double", "quad"]
    assert [p.epsilon for p in Precision] == [2.0**-52, 2.0**-63, 2.0**-105, 2.0**-112]
    assert [p.rounding for p in Precision] == [2.0**-53, 2.0**-64, 2.0**-106, 2.0**-113]
    heyoka_types = [Precision.DOUBLE, Precision.LONG_DOUBLE, Precision.QUAD]
    assert [p.fp_type for p in heyoka_types] == [float, np.longdouble, hy.real128]
    assert [p.dtype for p in Precision] == [np.dtype(float), np.dtype(np.longdouble), np.dtype(float),
                                            np.dtype(hy.real128)]
    assert list(Precision) == ["double", "long double", "double-double", "quad"]  # coarse to fine


def test_double_double_has_no_heyoka_type():
    """Only sleighsim.engine.ddtaylor integrates in double-double: asking heyoka's type says so."""
    with pytest.raises(ValueError, match="ddtaylor"):
        _ = Precision.DOUBLE_DOUBLE.fp_type


def test_the_config_schema_names_exactly_the_types_arithmetics():
    """The schema's two enums are the type's names (all, and heyoka's): the type is the one list, the
    schema cannot drift from it."""
    from pathlib import Path

    import yaml

    schema = yaml.safe_load((Path(__file__).parents[1] / "workflow" / "schemas" / "config.schema.yaml").read_text())
    assert schema["$defs"]["precision"]["enum"] == [p.value for p in Precision]
    heyoka = [p.value for p in Precision if p is not Precision.DOUBLE_DOUBLE]
    assert schema["$defs"]["heyoka_precision"]["enum"] == heyoka
