"""The value rules' quick single-item predicates (``Rule.item_holds``) answer as their NumPy predicates do."""

import itertools

import numpy as np
import pytest

from granum.core import validate

SPECIAL = (0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 1e300, -1e300, np.inf, -np.inf, np.nan)
RULES = [name for name in dir(validate) if isinstance(getattr(validate, name), validate.Rule)
         and getattr(validate, name).item_holds is not None]


def items(item_ndim: int):
    """Every item of shape (3,)*item_ndim whose components are drawn from SPECIAL (scalars: each value;
    vectors: every triple; matrices: 300 random ones and the identity with one special component)."""
    if item_ndim == 0:
        return [np.float64(x) for x in SPECIAL]
    if item_ndim == 1:
        return [np.array(t) for t in itertools.product(SPECIAL, repeat=3)]
    rng = np.random.default_rng(7)
    out = [rng.choice(SPECIAL, size=(3, 3)) for _ in range(300)]
    for k, x in itertools.product(range(9), SPECIAL):
        m = np.eye(3)
        m.flat[k] = x
        out.append(m)
    return out


@pytest.mark.parametrize("name", RULES)
def test_quick_predicate_agrees_with_the_rule(name):
    rule = getattr(validate, name)
    for item in items(rule.item_ndim):
        want = bool(np.all(rule.holds(item)))
        assert rule.item_holds(np.ravel(item).tolist()) == want, (name, item)
        value = float(item) if item.ndim == 0 else item
        if want:
            rule.check(value, "x")
        else:
            with pytest.raises(ValueError, match=f"x {rule.says}"):
                rule.check(value, "x")


def test_the_finite_and_positive_rules_have_quick_predicates():
    assert {"FINITE_VECTOR", "FINITE_MATRIX", "POSITIVE_FINITE", "NON_NEGATIVE_FINITE", "TIME_STEP",
            "EXTENTS"} <= set(RULES)
