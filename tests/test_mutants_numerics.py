"""Tests that close gaps mutation testing found in the numerics proof steps (docs/mutation.md):
the RK4 step check's advice (the number of steps per period it asks for).

A refusal of pendulab.numerics.step_check says "ask for at least N steps per drive period" and
a warning "N or more steps per drive period resolve it".  N must be the least whole number of
steps that the rule accepts: one step fewer is refused (warned about), N itself is not.  The
least number is found here by counting up from one step with the rule written out in this file
(RK4's imaginary-axis limit by bisection on R(iy), the aliasing limit h r < 2 pi, the warning
limits h sqrt(max|q|) <= 1 and h r <= 1/2), with max|q| = |theta0| + 2|theta1| from the
canonical pair (000 eq. 7) and r the drive's highest rate in tau.
"""

import math
import re

import numpy as np
import pytest

from pendulab.numerics import step_check as SC
from pendulab.numerics import sweep as S


def _imaginary_limit():
    """Where |R(iy)| = 1, R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24 (RK4's amplification), by
    bisection (Butcher; Hairer-Wanner II, sec. IV.2)."""
    coeffs = [1.0 / math.factorial(k) for k in range(5)][::-1]
    lo, hi = 1.0, 4.0
    for _ in range(200):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if abs(np.polyval(coeffs, 1j * mid)) <= 1 else (lo, mid)
    return lo


def _least_steps(period, rate, harmonic, rate_limit, drive_limit, drive_strict):
    """The least whole S with (period/S) rate <= rate_limit and (period/S) harmonic below
    drive_limit (strictly when drive_strict), counted up from 1."""
    for steps in range(1, 10_000):
        h = period / steps
        drive_ok = h * harmonic < drive_limit if drive_strict else h * harmonic <= drive_limit
        if h * rate <= rate_limit and drive_ok:
            return steps
    raise AssertionError("no step count found")


def _cell(system, a, w):
    fos = S.first_order_system(system)
    row = [[{"a_over_l": a, "w0_over_w": w}[s.name] for s in fos.params]]
    return fos, row


def _advised(text, pattern):
    found = re.search(pattern, text)
    assert found, text
    return int(found.group(1))


# (system, a/l, omega0/omega, steps asked for, the drive's highest rate r in tau)
REFUSED = [
    (S.SystemSpec("rod"), 0.1, 0.05, 1, 2.0),           # one step per period: aliased (r = 2)
    (S.SystemSpec("rod", drive="a*cos(omega*t) + a*cos(2*omega*t)"), 0.02, 0.05, 2, 4.0),
    # h r = (pi/2) 4 = 2 pi exactly at two steps: aliased at the bound itself, three needed
    (S.SystemSpec("rod", angle="down"), 0.0, 3.0, 6, 0.0),   # |q| = 36: stiff, no drive
    (S.SystemSpec("rod"), 1.5, 0.8, 2, 2.0),            # stiff and driven
]


@pytest.mark.parametrize("system,a,w,steps,harmonic", REFUSED)
def test_a_refusal_asks_for_the_least_step_count_that_is_accepted(system, a, w, steps, harmonic):
    fos, row = _cell(system, a, w)
    theta0, theta1 = (float(np.asarray(v).ravel()[0]) for v in S.mathieu_pair(system)(a, w)) \
        if harmonic <= 2.0 else (None, None)
    found = SC.check_step(fos, float(fos.period) / steps, row)
    assert found.unstable == 1 and found.harmonic == harmonic
    if theta0 is not None:   # Mathieu's equation: the rate is the canonical pair's (000 eq. 7)
        assert found.rate ** 2 == pytest.approx(abs(theta0) + 2 * abs(theta1), rel=1e-13)
    need = _advised(found.refusal("x"), r"ask for at least (\d+) steps per drive period")
    least = _least_steps(float(fos.period), found.rate, harmonic, _imaginary_limit(),
                         2 * math.pi, drive_strict=True)
    assert need == least > steps
    assert SC.check_step(fos, float(fos.period) / need, row).unstable == 0
    assert SC.check_step(fos, float(fos.period) / (need - 1), row).unstable == 1


# (system, a/l, omega0/omega, steps asked for); every cell is stable but warned about
WARNED = [
    (S.SystemSpec("rod"), 0.1, 0.05, 2),                # the source's drive: 13 steps resolve it
    (S.SystemSpec("rod"), 0.1, 0.05, 12),               # h r = pi/6 > 1/2, just under-resolved
    (S.SystemSpec("rod", angle="down"), 0.0, 0.5, 2),   # |q| = 1, no drive: h sqrt|q| = pi/2 > 1
]


@pytest.mark.parametrize("system,a,w,steps", WARNED)
def test_a_warning_asks_for_the_least_step_count_that_is_silent(system, a, w, steps):
    fos, row = _cell(system, a, w)
    found = SC.check_step(fos, float(fos.period) / steps, row)
    assert found.unstable == 0 and found.inaccurate == 1
    need = _advised(found.warning("x"), r"(\d+) or more steps per drive period resolve it")
    # the warning's rate is the bound from above (rate_upper): the least count is counted
    # with it, and max|q| lies between the grid maximum and that bound
    assert found.rate <= found.rate_upper
    least = _least_steps(float(fos.period), found.rate_upper, found.harmonic, 1.0, 0.5,
                         drive_strict=False)
    assert need == least > steps
    assert SC.check_step(fos, float(fos.period) / need, row).inaccurate == 0
    assert SC.check_step(fos, float(fos.period) / (need - 1), row).inaccurate == 1
