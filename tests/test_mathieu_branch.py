"""Branch points of a_m(q), b_m(q) and the radii of convergence of their series (DLMF 28.6).

References: DLMF Table 28.6.1 (tests/data/dlmf_table_28_6_1.csv, with its provenance), and
for the rows the available copy of the table does not give, an independent method: along
q = i t the matrix of a_{2n} or b_{2n+2} is similar to a real one, its eigenvalues are real
until two of them meet, and the first t at which the m-th of them leaves the real line is
found by bisection on NumPy's eigenvalues (no determinant, no Newton, no series).
"""

import csv
import math
import pathlib

import mpmath
import numpy as np
import pytest

from pendulab.analyses import mathieu_branch as mb
from pendulab.analyses import mathieu_radii
from pendulab.analyses import series as se
from pendulab.analyses.series import parity_rows
from pendulab.errors import ConvergenceError, InputError

DATA = pathlib.Path(__file__).parent / "data" / "dlmf_table_28_6_1.csv"


def _dlmf_entries():
    """(n, j, printed text) of every entry DLMF Table 28.6.1 gives in the stored copy."""
    lines = [ln for ln in DATA.read_text().splitlines() if not ln.startswith("#")]
    out = []
    for row in csv.DictReader(lines):
        for j in (1, 2, 3):
            if row[f"rho{j}"]:
                out.append((int(row["n"]), j, row[f"rho{j}"]))
    return out


def _matches_printed(value, printed, truncated=False):
    """``value`` (decimal text) shows the printed digits: rounded, or cut (``truncated``)."""
    decimals = len(printed.split(".")[1])
    if truncated:
        return value.startswith(printed)
    with mpmath.workdps(40):
        return abs(mpmath.mpf(value) - mpmath.mpf(printed)) <= mpmath.mpf(10) ** (-decimals) / 2


#: the one entry whose last printed digit is not the rounding of the computed radius:
#: rho_6^(2) (b_14), printed 95.80595 67052, computed 95.8059567052603 (0.60 units of the
#: last place above it; the printed digits are its truncation)
LAST_DIGIT_OFF = {(6, 2)}


@pytest.mark.slow
def test_computed_radii_reproduce_every_digit_of_dlmf_table_28_6_1():
    """Each entry of DLMF Table 28.6.1 from the branch point computed afresh (not the shipped
    table): rows 0-7 rounded to the printed digits, row 8's first entry as far as printed;
    b_14's entry (LAST_DIGIT_OFF) truncated, and the next test shows the computed one right."""
    entries = _dlmf_entries()
    assert len(entries) == 22
    for n, j, printed in entries:
        kinds = mb.kinds_of_row(n)[j - 1]
        for kind in kinds[:1] if n else kinds + ((("a2",), ("b4",), ("a3",))[j - 1]):
            p = mb.branch_point(kind)
            assert p.text == mathieu_radii.BRANCH_POINTS[kind][0], kind     # the shipped table
            cut = n == 8 or (n, j) in LAST_DIGIT_OFF
            assert _matches_printed(p.text, printed, truncated=cut), (kind, p.text, printed)
            if not cut:
                assert not p.text.startswith(printed[:-1] + str((int(printed[-1]) + 1) % 10))


@pytest.mark.slow
def test_b14_is_double_at_the_computed_radius_and_not_at_the_printed_one():
    """rho_6^(2): at the branch point computed to 20 digits, mpmath.eig's eigenvalues of the
    truncated matrix (an independent method: QR at 30 digits, no determinant, no Newton) have
    a pair within 1e-8 of each other; at the same angle and DLMF's printed radius
    95.8059567052 the pair is about 1e-4 apart.  (NumPy's double eig cannot tell: near a
    double eigenvalue its own error is ~1e-4 here.)"""
    p = mb.branch_point("b14", digits=20)
    rows = parity_rows("b14", 22)          # frequencies 2 .. 44: s^2 >> |q| = 96 at the end

    def pair_gap(q):
        n = len(rows)
        M = mpmath.zeros(n, n)
        for i, (c, v, w) in enumerate(rows):
            M[i, i] = c + q * v
            if i:
                M[i, i - 1] = M[i - 1, i] = q * mpmath.sqrt(w)
        vals = sorted(mpmath.eig(M, left=False, right=False), key=lambda e: abs(e - p.a))
        return abs(vals[0] - vals[1])

    with mpmath.workdps(30):
        assert pair_gap(p.q) < 1e-8
        assert pair_gap(p.q * mpmath.mpf("95.8059567052") / abs(p.q)) > 5e-5


