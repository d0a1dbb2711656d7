"""The proof steps of the double-precision band edges and of the stability map, each fed a
wrong candidate: a perturbed value, a swapped pair, a value past the truncation, a table
with a missing edge, a cell next to an edge.  Each test must see the step refuse (an
exception, a NaN width, the candidate replaced) or flag (a cell left to the exact verdict,
a warning).

Reference values: the characteristic values a_n(q), b_n(q) as eigenvalues of the four
symmetric tridiagonal matrices of DLMF 28.4.5-28.4.8 (recurrences for the Fourier
coefficients of ce_n, se_n), built here from the DLMF text, truncated to 30 rows and solved
by mpmath.eigsy at 30 digits; the neglected tail changes them by far less than 1e-25 for
|q| <= 5 and values below 40 (the eigenvector components decay like q^j/(j!)^2).  This is
neither the double-precision Newton nor the Sturm counts under test.
"""

import math
import warnings
from functools import lru_cache

import mpmath
import numpy as np
import pytest

from pendulab.analyses.floquet import _bands as B
from pendulab.analyses.floquet import _vectorised as V
from pendulab.analyses.stability_map import _classify
from pendulab.errors import AccuracyWarning, PrecisionError


@lru_cache(maxsize=None)
def reference_family(family, q, rows=30, dps=30):
    """Sorted eigenvalues (mpf) of the DLMF 28.4 matrix of ``family`` at q (30 rows, 30 digits).

    a_even: a_{2j}, diagonal (2j)^2, off-diagonal q with sqrt(2) q in the first place
    (DLMF 28.4.5 symmetrised); a_odd: a_{2j+1}, diagonal (2j+1)^2 with 1 + q first
    (28.4.6); b_odd: b_{2j+1}, 1 - q first (28.4.7); b_even: b_{2j+2}, (2j+2)^2 (28.4.8)."""
    with mpmath.workdps(dps):
        qm = mpmath.mpf(q)
        first = {"a_even": 0, "a_odd": 1, "b_odd": 1, "b_even": 2}[family]
        M = mpmath.zeros(rows)
        for j in range(rows):
            M[j, j] = mpmath.mpf(2 * j + first) ** 2
            if j + 1 < rows:
                M[j, j + 1] = M[j + 1, j] = qm
        if family == "a_even":
            M[0, 1] = M[1, 0] = mpmath.sqrt(2) * qm
        elif family == "a_odd":
            M[0, 0] += qm
        elif family == "b_odd":
            M[0, 0] -= qm
        ev = mpmath.eigsy(M, eigvals_only=True)
        return tuple(sorted(ev[i] for i in range(rows)))


def reference_values(q, top):
    """All characteristic values a_n(|q|), b_n(|q|) below top, sorted (mpf)."""
    out = []
    for fam in B.FAMILIES:
        out += [v for v in reference_family(fam, abs(float(q))) if v < top]
    return sorted(out)


# ---------------------------------------------------------------------------
# Sturm counts at the working precision (_bands._edge_count, the band index of
# characteristic_exponent)
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("q", [0.7, 2.5])
def test_edge_count_steps_by_one_across_each_reference_value(q):
    # theta0 = e_k -+ 1e-20 must count k and k + 1 values below it: a count that is off by
    # one (a shifted index) or does not see the off-diagonal (q = 0 counts) fails here
    vals = reference_values(q, 30)
    assert len(vals) >= 8
    with mpmath.workdps(30):
        for k, e in enumerate(vals):
            eps = mpmath.mpf(10) ** -20
            assert B._edge_count(e - eps, mpmath.mpf(-q), 30) == k, (q, k)
            assert B._edge_count(e + eps, mpmath.mpf(-q), 30) == k + 1, (q, k)


def test_sturm_count_of_one_family_against_the_reference():
    # the b_odd matrix at q = 2.5: between consecutive eigenvalues the count is their index
    q = 2.5
    ref = reference_family("b_odd", q)
    with mpmath.workdps(30):
        d, e2 = B._family_diagonals("b_odd", mpmath.mpf(q), 30, mpmath.mpf(1))
        for k in range(6):
            mid = (ref[k] + ref[k + 1]) / 2
            assert B._sturm_count(d, e2, mid) == k + 1
            assert B._sturm_count(d, e2, ref[k] - mpmath.mpf(10) ** -22) == k


