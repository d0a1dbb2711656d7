"""Points the double-precision routes of the vectorised exponent cannot
resolve (an audit): bands thinner than the rounding of their edges at
large |theta1|, and traces that lose their digits to cancellation at
theta0 << 0.  Before the checks in pendulab.analyses.floquet._vectorised the
exponent there was wrong by O(1) (0j for 10.709j; a band value for a gap) and
depended on the other points of the call.

Reference: characteristic_exponent by continued fractions (method "cf",
000 eq. 10) at 30 digits, a route that shares no code with the vectorised
trace or band Newton.
"""

import numpy as np
import pytest

from pendulab.analyses.floquet import characteristic_exponent, exponent, theta0_of_exponent
from pendulab.analyses.floquet import _vectorised as V

# (theta0, theta1): three with theta0 the double a_k(q) at large q (bands far
# thinner than one ulp), one a gap point next to an edge at theta0 = -126
POINTS = [(-592.4076234321313, 313.7920879733143), (-367.9690016950315, 263.48490064526516),
          (-306.69758148598225, -227.02128718478843), (-126.00068915214185, 90.97355072206977)]


def _exact(t0, q):
    return complex(characteristic_exponent(t0, q, dps=30, method="cf").lam)


@pytest.mark.parametrize("t0, q", POINTS)
def test_unresolved_points_are_right(t0, q):
    got = exponent([t0], [q])[0]
    ref = _exact(t0, q)
    assert abs(got - ref) <= 1e-9 * max(1.0, abs(ref)), (got, ref)


def test_answers_do_not_depend_on_the_batch():
    t0, q = POINTS[3]
    alone = exponent([t0], [q])[0]
    # more than 16 distinct |q|: the certified edges instead of LAPACK, a deeper trace
    batch = exponent(np.r_[t0, np.linspace(0, 5, 20)], np.r_[q, np.linspace(0.1, 2, 20)])[0]
    ref = _exact(t0, q)
    assert abs(alone - ref) <= 1e-9 and abs(batch - ref) <= 1e-9, (alone, batch, ref)


def test_round_trip_on_thin_bands(rng):
    # theta0 = a_k(q) rounded to a double lies in a gap at these q (the low bands
    # are far thinner than one ulp); the exponent there is the exact one at that
    # double, not the edge's k.  (At smaller q, where the bands are wider than
    # their rounding, such a point is within the backward error of its edge and
    # may be given to the band or to the gap: docs/floquet.md.)
    q = rng.uniform(150.0, 400.0, 6)
    k = rng.integers(0, 5, 6).astype(float)
    t0 = theta0_of_exponent(k, q)
    got = exponent(t0, q)
    for a, b, g in zip(t0, q, got):
        ref = _exact(float(a), float(b))
        assert abs(g - ref) <= 1e-9 * max(1.0, abs(ref)), (a, b, g, ref)


def test_ordinary_grids_take_no_scalar_fallback(monkeypatch, rng):
    # the checks must not send ordinary points to the slow scalar routine
    calls = []
    real = V._scalar_exponents
    monkeypatch.setattr(V, "_scalar_exponents", lambda a, b: calls.append(a.size) or real(a, b))
    t0 = rng.uniform(-400.0, 400.0, 4000)
    q = rng.uniform(-400.0, 400.0, 4000)
    exponent(t0, q)
    nu = np.round(np.arange(201) * 0.01, 2)[:, None]
    qq = np.round(np.arange(-500, 501, 5) * 0.01, 2)[None, :]
    NU, Q = np.broadcast_arrays(nu, qq)
    exponent(theta0_of_exponent(NU, -Q), -Q)
    assert sum(calls) == 0


def test_one_large_point_does_not_enlarge_every_table(monkeypatch, rng):
    # the certified edge tables are built per octave of size (SIZE_BUCKET): a
    # single nu = 150.5 or theta0 = 3.9e6 among 2000 small points gets its own
    # table instead of making all 2000 |theta1| as deep as itself
    seen = []
    real = V._certify_edges

    def spy(qs, top, *a, **k):
        seen.append((len(qs), float(top)))
        return real(qs, top, *a, **k)
    monkeypatch.setattr(V, "_certify_edges", spy)
    q = rng.uniform(0.01, 1.0, 2000)
    nu = rng.uniform(0.0, 3.0, 2000)
    nu[0] = 150.5
    got = theta0_of_exponent(nu, q)
    t0 = rng.uniform(0.0, 10.0, 2000)
    t0[0] = 3.9e6
    lam = exponent(t0, q)
    assert seen and all(n <= 16 or top <= 200.0 for n, top in seen), seen
    # and the large points are right (the scalar routines as the reference)
    assert abs(got[0] - theta0_of_exponent(150.5, float(q[0]))) <= 1e-12 * abs(got[0])
    assert abs(lam[0] - characteristic_exponent(3.9e6, float(q[0])).lam) <= 1e-9 * abs(lam[0])


def test_size_limit_is_the_inputs_own():
    # |theta0| + 2|theta1| = 4e6 exactly is accepted (the limit is inclusive); the
    # gap route's own edge E (a little larger) must not be checked against it
    from pendulab.analyses.floquet._inputs import SIZE_LIMIT

    lam = exponent([0.0], [SIZE_LIMIT / 2])
    assert np.isfinite(lam).all() and lam[0].imag > 100


@pytest.mark.parametrize("bad", [[1 + 1j], [0.5j], [10 ** 400]])
def test_complex_and_huge_inputs_are_refused(bad):
    # refused with one line, not cast to the real part (NumPy's ComplexWarning)
    from pendulab.errors import InputError

    with pytest.raises(InputError, match="must be real numbers"):
        exponent(bad, [1.0])
    with pytest.raises(InputError, match="must be real numbers"):
        exponent([1.0], bad)
    with pytest.raises(InputError, match="must be real numbers"):
        theta0_of_exponent(np.array([0.5]), bad)
