"""The exact series engines beside expert baselines; run: python benchmarks/bench_series_engines.py

Prints, from one run in one process, CPU time (time.process_time; python-flint
runs single-threaded), each figure beside its baseline and the ratio
baseline / ours:

* a_0(q) to q^100 and q^200 (DLMF 28.6.1), ours (Newton's iteration on the
  truncated Hill determinant, :class:`pendulab.analyses.series._CharEngine`)
  against a python-flint baseline written here: Newton's iteration on the
  continued fraction a = 2q^2/(a - 4 - q^2/(a - 16 - q^2/(a - 36 - ...)))
  (DLMF 28.6 / the recurrence of DLMF 28.4.5) in fmpq power series; and the
  previous engine (Rayleigh-Schroedinger in Fractions, also written here).
  Medians of 3 (the previous engine at q^200: one run).  Target: ours <= 0.4 s
  at q^200 and not slower than the flint baseline.
* the non-integer series alpha_n, c_n (000 eqs. 20-24) from scratch to order
  60 and 100, ours (fmpz_poly numerators) against the previous engine
  (Kronecker substitution in CPython integers, written here: the same
  recursion, the arithmetic of pendulab 0.2.0); target: order 100 in <= 60 s.
  The previous engine at order 100 takes 7-9 minutes, so it runs only with
  ``--full``.
* order 150 from scratch, ours (must complete), unless ``--quick``.

Every pair of routes is checked to give identical exact results before its
times are printed.

Options: ``--quick`` (skip order 150), ``--full`` (also the previous engine at
order 100 and its q^200 run is then the median of 3), ``--skip-old`` (no
previous-engine runs at all).
"""

import argparse
import gc
import os
import statistics
import sys
import time
from fractions import Fraction
from math import gcd, lcm, log2

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import flint  # noqa: E402
import numpy as np  # noqa: E402
from flint import fmpq_series  # noqa: E402

from pendulab.analyses import series as se  # noqa: E402
from pendulab.analyses.series_ratfun import ONE, ZERO, RatFun  # noqa: E402


def cpu(fn, repeat=1):
    """(median CPU seconds over ``repeat`` runs, result of the last run)."""
    times = []
    for _ in range(repeat):
        gc.collect()
        t0 = time.process_time()
        out = fn()
        times.append(time.process_time() - t0)
    return statistics.median(times), out


# =====================================================================================
# Baseline 1: a_0(q) by Newton's iteration on the continued fraction, fmpq power series
# =====================================================================================