# ---------------------------------------------------------------------------
# The certificate of one certified value (_vectorised._newton_certify)
# ---------------------------------------------------------------------------

def _one_column(family, q, j, n=15):
    cf = np.array([B.FAMILIES.index(family)])
    qq = np.array([float(q)])
    cj = np.array([j])
    return cf, qq, cj, n


def _delta(x, q):
    """The first delta of _newton_certify: 1e-13 max(1, |x|) + 4 eta."""
    return 1e-13 * max(1.0, abs(x)) + 4.0 * float(V._count_eta(np.array([q]))[0])


@pytest.mark.parametrize("family,q,j", [("a_even", 1.5, 1), ("b_odd", 3.0, 2), ("a_odd", 0.7, 0)])
@pytest.mark.parametrize("side", [+1, -1])
def test_a_perturbed_value_is_not_certified(monkeypatch, family, q, j, side):
    # The candidate is the true value moved by 4 delta; Newton is switched off so that the
    # certificate sees the candidate itself.  It must refuse it and fall back to the LAPACK
    # value (within delta of the reference); a certificate with a 10x wider delta would take
    # the candidate.  +: caught by the count at x - delta, -: by the count at x + delta.
    monkeypatch.setattr(V, "_newton_eigen", lambda d, e2, x, iters=8: np.array(x, float))
    true = float(reference_family(family, q)[j])
    cand = true + side * 4.0 * _delta(true, q)
    cf, qq, cj, n = _one_column(family, q, j)
    x, w = V._newton_certify(cf, qq, cj, np.array([cand]), n)
    assert abs(x[0] - cand) > 3.0 * _delta(true, q)          # the candidate was replaced
    assert abs(x[0] - true) <= w[0] and np.isfinite(w[0])     # by a value it proves


def test_a_swapped_pair_is_not_certified(monkeypatch):
    # the values of indices 1 and 2 of a_odd at q = 3 handed over in the wrong order
    monkeypatch.setattr(V, "_newton_eigen", lambda d, e2, x, iters=8: np.array(x, float))
    q = 3.0
    ref = [float(v) for v in reference_family("a_odd", q)[:3]]
    cf = np.array([1, 1])
    qq = np.array([q, q])
    cj = np.array([1, 2])
    x, w = V._newton_certify(cf, qq, cj, np.array([ref[2], ref[1]]), 15)
    assert np.all(np.abs(x - np.array([ref[1], ref[2]])) <= w)


def test_a_value_no_route_can_prove_leaves_a_nan_width(monkeypatch):
    # Newton and LAPACK both hand over the value moved by 5 times the second (wider) delta,
    # 1e-9 max(1, |x|): nothing is proved, the width is NaN
    import scipy.linalg

    q, j = 1.5, 1
    true = float(reference_family("a_even", q)[j])
    off = 5e-9 * max(1.0, abs(true))
    monkeypatch.setattr(V, "_newton_eigen", lambda d, e2, x, iters=8: np.array(x, float))
    monkeypatch.setattr(scipy.linalg, "eigvalsh_tridiagonal",
                        lambda *a, **k: np.array([true + off]))
    cf, qq, cj, n = _one_column("a_even", q, j)
    x, w = V._newton_certify(cf, qq, cj, np.array([true + off]), n)
    assert np.isnan(w[0])


def test_a_value_past_the_truncation_is_not_certified(monkeypatch):
    # Two rows of the a_even matrix at q = 5: its upper eigenvalue 9.35 is not a_2(5) = 7.45
    # (reference), since the neglected rows (diagonal 16, 36, ...; Gershgorin >= 16 - 2q = 6)
    # reach below it.  With the tail coupling left out of the lower count (_sided switched
    # off), only the tail bound x + delta + eta < (2n)^2 - 2|q| stands between it and a
    # certificate: it must refuse.
    monkeypatch.setattr(V, "_sided", lambda d, fams, q, side: d.copy())
    q = 5.0
    d, e2 = V._family_rows(np.array([0]), np.array([q]), 2)
    from scipy.linalg import eigvalsh_tridiagonal
    top2 = float(eigvalsh_tridiagonal(d[:, 0], np.sqrt(e2[:, 0]))[1])
    assert abs(top2 - float(reference_family("a_even", q)[1])) > 1.0
    x, w = V._newton_certify(np.array([0]), np.array([q]), np.array([1]), np.array([top2]), 2)
    assert np.isnan(w[0])


