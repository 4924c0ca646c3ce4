"""Parameter checks name the parameter and say what was wrong."""
import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
from mybot_common.params import ParamError, boolean, number, string  # noqa: E402


def test_number_accepts_ints_and_floats_in_range():
    assert number("~speed", 2) == 2.0
    assert number("~count", 3, low=1, integer=True) == 3
    assert number("~gain", 0.5, low=0.0, high=1.0) == 0.5


@pytest.mark.parametrize("value, kwargs, words", [
    ("fast", {}, "must be a number"),
    (True, {}, "must be a number"),
    (math.nan, {}, "must be finite"),
    (2.5, {"integer": True}, "must be an integer"),
    (0.0, {"low": 0.0, "low_open": True}, "must be > 0"),
    (7.0, {"high": 1.0}, "must be <= 1"),
])
def test_number_names_the_parameter(value, kwargs, words):
    with pytest.raises(ParamError) as e:
        number("~speed", value, **kwargs)
    assert "'~speed'" in str(e.value) and words in str(e.value)
    assert e.value.name == "~speed"


def test_boolean_and_string():
    assert boolean("~on", False) is False
    with pytest.raises(ParamError, match="true or false"):
        boolean("~on", "yes")
    assert string("~mode", "a", choices=["a", "b"]) == "a"
    with pytest.raises(ParamError, match="one of a, b"):
        string("~mode", "c", choices=["a", "b"])
