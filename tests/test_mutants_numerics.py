"""Tests that close gaps mutation testing found in the numerics proof steps (docs/mutation.md):
the RK4 step check's advice (the number of steps per period it asks for), a grid of cells
checked as its cells one by one, more cells than one chunk, the limits of the step check and
of the sweep's criteria at exact equality.

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


def _need(found):
    """The advice of a StepCheck: (kind, N) or None."""
    if found.refusal("x"):
        return "refused", _advised(found.refusal("x"), r"ask for at least (\d+) steps")
    if found.warning("x"):
        return "warned", _advised(found.warning("x"), r"(\d+) or more steps per drive period")
    return None


HILL = S.SystemSpec("rod", drive="a*cos(omega*t) + a*cos(2*omega*t)")
# rows that are not a product grid: a stiff undriven cell next to mild driven ones, so that
# the cell of the largest stiffness is not the cell of the fastest drive
# (at 8 steps per period the undriven (0, 2.5), sqrt(max|q|) = 5, is warned about and asks for
# 16 steps, more than the 13 of the drive's harmonic cos 2 tau)
ROWS = [(0.0, 0.9), (0.02, 0.05), (0.3, 0.2), (0.0, 0.0), (0.05, 0.6), (0.0, 2.5)]
# without the two stiffest cells: at one step per period of the two-harmonic drive the aliased
# cells need 3 steps and the stiff undriven (0, 0.9) only 2, though it is refused too
MILD_ROWS = [ROWS[k] for k in (0, 1, 3, 4)]


@pytest.mark.parametrize("cells", [ROWS, MILD_ROWS])
@pytest.mark.parametrize("system", [S.SystemSpec("rod"), HILL])
@pytest.mark.parametrize("steps", [1, 2, 3, 5, 8, 13, 20])
def test_many_cells_are_checked_as_each_cell_alone(system, steps, cells):
    # the counts of a grid are the sums of its cells checked one by one, and its advice is the
    # least step count that every cell accepts (refusal) or leaves silent (warning)
    fos, _ = _cell(system, 0.0, 0.0)
    rows = [[{"a_over_l": a, "w0_over_w": w}[s.name] for s in fos.params] for a, w in cells]
    period = float(fos.period)
    grid = SC.check_step(fos, period / steps, rows)
    alone = [SC.check_step(fos, period / steps, [r]) for r in rows]
    assert grid.cells == len(rows)
    assert grid.unstable == sum(c.unstable for c in alone)
    assert grid.inaccurate == sum(c.inaccurate for c in alone)
    advice = _need(grid)
    if advice is None:
        assert all(_need(c) is None for c in alone)
        return
    kind, need = advice
    field = "unstable" if kind == "refused" else "inaccurate"
    assert need == max(_need(c)[1] for c in alone if _need(c) and _need(c)[0] == kind)
    assert not any(getattr(SC.check_step(fos, period / need, [r]), field) for r in rows)
    assert any(getattr(SC.check_step(fos, period / (need - 1), [r]), field) for r in rows)
    # the worst cell reported is one whose own advice is the grid's
    worst = [grid.worst[s.name] for s in fos.params]
    assert _need(SC.check_step(fos, period / steps, [worst])) == advice


def test_more_cells_than_one_chunk_are_all_checked():
    # CHUNK (4096) cells are evaluated together: 2 CHUNK + 5 cells, the only stiff one last
    fos, _ = _cell(S.SystemSpec("rod", angle="down"), 0.0, 0.0)
    n = 2 * SC.CHUNK + 5
    rows = np.zeros((n, len(fos.params)))
    rows[:, [s.name for s in fos.params].index("w0_over_w")] = 0.01
    rows[-1, [s.name for s in fos.params].index("w0_over_w")] = 3.0   # |q| = 36
    found = SC.check_step(fos, float(fos.period) / 6, rows)
    assert found.unstable == 1 and found.worst["w0_over_w"] == 3.0
    assert found.rate == pytest.approx(6.0, rel=1e-13)


def test_the_limits_hold_as_written_at_equality():
    # the module's rule: refused for h sqrt(max|q|) > 2 sqrt(2) (at the limit |R(iy)| = 1: no
    # growth) and h r >= 2 pi; warned for h sqrt(max|q|) > 1 and h r > 1/2.  Products that
    # are exactly the limits in binary: |q| = 4 (rate 2, no drive) with h = sqrt(2) and 1/2,
    # and r = 2 with h = 1/4 (rate small).
    down, _ = _cell(S.SystemSpec("rod", angle="down"), 0.0, 1.0)
    row = [[{"a_over_l": 0.0, "w0_over_w": 1.0}[s.name] for s in down.params]]
    at = SC.check_step(down, SC.RK4_IMAGINARY_LIMIT / 2, row)
    assert at.rate == 2.0 and at.dt * at.rate == SC.RK4_IMAGINARY_LIMIT
    assert (at.unstable, at.inaccurate) == (0, 1)
    at = SC.check_step(down, 0.5, row)
    assert at.rate_upper == 2.0 and (at.unstable, at.inaccurate) == (0, 0)
    rod, _ = _cell(S.SystemSpec("rod"), 0.0, 0.0)
    row = [[{"a_over_l": 1e-6, "w0_over_w": 0.0}[s.name] for s in rod.params]]
    at = SC.check_step(rod, 0.25, row)
    assert at.harmonic == 2.0 and at.dt * at.harmonic == 0.5 and at.dt * at.rate_upper < 1
    assert (at.unstable, at.inaccurate) == (0, 0)


def test_the_sweep_criteria_are_strict_at_their_thresholds():
    # "theta medio menor que 0.1" (000 sec. 4): a mean of exactly 0.1 is not stable, nor a
    # mean |theta| of 0.1, nor a run that reaches |theta| = pi/2 (the horizontal)
    stats = {"mean_theta": [0.1, -0.1, np.nextafter(0.1, 0)],
             "mean_abs_theta": [0.1, np.nextafter(0.1, 0), 0.0],
             "max_abs_theta": [math.pi / 2, np.nextafter(math.pi / 2, 0), 0.0]}
    assert list(S.verdict("mean", stats)) == [False, False, True]
    assert list(S.verdict("mean-abs", stats)) == [False, True, True]
    assert list(S.verdict("bounded", stats)) == [False, True, True]