# ---------------------------------------------------------------------------
# The table of certified values (_vectorised._certify_edges)
# ---------------------------------------------------------------------------

QS = np.array([0.5, 1.5, 3.0])
TOP = 20.0


def test_the_table_holds_each_reference_value_once():
    E, W = V._certify_edges(QS, TOP)
    for i, q in enumerate(QS):
        ref = [float(v) for v in reference_values(q, TOP)]
        got = E[i][np.isfinite(E[i])]
        assert got.size == len(ref)
        assert np.all(np.abs(got - np.array(ref)) <= W[i][: got.size])
        assert np.all(W[i][: got.size] < 1e-11)


def test_a_table_that_misses_an_edge_is_refused(monkeypatch):
    # The predictor (numpy.linalg.eigvalsh on the stacked matrices) loses the largest
    # value below TOP of the b_even family (b_4 = 16.0x): that curve is never followed, and
    # the count at TOP (one more value than the table keeps) must refuse the table.
    real = np.linalg.eigvalsh

    def lose_one(A):
        vals = np.array(real(A))
        fam = np.repeat(np.arange(4), QS.size)
        for c in np.nonzero(fam == 3)[0]:
            below = np.nonzero(vals[c] <= TOP)[0]
            vals[c, below[-1]] = np.inf
        return vals
    monkeypatch.setattr(np.linalg, "eigvalsh", lose_one)
    with pytest.raises(PrecisionError, match="could not certify"):
        V._certify_edges(QS, TOP)


def test_a_table_with_an_uncertified_value_is_refused(monkeypatch):
    # every value handed over wrong by 5e-9 relative (Newton and LAPACK): refused as a whole
    import scipy.linalg

    real = scipy.linalg.eigvalsh_tridiagonal
    monkeypatch.setattr(V, "_newton_eigen", lambda d, e2, x, iters=8: np.array(x, float) + 5e-8)
    monkeypatch.setattr(scipy.linalg, "eigvalsh_tridiagonal",
                        lambda *a, **k: real(*a, **k) * (1 + 5e-9) + 5e-9)
    with pytest.raises(PrecisionError, match="could not certify"):
        V._certify_edges(QS, TOP)


def test_sturm_count_vec_against_the_reference():
    # the float count between and just beside reference values (1e-12 away: beyond the
    # rounding bound eta ~ 1e-15 |q| of _count_eta, so the count is exact there)
    q = np.array([3.0])
    d, e2 = V._family_rows(np.array([2]), q, 15)
    ref = [float(v) for v in reference_family("b_odd", 3.0)[:6]]
    for k, v in enumerate(ref):
        assert V._sturm_count_vec(d, e2, np.array([v - 1e-12]))[0] == k
        assert V._sturm_count_vec(d, e2, np.array([v + 1e-12]))[0] == k + 1


# ---------------------------------------------------------------------------
# The stability map's cells (stability_map._classify)
# ---------------------------------------------------------------------------

def _ref_parity(t0, q):
    return sum(1 for v in reference_values(q, 40) if v < t0) % 2 == 1


@pytest.mark.parametrize("separable", [True, False])
def test_cells_beside_an_edge_go_to_the_exact_verdict(separable):
    # Rows at b_1(1.5) + 0.3 w (w the cell's bound), just below a_1(1.5) beyond its certified
    # width but within the widening for the rounding of theta0 and theta1, and 3 w away from
    # a_2(1.5) (outside), plus plain rows; 4 columns, 7 rows (not square, rows not sorted).
    # The cells within the bound must be listed; a bound 10x wider would list the one 3 w
    # away too.  The other verdicts are the reference parity.
    q = np.array([0.5, 1.5, 3.0, 1.5])
    ref = [float(v) for v in reference_values(1.5, 40)]
    # the bound of _classify: certified width + 32 u (|edge| + 2.5 |q|); measured, not typed
    E, W = V._certify_edges(np.array([1.5]), 25.0)
    bound = {}
    for e, w in zip(E[0], W[0]):
        if np.isfinite(e):
            bound[round(e, 6)] = (w, 32 * V._U * (abs(e) + 2.5 * 1.5))

    def b(v):
        return sum(bound[round(v, 6)])
    b1, a1, a2 = ref[1], ref[2], ref[4]   # b_1, a_1, then a_2 (b_2 is ref[3])
    # the row next to a_1 lies beyond the certified width, within the widening for the
    # rounding of theta0 and theta1
    w_a1, extra_a1 = bound[round(a1, 6)]
    rows = np.array([9.5, b1 + 0.3 * b(b1), -3.0, a1 - (w_a1 + 0.5 * extra_a1), 0.25,
                     a2 + 3.0 * b(a2), 12.0])
    th0 = rows[:, None]
    th1 = -q[None, :]
    shape = (rows.size, q.size)
    if not separable:
        th0, th1 = np.broadcast_to(th0, shape).copy(), np.broadcast_to(th1, shape).copy()
    out, cells = _classify(th0, th1, shape)
    for j in (1, 3):
        assert (1, j) in cells and (3, j) in cells
        assert (5, j) not in cells
    for i, t in enumerate(rows):
        for j, qq in enumerate(q):
            if (i, j) not in cells:
                assert out[i, j] == _ref_parity(t, qq), (i, j)


