"""Brent's root finder and minimiser (pendulab.numerics.roots).

References: the roots and minima below are computed by mpmath at 50 digits
(``findroot`` from a nearby start, the minimum as the root of the
derivative), independently of the code under test; SciPy's ``brentq`` and
``minimize_scalar(method="bounded")``, which the module replaces, are the
second reference.
"""

import math
import subprocess
import sys

import mpmath
import pytest

from pendulab.errors import InputError
from pendulab.numerics.roots import EPS, NoConvergence, brent_minimum, brent_root

ROOTS = [
    # (f as float function, f as mpmath function, bracket, start for mpmath)
    (lambda x: x * x - 2.0, lambda x: x * x - 2, (0.0, 2.0), 1.4),
    (lambda x: math.cos(x) - x, lambda x: mpmath.cos(x) - x, (0.0, 1.0), 0.7),  # Dottie number
    (lambda x: x ** 3 - 2 * x - 5, lambda x: x ** 3 - 2 * x - 5, (2.0, 3.0), 2.1),  # Wallis' cubic
    (lambda x: math.exp(x) - 1e10, lambda x: mpmath.exp(x) - 10 ** 10, (0.0, 50.0), 23.0),  # steep
    (lambda x: (x - 1e-3) ** 3, None, (-1.0, 1.0), "1e-3"),  # a triple root
    (lambda x: math.atan(1e6 * (x - 0.3)), lambda x: mpmath.atan(10 ** 6 * (x - mpmath.mpf("0.3"))),
     (0.0, 1.0), 0.3),  # nearly a step
    (lambda x: math.sin(x), mpmath.sin, (3.0, 4.0), 3.1),  # pi
]


def _exact(fm, start):
    if isinstance(start, str):  # known exactly
        return mpmath.mpf(start)
    with mpmath.workdps(50):
        return mpmath.findroot(fm, mpmath.mpf(start), tol=mpmath.mpf(10) ** -45)


@pytest.mark.parametrize("case", range(len(ROOTS)))
@pytest.mark.parametrize("xtol, rtol", [(2e-12, 4 * EPS), (1e-16, 4 * EPS), (1e-6, 1e-6)])
def test_root_within_the_tolerance_of_the_50_digit_root(case, xtol, rtol):
    f, fm, (a, b), start = ROOTS[case]
    exact = _exact(fm, start)
    r = brent_root(f, a, b, xtol=xtol, rtol=rtol, maxiter=1000 if case == 4 else 100)
    assert a <= r <= b
    # the bracket [b, c] is shorter than 2 tol when it stops; the root's rounding adds a few eps
    bound = xtol + rtol * abs(float(exact)) + 8 * EPS * abs(float(exact))
    assert abs(r - float(exact)) <= bound, (r, exact)


@pytest.mark.parametrize("case", range(len(ROOTS)))
def test_root_agrees_with_scipy_brentq(case):
    from scipy.optimize import brentq
    f, _, (a, b), _ = ROOTS[case]
    ours = brent_root(f, a, b, xtol=1e-15, rtol=4 * EPS, maxiter=1000)
    theirs = brentq(f, a, b, xtol=1e-15, rtol=4 * EPS, maxiter=1000)
    assert abs(ours - theirs) <= 2e-15 + 8 * EPS * abs(theirs)


def test_root_counts_few_evaluations_where_interpolation_works():
    calls = []

    def f(x):
        calls.append(x)
        return math.cos(x) - x
    brent_root(f, 0.0, 1.0, xtol=1e-15)
    assert len(calls) <= 12  # bisection alone would need about 50


def test_root_at_an_end_of_the_bracket_is_returned_at_once():
    assert brent_root(lambda x: x - 1.0, 1.0, 5.0) == 1.0
    assert brent_root(lambda x: x - 5.0, 1.0, 5.0) == 5.0


@pytest.mark.parametrize("bad, match", [
    (dict(f=lambda x: x * x + 1, a=-1.0, b=1.0), "same sign"),
    (dict(f=lambda x: x, a=-math.inf, b=1.0), "not finite"),
    (dict(f=lambda x: x, a=math.nan, b=1.0), "not finite"),
    (dict(f=lambda x: x, a=-1.0, b=1.0, xtol=0.0), "xtol"),
    (dict(f=lambda x: x, a=-1.0, b=1.0, rtol=1e-20), "rtol"),
])
def test_root_refuses_bad_input_in_one_line(bad, match):
    with pytest.raises(InputError, match=match) as err:
        brent_root(**bad)
    assert "\n" not in str(err.value)


def test_root_reports_no_convergence():
    with pytest.raises(NoConvergence):
        brent_root(lambda x: (x - 0.123456789) ** 9, 0.0, 1.0, xtol=1e-16, maxiter=10)


