"""The certified characteristic values behind the map (floquet._vectorised._certify_edges):
every returned interval holds exactly one characteristic value and none is missed.

Reference: mathieu_a / mathieu_b at 30 digits (continued fraction refined at the
working precision, two precisions compared; tested against DLMF 28.8.1 and
Zhang & Jin's table elsewhere), i.e. an independent route from the
double-precision Newton and Sturm counts under test.
"""

import mpmath
import numpy as np

from pendulab.analyses.floquet import mathieu_a, mathieu_b
from pendulab.analyses.floquet._vectorised import _certify_edges


def _all_values_below(q, top, dps=30):
    vals = []
    m = 0
    while True:
        a = mathieu_a(m, q, dps=dps)
        b = mathieu_b(m, q, dps=dps) if m >= 1 else None
        low = [v for v in (a, b) if v is not None and v < top]
        vals += low
        if min(v for v in (a, b) if v is not None) > top and m > 1:
            return sorted(vals)
        m += 1


def test_every_value_in_exactly_one_interval():
    # many |q| (the predictor interpolates between 40 nodes), theta0 up to 30
    qs = np.concatenate([[0.0, 1e-7], np.linspace(0.05, 40.0, 97)])
    top = 30.0
    edges, width = _certify_edges(qs, top)
    for i in range(0, qs.size, 7):
        q = mpmath.mpf(float(qs[i]))
        ref = _all_values_below(q, top)
        got = edges[i][np.isfinite(edges[i])]
        w = width[i][np.isfinite(edges[i])]
        inside = [x for x in got if x - 0 <= top]
        assert len(inside) >= len(ref)
        for v in ref:
            hits = np.nonzero(np.abs(got - float(v)) <= w)[0]
            assert hits.size >= 1, (float(qs[i]), float(v))
        # no interval without a value (those above top are dropped)
        for x, wx in zip(got, w):
            assert any(abs(float(v) - x) <= wx for v in ref) or x - wx > top - 1e-9


def test_large_q_values_and_their_widths():
    qs = np.array([100.0, 1000.0, 2500.0])
    edges, width = _certify_edges(qs, 0.0)
    for i, q in enumerate(qs):
        got = edges[i][np.isfinite(edges[i])]
        # a_0 and b_1 at |q| = 2500 differ by ~exp(-200) (DLMF 28.8.2): two values, one double
        assert abs(got[0] - float(mathieu_a(0, q, dps=30))) <= width[i][0]
        assert abs(got[1] - float(mathieu_b(1, q, dps=30))) <= width[i][1]
        # delta = 1e-13 max(1, |x|) plus the rounding bounds 6 x 16 u |q|
        assert np.all(width[i][np.isfinite(edges[i])] <= 1.2e-13 * np.maximum(1, np.abs(got)) + 1.1e-13 * q)