def test_cells_on_an_edge_at_other_columns_are_not_listed():
    # the row 1e-15 above b_1(1.5) is far from every edge at |q| = 0.5 and 3: listed only
    # in the column of |q| = 1.5
    q = np.array([0.5, 1.5, 3.0])
    b1 = float(reference_values(1.5, 40)[1])
    rows = np.array([b1 + 1e-15, 2.0])
    out, cells = _classify(rows[:, None], -q[None, :], (2, 3))
    assert (0, 1) in cells and (0, 0) not in cells and (0, 2) not in cells
    assert out[0, 0] == _ref_parity(b1, 0.5) and out[0, 2] == _ref_parity(b1, 3.0)


# ---------------------------------------------------------------------------
# is_stable's resolution warning
# ---------------------------------------------------------------------------

def test_is_stable_warns_only_within_its_resolution():
    # rtol 1e-12 scaled by max(1, |theta0|)(1 + q): a point 0.3 of it from a_1(1.5) warns,
    # one 3 of it away does not (a 10x looser rtol would warn there too)
    q = 1.5
    a1 = float(reference_values(q, 40)[2])
    scale = 1e-12 * max(1.0, abs(a1)) * (1 + q)
    with pytest.warns(AccuracyWarning, match="1 point"):
        V.is_stable(np.array([a1 + 0.3 * scale, 0.3]), -q)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        v = V.is_stable(np.array([a1 + 3 * scale, a1 - 3 * scale]), -q)
    assert list(v) == [_ref_parity(a1 + 1e-9, q), _ref_parity(a1 - 1e-9, q)]


# ---------------------------------------------------------------------------
# The gap route of exponent(): the edge's own trace must be +-1
# ---------------------------------------------------------------------------

def test_a_gap_point_whose_edge_trace_is_off_is_answered_otherwise(monkeypatch):
    # theta0 = 0.5, theta1 = -1.5 lies in the first gap (b_1 = -0.73 < 0.5 < a_1 = 2.17 at
    # q = 1.5): lam = 1 + i mu from the traces at theta0 and at the nearer edge.  The trace at
    # the edge is handed over wrong by 3 EDGE_TRACE_TOL; the route must see that it is not
    # +-1 and answer the point otherwise, so that lam still agrees with the continued
    # fractions at 20 digits (a 10x looser tolerance would let mu move by ~1e-6).
    from pendulab.analyses.floquet import characteristic_exponent

    ref = complex(characteristic_exponent("0.5", "-1.5", dps=20, method="cf").lam)
    real = V._trace_half
    calls = []

    def edge_off(f0, f1, N0):
        calls.append(f0.size)
        y = real(f0, f1, N0)
        return y + 3.0 * V.EDGE_TRACE_TOL if len(calls) == 2 else y
    monkeypatch.setattr(V, "_trace_half", edge_off)
    lam = complex(V.exponent(np.array([0.5]), np.array([-1.5]))[0])
    assert len(calls) >= 2                    # the edge's trace was asked for
    assert abs(ref.real - 1.0) < 1e-15 and ref.imag > 0.1
    assert abs(lam - ref) < 1e-9, (lam, ref)


