"""Speed and memory of the perturbation series; run: python benchmarks/bench_series.py

Prints, from one run in one process:

* the time and peak memory (tracemalloc) of alpha_2..alpha_N and every c_n, s_n
  up to N = 40 (target: <= 5 s, < 500 MB), all in lowest terms;
* the time of a straightforward SymPy implementation of the source's method
  (generic expressions, ``cancel`` of every coefficient at every order; 000
  eqs. 24-26) at order 20, next to ours at
  order 20, and their ratio (target: >= 50);
* the time to write the order-40 series as the product does (JSON through
  SymPy, and LaTeX);
* the time to extend the series to order 100 (must complete), unless
  ``--quick`` is given.

Options: ``--quick`` (skip order 100), ``--naive-order N`` (default 20),
``--naive-budget S`` (default 600): the naive route needs hours for order 20
(cancel re-expands ever larger products), so it stops starting new orders after
S seconds and the ratio printed is then a lower bound, with the ratio at the
order it did reach beside it.
"""

import argparse
import gc
import os
import resource
import sys
import time
import tracemalloc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import sympy as sp  # noqa: E402

from pendulab.analyses import series as se  # noqa: E402


def naive_series(order, budget=None, log=None):
    """The source's procedure with generic SymPy expressions (000 eqs. 24-26), order by order.

    c_n is a dict k -> SymPy expression (coefficient of cos((nu + 2k) tau)); the
    product 2 cos 2tau c_{n-1} is spread by 000 eq. 26, the sum over alpha_m c_{n-m}
    added as expressions, and every coefficient is brought to lowest terms with
    ``cancel`` at every order.  (Keeping c_n as one trigonometric expression and
    using ``TR8`` and ``.coeff`` instead is slower still: 150 s at order 12.)
    """
    nu = sp.Symbol("nu")
    alpha = {1: sp.Integer(0)}
    c = {0: {0: sp.Integer(1)}}
    t0 = time.perf_counter()
    for n in range(1, order + 1):
        if budget is not None and time.perf_counter() - t0 > budget:
            break
        known = {}
        for k, v in c[n - 1].items():
            for kk in (k - 1, k + 1):
                known[kk] = known.get(kk, 0) + v
        for m in range(2, n):
            if alpha[m] != 0:
                for k, v in c[n - m].items():
                    known[k] = known.get(k, 0) + alpha[m] * v
        alpha[n] = sp.cancel(-known.pop(0, 0)) if n > 1 else sp.Integer(0)
        c[n] = {k: sp.cancel(v / (4 * k * (nu + k))) for k, v in known.items()}
        c[n] = {k: v for k, v in c[n].items() if v != 0}
        if log is not None:
            log(n, time.perf_counter() - t0)
    return nu, alpha, c


def _fresh_engine():
    """A new, empty series engine (so timings never reuse earlier orders)."""
    se._ENGINE = se._Engine()


def timed(fn):
    gc.collect()
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip the order-100 extension")
    ap.add_argument("--naive-order", type=int, default=20)
    ap.add_argument("--naive-budget", type=float, default=600.0,
                    help="seconds after which the naive route stops starting new orders "
                         "(it needs hours for order 20; use a large value to let it finish)")
    args = ap.parse_args(argv)

    # correctness first: the naive route and ours agree exactly at a low order
    nu_n, alpha_n, c_n = naive_series(6)
    _fresh_engine()
    s6 = se.mathieu_series(6)
    for n in range(1, 7):
        from pendulab.symbols import nu as nu_sym
        ours = s6.alpha[n].subs(nu_sym, nu_n)
        assert sp.cancel(ours - alpha_n[n]) == 0, n
    print("check: naive and fast series agree exactly to order 6")

    # order 40: time (no tracing), then peak memory in a second, traced run
    _fresh_engine()
    t40, s40 = timed(lambda: se.mathieu_series(40))
    _fresh_engine()
    tracemalloc.start()
    se.mathieu_series(40)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    deg = s40.alpha_raw[40].degree()
    print(f"order 40: {t40:.3f} s, peak traced memory {peak / 2**20:.1f} MB "
          f"(alpha_40: numerator degree {deg[0]}, denominator degree {deg[1]}; "
          f"{sum(len(r) for r in s40.c_raw.values())} coefficients of c_n, all in lowest terms)")

    # what the product adds at order 40: SymPy expressions, their strings, the LaTeX
    from pendulab.io import canonical_json
    from pendulab.products import series as product
    t_json, text = timed(lambda: canonical_json(product.record("nu", 40)))
    t_tex, tex = timed(lambda: product.latex_text(["nu"], 40))
    print(f"order 40 as the product writes it: JSON {t_json:.1f} s ({len(text) / 1e6:.1f} MB), "
          f"LaTeX {t_tex:.1f} s ({len(tex) / 1e6:.1f} MB), both from the series already computed")

    # ours vs naive at the naive order
    N = args.naive_order
    _fresh_engine()
    t_fast, _ = timed(lambda: se.mathieu_series(N))
    fast_at = {}
    for n in range(2, N + 1):
        _fresh_engine()
        fast_at[n], _ = timed(lambda: se.mathieu_series(n))
    naive_at = {}
    t_naive, (nu_n, alpha_n, _) = timed(lambda: naive_series(
        N, budget=args.naive_budget, log=lambda n, t: naive_at.__setitem__(n, t)))
    from pendulab.symbols import nu as nu_sym
    reached = max(alpha_n)
    assert sp.cancel(se.mathieu_series(reached).alpha[reached].subs(nu_sym, nu_n) - alpha_n[reached]) == 0
    print("naive SymPy, cumulative seconds by order: "
          + ", ".join(f"{n}: {t:.2f}" for n, t in sorted(naive_at.items())))
    if reached == N:
        print(f"order {N}: ours {t_fast:.4f} s, naive SymPy {t_naive:.1f} s, ratio {t_naive / t_fast:.0f}x")
    else:
        print(f"order {N}: ours {t_fast:.4f} s; naive SymPy stopped by the {args.naive_budget:.0f} s budget "
              f"after order {reached} ({naive_at[reached]:.1f} s), so the ratio at order {N} is at least "
              f"{naive_at[reached] / t_fast:.0f}x; at order {reached} itself: ours {fast_at[reached]:.4f} s, "
              f"ratio {naive_at[reached] / fast_at[reached]:.0f}x")

    if not args.quick:
        _fresh_engine()
        se.mathieu_series(40)
        t100, s100 = timed(lambda: se.mathieu_series(100))
        deg = s100.alpha_raw[100].degree()
        print(f"order 100 (extending order 40): {t100:.1f} s "
              f"(alpha_100: numerator degree {deg[0]}, denominator degree {deg[1]})")
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak resident memory of the whole run: {rss:.0f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
