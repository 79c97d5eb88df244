"""The F11 grid's per-row faithfulness gauge (sleighsim.scenes.grid): which arithmetic follows each row's orbit."""


def test_each_rows_faithful_arithmetic_and_whether_lambda_1s_follows_on_each_branch():
    """faithful_code indexes grid.LADDER (double, long double, double-double, quad): a row double follows, one
    only long double follows, one no arithmetic of the ladder follows, one without a complete spike cycle."""
    from sleighsim.precision import Precision
    from sleighsim.scenes.grid import faithful_words

    names, follow = faithful_words([0.0, 1.0, 4.0, float("nan")], Precision.DOUBLE)
    assert names[:2] == ["double", "long double"] and names[2].startswith("none of double, long double")
    assert names[3].startswith("unknown") and follow == ["follows", "does not follow", "does not follow", "unknown"]
    assert faithful_words([1.0, 2.0], Precision.LONG_DOUBLE)[1] == ["follows", "does not follow"]