# ---------------------------------------------------------------------------
# Consumers of the table: a short table is not read past its end; listed cells are
# decided exactly
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("cut", ["columns", "one row"])
def test_a_table_short_of_the_index_asked_is_not_used(monkeypatch, cut):
    # theta0_of_exponent at integer nu (a_n(q)) for 20 distinct |q| reads the certified
    # table; handed a table that stops before the value asked (for every |q|, or +inf
    # padded for one |q|), it must fall back to LAPACK rather than read past the end
    from pendulab.analyses.floquet._vectorised import _theta0_of_exponent_array

    real = V._certify_edges

    def short(qs, top, nodes=40):
        E, W = real(qs, top, nodes)
        if cut == "columns":
            return E[:, :5], W[:, :5]
        E = E.copy()
        E[3, 5:] = np.inf
        return E, W
    monkeypatch.setattr(V, "_certify_edges", short)
    q = np.linspace(0.3, 3.0, 20)
    got = _theta0_of_exponent_array(np.full(q.size, 3.0), -q)    # a_3(q), sorted index 6
    for g, qq in zip(got, q):
        ref = float(reference_family("a_odd", float(qq))[1])      # a_3 = a_{2j+1}, j = 1
        assert abs(g - ref) < 1e-11 * max(1.0, abs(ref)), (qq, g, ref)


def test_listed_cells_take_the_exact_verdict(monkeypatch):
    # _classify's verdict of every listed cell is turned wrong; map_stability must replace
    # it by characteristic_exponent's on the exact values (the point mass: theta0 = -4 r^2,
    # theta1 = 2 a/l; 000 eqs. 5-6)
    from fractions import Fraction

    from pendulab.analyses import stability_map as SM
    from pendulab.analyses.floquet import characteristic_exponent

    real = SM._classify

    def wrong(th0, th1, shape):
        out, cells = real(th0, th1, shape)
        out = out.copy()
        for i, j in cells:
            out[i, j] = not out[i, j]
        return out, cells
    monkeypatch.setattr(SM, "_classify", wrong)
    r = 0.1
    lim = SM.stability_limits("0.1", 1, dps=30)
    cols = []
    for x in (float(lim[0]), float(lim[1])):
        cols += [x, np.nextafter(x, 0), np.nextafter(x, 1)]
    m = SM.stability_map(np.array(cols), np.array([r]))
    assert SM.map_stability.last_exact >= 4
    for j, a in enumerate(cols):
        ref = characteristic_exponent(-4 * Fraction(r) ** 2, 2 * Fraction(a)).stable
        assert m[0, j] == ref, (a, m[0, j], ref)


# ---------------------------------------------------------------------------
# theta0_of_exponent's polished double (_vectorised._theta0_of_exponent_polished)
# ---------------------------------------------------------------------------

@lru_cache(maxsize=None)
def reference_lambda(nu, theta1, k=0, half=20, dps=30):
    """lambda_nu: the k-th eigenvalue of J(nu) (diagonal (2n + nu)^2, off-diagonal theta1,
    |n| <= half; 000 eqs. 9-10 read as an eigenproblem in theta0) by mpmath.eigsy."""
    with mpmath.workdps(dps):
        nu, t1 = mpmath.mpf(nu), mpmath.mpf(theta1)
        size = 2 * half + 1
        M = mpmath.zeros(size)
        for i in range(size):
            M[i, i] = (2 * (i - half) + nu) ** 2
            if i + 1 < size:
                M[i, i + 1] = M[i + 1, i] = t1
        ev = mpmath.eigsy(M, eigvals_only=True)
        return sorted(ev[i] for i in range(size))[k]


NU, TH1 = 0.5, 1.25        # band 0, exact doubles


def test_polished_theta0_against_the_reference():
    v = V._theta0_of_exponent_polished(mpmath.mpf(NU), mpmath.mpf(TH1))
    ref = float(reference_lambda(NU, TH1))
    assert v is not None and abs(v - ref) <= 2e-16 * max(1.0, abs(ref))


@pytest.mark.parametrize("moved,refused", [(3e-10, True), (3e-11, False)])
def test_polished_theta0_refuses_a_double_root_far_from_its_refinement(monkeypatch, moved,
                                                                       refused):
    # the vectorised root handed over 3e-10 (refused: more than 1e-10 from where Newton in
    # mpmath lands) or 3e-11 (accepted, and the refined value is right) from the reference
    ref = float(reference_lambda(NU, TH1))
    monkeypatch.setattr(V, "_band_eigen", lambda *a, **k: np.array([ref + moved]))
    v = V._theta0_of_exponent_polished(mpmath.mpf(NU), mpmath.mpf(TH1))
    if refused:
        assert v is None
    else:
        assert v is not None and abs(v - ref) <= 2e-16 * max(1.0, abs(ref))