def a0_continued_fraction(order):
    """Coefficients 0..order of a_0(q) (Fractions).

    a = 2 T_1, T_r = q^2 / (a - 4r^2 - T_{r+1}) (DLMF 28.4.5 written as a
    continued fraction), T beyond frequency order + 2 dropped (it enters at
    q^(order+4)).  G(a) = a - 2 T_1(a) = 0 is solved by Newton's iteration on
    power series, G'(a) = 1 - 2 T_1'(a), T_r' = -(1 - T_{r+1}') T_r / (a - 4r^2 - T_{r+1}).
    """
    flint.ctx.cap = order + 8
    a = fmpq_series([0], prec=1)
    k = 1
    while k < order + 1:
        p = min(2 * k, order + 1)
        q2 = fmpq_series([0, 0, 1], prec=p)
        a = fmpq_series(a.coeffs(), prec=p)
        tail, dtail = fmpq_series([0], prec=p), fmpq_series([0], prec=p)
        for r in range(p // 2 + 1, 0, -1):
            inv = 1 / (a - 4 * r * r - tail)
            tail, dtail = q2 * inv, -(1 - dtail) * q2 * inv * inv
        a = a - (a - 2 * tail) / (1 - 2 * dtail)
        k = p
    coeffs = [Fraction(int(c.p), int(c.q)) for c in a.coeffs()] + [Fraction(0)] * (order + 1)
    return coeffs[:order + 1]


# =====================================================================================
# Baseline 2: the previous integer-order engine (Rayleigh-Schroedinger in Fractions)
# =====================================================================================

def rayleigh_schroedinger(letter, m, order):
    """lam_0..lam_order of a_m / b_m: lam_n = (V x_{n-1})_m, x_n[t] = (sum_p lam_p x_{n-p}[t] - (V x_{n-1})_t) / (t^2 - m^2)."""
    lam, x = [Fraction(m * m)], [{m: Fraction(1)}]
    for n in range(1, order + 1):
        vx = {}
        for s, v in x[n - 1].items():
            for t, w in se._action(letter, s).items():
                vx[t] = vx.get(t, 0) + w * v
        lam.append(vx.get(m, Fraction(0)))
        support = set(vx)
        for p in range(1, n):
            support.update(x[n - p])
        xn = {}
        for t in support:
            if t == m:
                continue
            acc = -vx.get(t, 0)
            for p in range(1, n):
                if lam[p]:
                    v = x[n - p].get(t)
                    if v:
                        acc += lam[p] * v
            if acc:
                xn[t] = Fraction(acc) / (t * t - m * m)
        x.append(xn)
    return lam


def ours_characteristic(letter, m, order):
    engine = se._CharEngine(letter, m)
    engine.extend(order)
    return engine.lam


# =====================================================================================
# Baseline 3: the previous non-integer engine (Kronecker substitution in CPython ints)
# =====================================================================================

_PRIME = 67108859


def _ones(count, width):
    return int.from_bytes((b"\x01" + b"\x00" * (width - 1)) * count, "little")


def _pack(num, width):
    if not num:
        return 0
    half = 1 << (8 * width - 1)
    data = b"".join((c + half).to_bytes(width, "little") for c in num)
    return int.from_bytes(data, "little") - (_ones(len(num), width) << (8 * width - 1))


def _unpack(value, width, count):
    shift = 8 * width - 1
    half = 1 << shift
    data = (value + (_ones(count, width) << shift)).to_bytes(count * width, "little")
    out = [int.from_bytes(data[i:i + width], "little") - half for i in range(0, count * width, width)]
    while out and out[-1] == 0:
        out.pop()
    return out


def _linear_product(base, exps):
    factors = [(base + j) ** e for j, e in exps if e]
    while len(factors) > 1:
        factors = [factors[i] * factors[i + 1] if i + 1 < len(factors) else factors[i]
                   for i in range(0, len(factors), 2)]
    return factors[0] if factors else 1


def old_linear_sum(terms):
    """Sum of products over the least common denominator, by Kronecker substitution (Python ints)."""
    terms = [t for t in terms if all(not f.is_zero() for f in t)]
    if not terms:
        return ZERO
    prods = []
    for t in terms:
        den, exps, deg, bits = 1, {}, 0, 0
        for f in t:
            den *= f.den
            for j, e in f.exps:
                exps[j] = exps.get(j, 0) + e
            deg += len(f.num) - 1
            bits += sum(abs(c) for c in f.num).bit_length()
        prods.append((t, den, exps, deg, bits))
    big_den, big_exps = 1, {}
    for _, den, exps, _, _ in prods:
        big_den = lcm(big_den, den)
        for j, e in exps.items():
            big_exps[j] = max(big_exps.get(j, 0), e)
    bound, ndeg = 0, 0
    for t, den, exps, deg, bits in prods:
        cof = [(j, big_exps[j] - exps.get(j, 0)) for j in big_exps]
        bound = max(bound, bits + (big_den // den).bit_length()
                    + int(sum(e * log2(1 + abs(j)) for j, e in cof)) + 2)
        ndeg = max(ndeg, deg + sum(e for _, e in cof))
    bound += len(prods).bit_length() + 2
    width = bound // 8 + 1
    base = 1 << (8 * width)
    total = 0
    for t, den, exps, deg, bits in prods:
        cof = [(j, big_exps[j] - exps.get(j, 0)) for j in sorted(big_exps)]
        factors = sorted([_pack(f.num, width) for f in t] + [_linear_product(base, cof)],
                         key=lambda v: v.bit_length())
        value = big_den // den
        for f in factors:
            value *= f
        total += value
    return RatFun(_unpack(total, width, ndeg + 1), big_den, sorted((j, e) for j, e in big_exps.items() if e))


def _root_candidates(num, js):
    if len(num) > 1000:
        return list(js)
    residues = np.array([c % _PRIME for c in num], dtype=np.int64)
    rows = []
    for j in js:
        row, v, mm = np.empty(len(num), dtype=np.int64), 1, (-j) % _PRIME
        for i in range(len(num)):
            row[i] = v
            v = v * mm % _PRIME
        rows.append(row)
    values = (np.stack(rows) @ residues) % _PRIME
    return [j for j, v in zip(js, values) if v == 0]


def old_reduce(x):
    num = list(x.num)
    if not num:
        return ZERO
    exps = dict(x.exps)
    pending = [j for j, e in exps.items() if e]
    while pending and len(num) > 1:
        cancelled = []
        for j in _root_candidates(num, pending):
            root, out, acc = -j, [0] * (len(num) - 1), 0
            for i in range(len(num) - 1, -1, -1):
                acc = acc * root + num[i]
                if i:
                    out[i - 1] = acc
            if acc == 0:
                num = out
                exps[j] -= 1
                cancelled.append(j)
                if len(num) == 1:
                    break
        pending = [j for j in cancelled if exps[j] > 0]
    den, g = x.den, x.den
    for c in num:
        g = gcd(g, c)
    if g > 1:
        num, den = [c // g for c in num], den // g
    return RatFun(num, den, sorted((j, e) for j, e in exps.items() if e))


def old_reflect(x):
    sign = -1 if sum(e for _, e in x.exps) % 2 else 1
    return RatFun([(c if i % 2 == 0 else -c) * sign for i, c in enumerate(x.num)], x.den,
                  sorted((-j, e) for j, e in x.exps))


def old_divided_by_linear(x, const, j):
    num, den = x.num, x.den * const
    if den < 0:
        den, num = -den, [-c for c in num]
    exps = dict(x.exps)
    exps[j] = exps.get(j, 0) + 1
    return RatFun(num, den, sorted(exps.items()))


def old_nu_series(order):
    """alpha_n, C[n][k] (k > 0) by the recursion of 000 eq. 24 with the previous arithmetic."""
    alpha, c = [ZERO, ZERO], [{0: ONE}]

    def coefficient(n, k):
        if k >= 0:
            return c[n].get(k, ZERO)
        v = c[n].get(-k)
        return ZERO if v is None else old_reflect(v)

    for n in range(1, order + 1):
        if n >= 2:
            g0 = old_reduce(old_linear_sum([(coefficient(n - 1, -1),), (coefficient(n - 1, 1),)]))
            alpha.append(RatFun([-v for v in g0.num], g0.den, g0.exps))
        row = {}
        for k in range(2 - n % 2, n + 1, 2):
            terms = [(coefficient(n - 1, k - 1),), (coefficient(n - 1, k + 1),)]
            for m in range(2, n - k + 1, 2):
                if not alpha[m].is_zero() and k in c[n - m]:
                    terms.append((alpha[m], c[n - m][k]))
            g = old_linear_sum(terms)
            if not g.is_zero():
                row[k] = old_reduce(old_divided_by_linear(g, 4 * k, k))
        c.append(row)
    return alpha, c


def ours_nu_series(order):
    engine = se._Engine()
    engine.extend(order)
    return engine.alpha, engine.c


def same_nu(a, b):
    def key(v):
        return (tuple(v.num), v.den, tuple(v.exps))
    return ([key(v) for v in a[0]] == [key(v) for v in b[0]]
            and [{k: key(v) for k, v in row.items()} for row in a[1]]
            == [{k: key(v) for k, v in row.items()} for row in b[1]])


def line(what, ours, base, name):
    print(f"{what}: ours {ours:.3f} s, {name} {base:.3f} s, ratio {base / ours:.1f}x", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip order 150 of the nu series")
    ap.add_argument("--full", action="store_true", help="also run the previous nu engine at order 100 (7-9 min)")
    ap.add_argument("--skip-old", action="store_true", help="no runs of the previous engines")
    args = ap.parse_args(argv)
    print(f"CPU seconds (time.process_time); Python {sys.version.split()[0]}, python-flint {flint.__version__}")

    # -- integer order: a_0(q) ------------------------------------------------------
    for order in (100, 200):
        t_ours, ours = cpu(lambda: ours_characteristic("a", 0, order), 3)
        t_cf, cf = cpu(lambda: a0_continued_fraction(order), 3)
        assert ours == cf, f"a_0 to q^{order}: the engines differ"
        line(f"a_0(q) to q^{order}", t_ours, t_cf, "flint continued-fraction Newton baseline")
        if not args.skip_old:
            t_old, old = cpu(lambda: rayleigh_schroedinger("a", 0, order), 3 if order < 200 or args.full else 1)
            assert old == ours, f"a_0 to q^{order}: the previous engine differs"
            line(f"a_0(q) to q^{order}", t_ours, t_old, "previous engine (Rayleigh-Schroedinger, Fractions)")
    t_b1, _ = cpu(lambda: ours_characteristic("b", 1, 200), 3)
    print(f"b_1(q) to q^200: ours {t_b1:.3f} s", flush=True)

    # -- non-integer nu: alpha_n, c_n ------------------------------------------------
    for order in (60, 100):
        t_ours, ours = cpu(lambda: ours_nu_series(order))
        deg = ours[0][order].degree()
        if args.skip_old or (order == 100 and not args.full):
            print(f"nu series to order {order}: ours {t_ours:.1f} s (alpha_{order}: numerator degree "
                  f"{deg[0]}, denominator degree {deg[1]}); previous engine not run"
                  f"{' (--full runs it, 7-9 min)' if not args.skip_old else ''}", flush=True)
            continue
        t_old, old = cpu(lambda: old_nu_series(order))
        assert same_nu(ours, old), f"nu series to order {order}: the engines differ"
        line(f"nu series to order {order}", t_ours, t_old, "previous engine (Kronecker, CPython ints)")
    if not args.quick:
        t150, s150 = cpu(lambda: ours_nu_series(150))
        deg = s150[0][150].degree()
        print(f"nu series to order 150: ours {t150:.1f} s (alpha_150: numerator degree {deg[0]}, "
              f"denominator degree {deg[1]})", flush=True)
    import resource
    print(f"peak resident memory of the run: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
