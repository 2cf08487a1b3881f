"""The terms of a study's prediction equations (study/terms.py: an
arithmetic expression of the inputs with + - * / ^ and brackets) against
the same expressions written out by hand in Python, whose own arithmetic,
precedence and associativity are the independent reference: '^' a power
(x^2 = x**2, right-associative: 2^3^2 = 2**9), '-x^2' = -(x**2), '/' and
'-' left-associative."""
import numpy as np
import pytest

from masonrydem.study.terms import evaluate_term, parse_term

INPUTS = ("f_tu", "f_tj", "sigma_v", "L", "H", "t")

# each term with its value written out by hand, and the inputs it uses in
# the order they first appear in it
TERMS = [
    ("f_tu", lambda f_tu, **_: f_tu, ("f_tu",)),
    ("f_tu^2", lambda f_tu, **_: f_tu ** 2, ("f_tu",)),
    ("f_tu ^ 3", lambda f_tu, **_: f_tu * f_tu * f_tu, ("f_tu",)),
    ("f_tj*sigma_v", lambda f_tj, sigma_v, **_: f_tj * sigma_v, ("f_tj", "sigma_v")),
    ("f_tj*(L + t)/(H + t)", lambda f_tj, L, t, H, **_: f_tj * (L + t) / (H + t), ("f_tj", "L", "t", "H")),
    ("-f_tj", lambda f_tj, **_: -f_tj, ("f_tj",)),
    ("-f_tu^2", lambda f_tu, **_: -(f_tu * f_tu), ("f_tu",)),
    ("(-f_tj)^2", lambda f_tj, **_: f_tj * f_tj, ("f_tj",)),
    ("f_tu - f_tj - sigma_v", lambda f_tu, f_tj, sigma_v, **_: (f_tu - f_tj) - sigma_v, ("f_tu", "f_tj", "sigma_v")),
    ("f_tu - (f_tj - sigma_v)", lambda f_tu, f_tj, sigma_v, **_: f_tu - f_tj + sigma_v, ("f_tu", "f_tj", "sigma_v")),
    ("L/H/t", lambda L, H, t, **_: (L / H) / t, ("L", "H", "t")),
    ("L/(H*t)", lambda L, H, t, **_: L / H / t, ("L", "H", "t")),
    ("f_tu + f_tj*sigma_v", lambda f_tu, f_tj, sigma_v, **_: f_tu + (f_tj * sigma_v), ("f_tu", "f_tj", "sigma_v")),
    ("(f_tu + f_tj)*sigma_v", lambda f_tu, f_tj, sigma_v, **_: f_tu * sigma_v + f_tj * sigma_v,
     ("f_tu", "f_tj", "sigma_v")),
    ("2*f_tj^2", lambda f_tj, **_: 2 * (f_tj * f_tj), ("f_tj",)),
    ("t^2^-1", lambda t, **_: t ** 0.5, ("t",)),
    ("f_tu^0.5 - 1.5e-1*+t", lambda f_tu, t, **_: np.sqrt(f_tu) - 0.15 * t, ("f_tu", "t")),
    ("sigma_v/-2 + f_tj^-1", lambda sigma_v, f_tj, **_: -0.5 * sigma_v + 1 / f_tj, ("sigma_v", "f_tj")),
    ("sigma_v*f_tu^2*f_tj", lambda sigma_v, f_tu, f_tj, **_: sigma_v * (f_tu * f_tu) * f_tj,
     ("sigma_v", "f_tu", "f_tj")),
    ("t*(f_tj + L) + f_tj", lambda t, f_tj, L, **_: t * f_tj + t * L + f_tj, ("t", "f_tj", "L")),
]


def _inputs(seed=0, n=7):
    """Positive values, distinct and away from 1, so that x^2, 2x and x
    differ, and so do a - b and b - a."""
    rng = np.random.default_rng(seed)
    return {name: rng.uniform(1.3, 4.0, n) for name in INPUTS}


@pytest.mark.parametrize("term, by_hand, names", TERMS, ids=[t for t, _, _ in TERMS])
def test_a_term_is_its_arithmetic_written_out_by_hand(term, by_hand, names):
    """Each term's values equal those of the expression written out in
    Python (products for powers where they can be, the brackets that the
    precedence implies written out), to 1e-12, over seven random values of
    each input; and the inputs it uses are named in the order they first
    appear in it.  A swapped operator, '^' read as a product, a dropped
    unary minus or a wrong precedence changes a value by far more."""
    x = _inputs()
    np.testing.assert_allclose(evaluate_term(term, x), by_hand(**x), rtol=1e-12, atol=0)
    assert parse_term(term, INPUTS)[1] == names


def test_a_term_is_evaluated_elementwise_over_arrays_and_scalars():
    """Over arrays each value is the term at that element (the first
    element evaluated on its own, as scalars, gives the first value);
    a scalar input broadcasts."""
    x = _inputs(1)
    for term, by_hand, _ in TERMS:
        one = {k: float(v[0]) for k, v in x.items()}
        assert float(evaluate_term(term, one)) == pytest.approx(float(by_hand(**one)), rel=1e-12), term
    both = dict(x, sigma_v=0.25)
    np.testing.assert_allclose(evaluate_term("f_tj*sigma_v", both), x["f_tj"] * 0.25, rtol=1e-15)


@pytest.mark.parametrize("term, words", [
    ("f_tu^2 + E_b", "'E_b' in 'f_tu^2 + E_b' is not an input"),
    ("exp(f_tu)", "only inputs, numbers, + - * / ^ and brackets"),
    ("f_tu.real", "only inputs, numbers, + - * / ^ and brackets"),
    ("f_tu > 2", "only inputs, numbers, + - * / ^ and brackets"),
    ("f_tu % 2", "only inputs, numbers, + - * / ^ and brackets"),
    ("f_tu // 2", "only inputs, numbers, + - * / ^ and brackets"),
    ("f_tu * 'a'", "'a' in \"f_tu * 'a'\" is not a number"),
    ("f_tu * True", "True in 'f_tu * True' is not a number"),
    ("2 * 3", "'2 * 3' uses no input"),
    ("f_tu *", "is not an arithmetic expression of the inputs"),
    ("(f_tu", "is not an arithmetic expression of the inputs"),
])
def test_a_term_that_is_not_arithmetic_of_the_inputs_is_refused(term, words):
    with pytest.raises(ValueError) as e:
        parse_term(term, INPUTS)
    assert words in str(e.value)