def test_polished_theta0_refuses_a_value_outside_its_band(monkeypatch):
    # the band handed over ends 0.01 below the true value; the double root is the true one,
    # so only the band check stands between the value and the caller
    ref = float(reference_lambda(NU, TH1))
    real = V._band_edges
    monkeypatch.setattr(V, "_band_edges",
                        lambda absq, k: (real(absq, k)[0], np.array([ref - 0.01])))
    monkeypatch.setattr(V, "_band_eigen", lambda *a, **k: np.array([ref]))
    assert V._theta0_of_exponent_polished(mpmath.mpf(NU), mpmath.mpf(TH1)) is None


def test_polished_theta0_refuses_two_precisions_that_disagree(monkeypatch):
    # the 30-digit refinement gets 3 rows, the 40-digit one 11: they disagree far beyond
    # 1e-22, and the value must be refused
    real = V._shifted_rows
    monkeypatch.setattr(V, "_shifted_rows",
                        lambda top, absq, digits=8: 3 if digits == 16 else real(top, absq, digits))
    assert V._theta0_of_exponent_polished(mpmath.mpf(NU), mpmath.mpf(TH1)) is None


# ---------------------------------------------------------------------------
# exponent(): a band thinner than its edges' rounding is not solved between them
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("q", [36.0, 50.0])
def test_a_band_thinner_than_its_rounding_is_answered_one_by_one(q):
    # The first band between a_0(q) and b_1(q) is 2.3e-10 (q = 36) and 2.8e-12 (q = 50) of
    # the scale max(1, |theta0|, |theta1|) wide, below THIN_BAND = 1e-9: the Newton route
    # between double edges would be off by ~5e-8 and ~4e-6 there (a 10x smaller THIN_BAND
    # sends the q = 36 point to it).  Reference: the continued fractions at 20 digits at the
    # exact double theta0 (lam moves by ~1e-5 per ulp of theta0 in so thin a band).
    from fractions import Fraction

    from pendulab.analyses.floquet import characteristic_exponent, mathieu_a, mathieu_b

    with mpmath.workdps(30):
        mid = (mathieu_a(0, q, dps=30) + mathieu_b(1, q, dps=30)) / 2
    x = float(mid)
    ref = complex(characteristic_exponent(Fraction(x), Fraction(-q), dps=20, method="cf").lam)
    assert 0.4 < ref.real < 0.6 and ref.imag == 0
    lam = complex(V.exponent(np.array([x, 0.3]), np.array([-q, -q]))[0])
    assert abs(lam - ref) < 1e-12, (lam, ref)


def test_an_edge_just_above_the_largest_theta0_still_lists_its_cell():
    # The largest row lies below a_1(1.5) by more than the edge's certified width but within
    # the widening for rounding: the table must reach past the largest theta0 far enough to
    # hold a_1, or that cell would not be listed
    E, W = V._certify_edges(np.array([1.5]), 25.0)
    a1 = float(reference_values(1.5, 40)[2])
    k = int(np.argmin(np.abs(E[0] - a1)))
    w, extra = W[0][k], 32 * V._U * (abs(a1) + 2.5 * 1.5)
    rows = np.array([0.5, a1 - (w + 0.5 * extra)])
    out, cells = _classify(rows[:, None], np.array([[-1.5, -0.5]]), (2, 2))
    assert (1, 0) in cells and (1, 1) not in cells


# ---------------------------------------------------------------------------
# The band Newton loops keep their bracket by a Sturm count (NumPy path)
# ---------------------------------------------------------------------------

# points inside the stable bands 0 to 3 at q = 1.5 (edges: reference_values) and band 2 at q = 3
BAND_POINTS = [(-0.8, -1.5), (3.0, -1.5), (7.0, -1.5), (12.0, -1.5), (10.0, -3.0)]