def _axis_collision(kind, t_hi, steps=400):
    """The first t in (0, t_hi) at which a_m (the eigenvalue of the class that starts at m^2)
    leaves the real line along q = i t: NumPy's eigenvalues of the real matrix similar to
    D + i t V (off-diagonal entries -t sqrt(W), t sqrt(W)), a_m followed by continuity on a grid of t, then
    bisection in the step where its nearest eigenvalue stops being real."""
    m = int(kind[1:])
    rows = parity_rows(kind, m // 2 + 60)

    def eigenvalues(t):
        n = len(rows)
        M = np.zeros((n, n))
        for i, (c, v, w) in enumerate(rows):
            assert v == 0                       # a_{2n}, b_{2n+2}: no diagonal term in q
            M[i, i] = c
            if i:
                M[i, i - 1], M[i - 1, i] = -t * math.sqrt(w), t * math.sqrt(w)
        return np.linalg.eigvals(M)

    def follow(value, t):
        vals = eigenvalues(t)
        near = vals[np.argmin(np.abs(vals - value))]
        return near.real, abs(near.imag) <= 1e-9 * abs(near)

    value, t0 = float(m * m), 0.0
    for k in range(1, steps + 1):
        t1 = t_hi * k / steps
        new, real = follow(value, t1)
        if not real:
            break
        value, t0 = new, t1
    else:
        raise AssertionError(f"{kind}: real up to t = {t_hi}")
    lo, hi = t0, t1
    for _ in range(50):
        mid = (lo + hi) / 2
        new, real = follow(value, mid)
        if real:
            lo, value = mid, new
        else:
            hi = mid
    return (lo + hi) / 2


@pytest.mark.parametrize("kind", ["a18", "b20", "a22", "b24"])
def test_rows_past_the_stored_table_by_an_independent_method(kind):
    """rho_9^(1) (a_18), rho_9^(2) (b_20) and two kinds of rows 10-11, whose nearest branch
    points lie on the imaginary axis: the shipped radius against the eigenvalues' bisection."""
    radius = float(mathieu_radii.BRANCH_POINTS[kind][0])
    assert mathieu_radii.BRANCH_POINTS[kind][1].startswith("0.0+")
    t = _axis_collision(kind, 1.05 * radius)
    assert abs(t - radius) <= 1e-8 * radius, (kind, t, radius)


def test_odd_kinds_mirror_each_other():
    """b_{2n+1}(q) = a_{2n+1}(-q) (DLMF 28.2.26): the same radius, the branch point mirrored;
    computed independently for each letter."""
    for m in (1, 5):
        pa, pb = mb.branch_point(f"a{m}"), mb.branch_point(f"b{m}")
        assert pa.text == pb.text
        assert abs(pa.q + mpmath.conj(pb.q)) < 1e-12 * pa.radius


def _table_point(kind):
    radius, q = mathieu_radii.BRANCH_POINTS[kind]
    return complex(q.replace("+-", "-"))


def test_the_certificate_accepts_the_branch_point_and_refuses_others():
    p = mb.branch_point("a4")
    assert mb.check_branch_point("a4", p.q, p.a) < 1e-15
    # q off the branch point by 1e-6 of it: Newton's correction is far above 1e-15
    with pytest.raises(ConvergenceError, match="not a branch point"):
        mb.check_branch_point("a4", p.q * (1 + 1e-6), p.a)
    # the right q with a wrong double value
    with pytest.raises(ConvergenceError, match="not a branch point"):
        mb.check_branch_point("a4", p.q, p.a + 1e-4)
    # a branch point of another class (b_2, b_4) is not one of a_4's class
    with pytest.raises(ConvergenceError):
        mb.check_branch_point("a4", _table_point("b4"), 11.1904736)
    # asked for more digits than the candidate carries
    with pytest.raises(ConvergenceError):
        mb.check_branch_point("a4", complex(p.q), complex(p.a), digits=25)
    with pytest.raises(ConvergenceError):
        mb.check_branch_point("a0", 0, 0)


def test_the_pair_test_refuses_separated_eigenvalues():
    """Newton's correction can be small where the two eigenvalues are still apart: the second
    test of the certificate is then the one that refuses."""
    p = mb.branch_point("a0", digits=30)
    with mpmath.workdps(40):
        # q off by 5e-21 of it: the correction (5e-21) passes at 20 digits, but the two
        # eigenvalues near a_b are c sqrt(5e-21 |q|) ~ 4e-10 apart, above 1e-10 |a_b| = 2.1e-10
        q = p.q * (1 + 5 * mpmath.mpf(10) ** -21)
        with pytest.raises(ConvergenceError, match="apart"):
            mb.check_branch_point("a0", q, p.a, digits=20)
        assert mb.check_branch_point("a0", p.q, p.a, digits=20) < 1e-25


def test_a_branch_point_of_the_class_off_the_sheet_is_not_taken():
    """a_2 and a_4 meet at 5.174 + 5.104 i (a_4's radius); a_0 follows its own path there."""
    p = mb.branch_point("a4")
    n = mb._size(0, 8.0)
    assert mb._on_sheet("a", 4, p.q, p.a, n)
    assert not mb._on_sheet("a", 0, p.q, p.a, n)


def test_the_shipped_table_is_reproduced():
    """pendulab/analyses/mathieu_radii.py holds what table_source computes: rows 0-2 afresh
    (the slow test above recomputes rows 0-9, whose texts must match too)."""
    for n in range(3):
        for col in mb.kinds_of_row(n):
            for kind in col:
                p = mb.branch_point(kind)
                radius, q = mathieu_radii.BRANCH_POINTS[kind]
                assert p.text == radius, kind
                assert abs(complex(q) - complex(p.q)) < 1e-12 * p.radius, kind
    assert mathieu_radii.DIGITS == mb.TABLE_DIGITS
    assert len(mathieu_radii.BRANCH_POINTS) == 4 * mb.TABLE_ROWS


def test_each_residue_of_m_mod_4_lies_on_one_smooth_curve():
    """The radii grow like m^2 (DLMF 28.6, after Table 28.6.1): within each letter and residue
    of m mod 4 the second differences of the shipped radii are constant to 1e-3 of them, which
    a missed nearer branch point (as the series' starts alone gave for b_32: 513.459 instead of
    512.128) breaks."""
    R = {k: float(v[0]) for k, v in mathieu_radii.BRANCH_POINTS.items()}
    for letter in "ab":
        for r in range(4):
            ms = [m for m in range(r, 33, 4) if f"{letter}{m}" in R and m >= 4]
            vals = [R[f"{letter}{m}"] for m in ms]
            second = [vals[i] - 2 * vals[i + 1] + vals[i + 2] for i in range(len(vals) - 2)]
            assert max(second) - min(second) < 1e-3 * max(second), (letter, r, second)


def test_bad_input_is_one_line():
    for bad in ("c3", "b0", "a", 3):
        with pytest.raises(InputError):
            mb.branch_point(bad)
    with pytest.raises(InputError, match="m <= 64"):
        mb.branch_point("a65")
    with pytest.raises(InputError, match="digits"):
        mb.branch_point("a0", digits=2)


def test_the_series_refuses_beyond_the_computed_radius():
    s = se.characteristic_series("a20", 4)
    assert s.radius == float(mathieu_radii.BRANCH_POINTS["a20"][0])
    assert s.radius_source == "computed branch point, beyond DLMF Table 28.6.1"
    assert se.characteristic_series("a4", 4).radius_source == "computed branch point, DLMF Table 28.6.1"
    with pytest.raises(Exception, match="beyond the radius of convergence 197.93787955"):
        s.evaluate(198.0)
    assert math.isfinite(s.evaluate(150.0)[0])


@pytest.mark.slow
def test_b32_recomputed_is_the_nearer_point_on_the_axis():
    """Row 15's b_32 afresh: the series' starts alone give a farther point (91.71 + 505.20 i,
    |q| = 513.459); the start extrapolated from b_20, b_24, b_28 finds the nearer one on the
    axis, which is the shipped radius."""
    p = mb.branch_point("b32")
    assert p.text == mathieu_radii.BRANCH_POINTS["b32"][0] == "512.128473373035"
    assert p.q.real == 0 and p.radius < 513