MINIMA = [
    # (f float, f' mpmath (its root is the minimum), interval, start)
    (lambda x: (x - 1.0) ** 2 + 3.0, lambda x: 2 * (x - 1), (0.0, 4.0), 1.0),
    (math.cos, lambda x: -mpmath.sin(x), (2.0, 4.0), 3.1),  # pi
    (lambda x: x ** 4 - 3 * x + 1, lambda x: 4 * x ** 3 - 3, (-2.0, 3.0), 0.9),  # (3/4)^(1/3)
    (lambda x: math.exp(x) - 2 * x, lambda x: mpmath.exp(x) - 2, (-5.0, 5.0), 0.7),  # log 2
    (lambda x: -x * math.exp(-x), lambda x: (x - 1) * mpmath.exp(-x), (0.0, 10.0), 1.0),
]


@pytest.mark.parametrize("case", range(len(MINIMA)))
@pytest.mark.parametrize("xatol", [1e-5, 1e-10, 1e-13])
def test_minimum_within_the_tolerance_of_the_50_digit_minimiser(case, xatol):
    f, fprime, (a, b), start = MINIMA[case]
    exact = float(_exact(fprime, start))
    x, fx = brent_minimum(f, a, b, xatol=xatol)
    assert a < x < b and fx == f(x)
    # near a minimum f is flat to about sqrt(eps) |x|: that is the attainable accuracy
    assert abs(x - exact) <= 3 * xatol + 4 * math.sqrt(EPS) * max(1.0, abs(exact))
    if xatol <= 1e-10:  # then f(x) is the minimum to rounding
        assert fx <= f(exact) + 4 * EPS * max(1.0, abs(f(exact)))


@pytest.mark.parametrize("case", range(len(MINIMA)))
def test_minimum_value_agrees_with_scipy_bounded(case):
    from scipy.optimize import minimize_scalar
    f, _, (a, b), _ = MINIMA[case]
    x, fx = brent_minimum(f, a, b, xatol=1e-13, maxiter=500)
    res = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-13, "maxiter": 500})
    assert abs(fx - res.fun) <= 4 * EPS * max(1.0, abs(res.fun))


def test_minimum_of_a_monotone_function_lies_at_the_low_end():
    x, _ = brent_minimum(lambda x: x, 2.0, 3.0, xatol=1e-9)
    assert 2.0 < x < 2.0 + 1e-7  # within 2 (sqrt(eps) |x| + xatol / 3) of the end


@pytest.mark.parametrize("bad", [dict(a=1.0, b=1.0), dict(a=2.0, b=1.0), dict(a=0.0, b=math.inf),
                                 dict(a=0.0, b=1.0, xatol=-1.0)])
def test_minimum_refuses_bad_input_in_one_line(bad):
    with pytest.raises(InputError) as err:
        brent_minimum(lambda x: x * x, **bad)
    assert "\n" not in str(err.value)


def test_refinements_of_a_build_import_neither_scipy_optimize_nor_scipy_integrate():
    """The point of the module: the events of the reference integration, the series'
    stability interval and the motion's zero length refine without scipy.optimize, and
    the DOP853 tables come without scipy.integrate's package (about 0.3 s each process)."""
    code = (
        "import sys\n"
        "from pendulab.numerics import dop853\n"
        "from pendulab.analyses.series import interval_series_theta1\n"
        "ys = dop853.solve(lambda t, a, b: (b, -a), [0.0, 5.0], (0.0, 1.0), 1e-10, 1e-12,\n"
        "                  events=[lambda t, a, b: a])\n"
        "lo, up = interval_series_theta1(4, -0.04)\n"
        "assert lo is not None\n"
        "(te, _), = ys[3]\n"
        "assert te[0] == 0.0 and abs(te[-1] - 3.141592653589793) < 1e-9, te  # a = sin t\n"
        "print(sorted(m for m in ('scipy.optimize', 'scipy.integrate') if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("f", [
    lambda x: math.nan if x == 0 else 1.0,                               # NaN at an end
    lambda x: x - 0.3 if abs(x - 0.5) > 0.2 else math.nan,               # NaN inside, root at its edge
    lambda x: -1.0 if x == 0 else (1.0 if x == 1 else math.nan),         # NaN everywhere inside
])
def test_root_refuses_a_nan_value_instead_of_returning_a_false_root(f):
    """SciPy's brentq raises on NaN; so does brent_root (a pendulab error: one line), and it
    never returns a point where f is not 0 within the tolerance."""
    from pendulab.errors import PendulabError
    from pendulab.numerics.roots import NotANumber
    with pytest.raises(NotANumber) as err:
        brent_root(f, 0.0, 1.0)
    assert isinstance(err.value, PendulabError) and "\n" not in str(err.value)


def test_no_convergence_is_a_pendulab_error():
    from pendulab.errors import PendulabError
    assert issubclass(NoConvergence, PendulabError)