@pytest.mark.parametrize("end", [1e-9, 1.0 - 1e-9])
def test_band_exponent_from_a_guess_at_the_far_end_of_its_bracket(monkeypatch, end):
    # lam in (k, k + 1) from a first guess at k + 1e-9 or k + 1 - 1e-9: the Sturm count of
    # J(lam) - theta0 must keep each step in the bracket (with the bracket left open, steps
    # leave the band and land on another root).  Reference: the continued fractions at 20
    # digits.  The C kernel runs the same operations (tests/test_vectorised_ckernel.py).
    from fractions import Fraction

    from pendulab.analyses.floquet import characteristic_exponent

    monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
    monkeypatch.setattr(V, "_band_nu_guess", lambda th0, k, lo, hi: k.astype(float) + end)
    f0 = np.array([p[0] for p in BAND_POINTS])
    f1 = np.array([p[1] for p in BAND_POINTS])
    ref = np.array([complex(characteristic_exponent(Fraction(a), Fraction(b), dps=20,
                                                    method="cf").lam) for a, b in BAND_POINTS])
    assert np.all(ref.imag == 0)
    assert np.all(np.abs(V.exponent(f0, f1) - ref) < 1e-13)


@pytest.mark.parametrize("side", ["lo", "hi"])
def test_band_eigenvalue_from_a_guess_at_the_far_end_of_its_bracket(monkeypatch, side):
    # theta0_of_exponent's eigenvalue of J(nu) in band k from a first guess at an edge of
    # the band: the Sturm count keeps each step between the edges
    from pendulab.analyses.floquet._vectorised import _theta0_of_exponent_array

    monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
    monkeypatch.setattr(V, "_band_eigen_guess",
                        lambda nu, k, lo, hi: (lo if side == "lo" else hi).copy())
    nus = (0.5, 1.3, 2.7, 3.9)
    th1 = (1.25, -2.0, 3.0, 0.8)
    got = _theta0_of_exponent_array(np.array(nus), np.array(th1))
    for g, nu, t in zip(got, nus, th1):
        ref = float(reference_lambda(nu, t, k=int(nu)))
        assert abs(g - ref) < 1e-13 * max(1.0, abs(ref)), (nu, t, g, ref)


def test_an_overflowed_trace_is_answered_one_by_one():
    # theta0 = -6e4, theta1 = 1: |Im lam| = 245, the trace cosh(pi 245) overflows a double;
    # the gap route must not read lam from it.  Reference: 000 eqs. 9-10 kept to |n| <= 1,
    # theta0 - lam^2 = theta1^2 (1/C_1 + 1/C_-1) = -theta1^2/(2 mu^2) + O(theta1^4/mu^6) for
    # lam = i mu, so mu = sqrt(-theta0 - theta1^2/(2 (-theta0))) to ~1e-19 relative.
    t0, t1 = -6e4, 1.0
    mu = math.sqrt(-t0 - t1 * t1 / (2 * (-t0)))
    assert not np.isfinite(V.trace_monodromy(np.array([t0]), np.array([t1]))[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lam = complex(V.exponent(np.array([t0, -1.0]), np.array([t1, 0.5]))[0])
    assert lam.real == 0.0 and abs(lam.imag - mu) < 1e-12 * mu, (lam, mu)


def test_a_table_with_a_gap_in_its_indices_is_refused(monkeypatch):
    # At the first |q| the predictor loses a_10 (~100, index 5 of the a_even family) but
    # keeps a_12 (~144): both lie above TOP = 98 (so the count at TOP does not see the
    # loss) and below TOP + margin, where curves are followed.  The indices kept at that
    # |q| then skip one, and the table must be refused.
    top = 98.0
    real = np.linalg.eigvalsh

    def gap(A):
        vals = np.array(real(A))
        assert 99.0 < vals[0, 5] < 101.0 and 143.0 < vals[0, 6] < 145.0
        vals[0, 5] = np.inf          # column 0: the a_even family at QS[0]
        return vals
    monkeypatch.setattr(np.linalg, "eigvalsh", gap)
    with pytest.raises(PrecisionError, match="could not certify"):
        V._certify_edges(QS, top)


def test_a_refused_table_leaves_the_band_count_to_lapack(monkeypatch):
    # exponent() on 20 distinct |q| asks for a certified table; refused, it counts the
    # bands with LAPACK instead and still gives lam (reference: the continued fractions)
    from fractions import Fraction

    from pendulab.analyses.floquet import characteristic_exponent

    def refuse(qs, top, nodes=40):
        raise PrecisionError("refused for the test")
    monkeypatch.setattr(V, "_certify_edges", refuse)
    q = np.linspace(0.5, 2.4, 20)
    t0 = np.full(q.size, 3.0)
    lam = V.exponent(t0, -q)
    for i in (0, 7, 13, 19):
        ref = complex(characteristic_exponent(Fraction(3), Fraction(float(-q[i])), dps=20,
                                              method="cf").lam)
        assert abs(lam[i] - ref) < 1e-9, (q[i], lam[i], ref)


@pytest.mark.parametrize("order", ["ascending", "descending", "unsorted"])
def test_map_verdicts_for_rows_in_any_order(order):
    # the separable path reads its per-column counts back in the rows' order: ascending,
    # descending and any other order take three different ways back; 5 rows x 3 columns
    q = np.array([0.5, 1.5, 3.0])
    rows = np.array([-2.0, -0.8, 1.0, 3.0, 7.0])
    rows = {"ascending": rows, "descending": rows[::-1].copy(),
            "unsorted": rows[[2, 0, 4, 1, 3]]}[order]
    out, cells = _classify(rows[:, None], -q[None, :], (rows.size, q.size))
    assert cells == []
    ref = np.array([[_ref_parity(t, qq) for qq in q] for t in rows])
    assert ref.any() and not ref.all()
    assert np.array_equal(out, ref)


def test_edge_count_reaches_deep_enough_at_large_theta0():
    # q = 20, the values near theta0 = 400 (index ~40): the truncation of the four matrices
    # (the depth rules of _bands) must reach past them, or the count near the top falls
    # short.  a_20(20), b_20(20) and a_21(20), b_21(20) differ by 5e-20 and 6e-22 (the
    # reference), so each value is approached to a quarter of its distance to its neighbours.
    q = 20.0
    allv = reference_values(q, 450)
    k0 = len(reference_values(q, 380))
    assert len(allv) - k0 >= 3
    with mpmath.workdps(30):
        for k in range(k0, len(allv)):
            e = allv[k]
            gap = min(abs(e - allv[k - 1]), abs(allv[k + 1] - e) if k + 1 < len(allv) else 1)
            eps = min(mpmath.mpf(10) ** -20, gap / 4)
            assert B._edge_count(e - eps, mpmath.mpf(-q), 30) == k, k
            assert B._edge_count(e + eps, mpmath.mpf(-q), 30) == k + 1, k


@pytest.mark.parametrize("q", [5.0, 8.0, 20.0])
def test_a_value_above_every_row_within_the_widening_lists_its_cell(q):
    # The value e of smallest |e| at q (1.86 at q = 5, -0.39 at 8, 1.15 at 20), the only row
    # below it by more than its certified width but within the widening 32 u (|e| + 2.5 q):
    # the table must reach far enough above the largest theta0 for that widening (at large
    # q it exceeds 64 u |theta0|), or the cell is never decided exactly
    vals = [float(v) for v in reference_values(q, 10)]
    e = min(vals, key=abs)
    E, W = V._certify_edges(np.array([q]), e + 1.0)
    w = W[0][int(np.argmin(np.abs(E[0] - e)))]
    extra = 32 * V._U * (abs(e) + 2.5 * q)
    t0 = e - (w + 0.5 * extra)
    assert e - t0 > 64 * V._U * abs(t0) + w        # beyond the old reach of the table
    out, cells = _classify(np.array([[t0]]), np.array([[-q]]), (1, 1))
    assert cells == [(0, 0)]


def test_a_table_predicted_with_an_edge_twice_is_repaired(monkeypatch):
    # The predictor hands over a_4 (a_even index 2) in place of a_2 (index 1) as well, at
    # every |q| (Newton switched off, so the candidate stays): the certificate of index 1
    # refuses it, and the table that comes back holds each reference value once, not a_4
    # twice and a_2 never (swapped values, by contrast, come back sorted and are harmless)
    real = np.linalg.eigvalsh

    def swap(A):
        vals = np.array(real(A))
        fam = np.repeat(np.arange(4), QS.size)
        for c in np.nonzero(fam == 0)[0]:
            vals[c, 1] = vals[c, 2]
        return vals
    monkeypatch.setattr(np.linalg, "eigvalsh", swap)
    monkeypatch.setattr(V, "_newton_eigen", lambda d, e2, x, iters=8: np.array(x, float))
    E, W = V._certify_edges(QS, TOP)
    for i, q in enumerate(QS):
        ref = [float(v) for v in reference_values(q, TOP)]
        got = E[i][np.isfinite(E[i])]
        assert got.size == len(ref)
        assert np.all(np.abs(got - np.array(ref)) <= W[i][: got.size])
