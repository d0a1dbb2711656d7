"""Limits of a/l for the inverted pendulum by every method, side by side.

For a body with I/(m l^2) = ``inertia_ratio`` and a drive with
omega0/omega = ``ratio``, the inverted position is stable for
lower < a/l < upper.  Methods:

* ``"exact"`` - the exact characteristic curves a_0 and b_1 of Mathieu's
  equation (:func:`pendulab.analyses.floquet.stability_limits`);
* ``"eq12"`` - Phelps–Hunter's small-parameter interval (000 eq. 12), as
  derived in :func:`pendulab.analyses.phelps_hunter.interval_eq12`;
* ``"eq19"`` - Butikov's lower bound as the source prints it (000 eq. 19,
  :func:`pendulab.analyses.averaging.lower_bound_source`); no upper limit;
* ``"eq19-corrected"`` - the same averaging done for a physical pendulum
  (:func:`pendulab.analyses.averaging.lower_bound_physical`); no upper limit;
* ``"eq28"`` - the source's own series at second order (000 eq. 28),
  :func:`pendulab.analyses.series.stability_interval_series` with order 2;
* ``"series:N"`` - that series at order N;
* ``"integer-series:N"`` - the series of the boundary curves a_0(q) and b_1(q)
  (DLMF 28.6) at order N,
  :func:`pendulab.analyses.series.stability_interval_integer_series`; a limit
  beyond the series' radius of convergence (computed branch point, DLMF Table 28.6.1) is None.

The symbolic formulas are turned into numbers here, never re-typed.

>>> lower, upper = limits(0.1, 4/3, "eq12")
>>> round(lower, 6), round(upper, 6)
(0.188562, 0.629133)
>>> lower, upper = limits(0.1, 1, "eq19")
>>> round(lower, 12), upper
(0.141421356237, None)
"""

import functools
import math
import numbers

from pendulab.errors import InputError
from pendulab.limits import LIMITS, ascii_digits

#: The fixed method names; "series:N" (MIN_SERIES_ORDER <= N <= MAX_SERIES_ORDER) is accepted too.
METHODS = ("exact", "eq12", "eq19", "eq19-corrected", "eq28")
#: Methods of the comparison table when none are named.
DEFAULT_METHODS = ("exact", "eq12", "eq19", "eq19-corrected", "eq28", "series:4")
#: Orders of "series:N" accepted.  The stability interval needs the series to
#: order 2 at least (eq. 28 is order 2; stability_interval_series refuses 1),
#: so the range here is the one that function accepts, capped at 40.
MIN_SERIES_ORDER = 2
MAX_SERIES_ORDER = 40
#: Largest omega0/omega and I/(m l^2) accepted: beyond them the limits of a/l
#: exceed 1e6 and the closed forms overflow double precision.
#: (pendulab.limits.LIMITS "stability.ratio", "stability.inertia_ratio": one table)
MAX_RATIO = float(LIMITS["stability.ratio"][2])
MAX_INERTIA_RATIO = float(LIMITS["stability.inertia_ratio"][2])


def _number(value, name):
    """A finite real number from ``value`` (int, float, Fraction, numeric SymPy or decimal text)."""
    if isinstance(value, bool):
        raise InputError(f"{name} must be a number, got {value!r}")
    if isinstance(value, str):
        text = value.strip()
        try:
            from pendulab.limits import fraction
            value = float(fraction(text))
        except (ValueError, ZeroDivisionError, OverflowError):
            raise InputError(f"{name} must be a number, got {text!r}") from None
    if not isinstance(value, numbers.Real):
        try:
            import sympy as sp
            expr = sp.sympify(value)
            if not (expr.is_number and expr.is_real):
                raise TypeError
            value = float(expr)
        except Exception:
            raise InputError(f"{name} must be a real number, got {value!r}") from None
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"{name} must be finite, got {value!r}")
    return value


def check_ratio(ratio):
    """omega0/omega as a float; it must be finite and >= 0."""
    value = _number(ratio, "omega0/omega")
    if not 0 <= value <= MAX_RATIO:
        raise InputError(f"omega0/omega must be >= 0 and <= {MAX_RATIO:g}, got {value!r}")
    return value


def check_inertia_ratio(inertia_ratio):
    """I/(m l^2) as a float; >= 1 since I = m l^2 + I0 with I0 >= 0 (000 sec. 2.1)."""
    value = _number(inertia_ratio, "I/(m l^2)")
    if value < 1:
        raise InputError(f"I/(m l^2) must be >= 1 (I = m l^2 + I0, I0 >= 0), got {value!r}")
    if value > MAX_INERTIA_RATIO:
        raise InputError(f"I/(m l^2) must be <= {MAX_INERTIA_RATIO:g}, got {value!r}")
    return value


def parse_method(method):
    """("exact" | "eq12" | ... | "series", order or None) from a method name."""
    if not isinstance(method, str):
        raise InputError(f"method must be a string, got {method!r}")
    if method in METHODS:
        return method, None
    for kind, lowest in (("series", MIN_SERIES_ORDER), ("integer-series", 1)):
        if method.startswith(kind + ":"):
            text = method[len(kind) + 1:]
            if not ascii_digits(text) or not lowest <= int(text) <= MAX_SERIES_ORDER:
                raise InputError(f"method {method!r}: the series order must be an integer "
                                 f"between {lowest} and {MAX_SERIES_ORDER}")
            return kind, int(text)
    raise InputError(f"unknown method {method!r} (known: {', '.join(METHODS)}, series:N, "
                     f"integer-series:N)")


@functools.lru_cache(maxsize=None)
def _formula(name):
    """Numeric function (ratio, inertia_ratio) -> limit, lambdified from the derived formula."""
    import sympy as sp

    from pendulab.analyses import averaging, phelps_hunter as ph

    expr = {
        "eq12-lower": lambda: ph.interval_eq12()[0],
        "eq12-upper": lambda: ph.interval_eq12()[1],
        "eq19": averaging.lower_bound_source,
        "eq19-corrected": averaging.lower_bound_physical,
    }[name]()
    return sp.lambdify((ph.w0_over_w, ph.inertia_ratio), expr, "math")


def formulas():
    """The derived closed forms used by the methods eq12, eq19 and eq19-corrected.

    A dict method -> (lower, upper) of SymPy expressions in ``w0_over_w`` and
    ``inertia_ratio`` (upper None where the method has none).
    """
    from pendulab.analyses import averaging, phelps_hunter as ph

    return {
        "eq12": ph.interval_eq12(),
        "eq19": (averaging.lower_bound_source(), None),
        "eq19-corrected": (averaging.lower_bound_physical(), None),
    }


def _exact(ratio, inertia_ratio):
    from pendulab.analyses.floquet import stability_limits
    lower, upper = stability_limits(ratio, inertia_ratio=inertia_ratio)
    return (None if lower is None else float(lower)), (None if upper is None else float(upper))


@functools.lru_cache(maxsize=4096)
def _series_theta1(order, ratio):
    """theta1 at the (lower, upper) limits of the series at ``order`` for omega0/omega = ``ratio``.

    theta1 = 2 (a/l)/(I/(m l^2)) (000 eq. 6) does not depend on the body, so
    the limits in theta1 are computed once per (order, ratio) and shared by
    every body of a build (the point mass and the rod use one grid).  They
    are read as the limits of a/l for I/(m l^2) = 2, where a/l = theta1 * 2/2
    is theta1 itself, bit for bit.
    """
    from pendulab.analyses.series import stability_interval_series
    return stability_interval_series(order, ratio, 2.0)


def _series(order, ratio, inertia_ratio):
    """a/l = theta1 * inertia_ratio / 2, the operations stability_interval_series does itself."""
    t_lower, t_upper = _series_theta1(order, ratio)
    lower = None if t_lower is None else float(t_lower) * inertia_ratio / 2
    upper = None if t_upper is None else float(t_upper) * inertia_ratio / 2
    return lower, upper


def _integer_series(order, ratio, inertia_ratio):
    from pendulab.analyses.series import stability_interval_integer_series
    return stability_interval_integer_series(order, ratio, inertia_ratio, on_domain="omit")


def limits(ratio, inertia_ratio=1, method="exact"):
    """(lower, upper) limits of a/l for stability of the inverted position.

    ``ratio`` = omega0/omega >= 0, ``inertia_ratio`` = I/(m l^2) >= 1 (1 for a
    point mass, 4/3 for a rod), ``method`` one of :data:`METHODS`,
    "series:N" or "integer-series:N".  ``upper`` is None for eq19 and
    eq19-corrected (the averaging gives no upper limit).  Raises
    :class:`~pendulab.errors.InputError` for bad input.
    """
    problems = []
    for check, value in ((check_ratio, ratio), (check_inertia_ratio, inertia_ratio),
                         (parse_method, method)):
        try:
            check(value)
        except InputError as exc:
            problems.append(str(exc))
    if problems:
        raise InputError("; ".join(problems))
    rho, r = check_ratio(ratio), check_inertia_ratio(inertia_ratio)
    kind, order = parse_method(method)
    if kind == "exact":
        return _exact(rho, r)
    if kind == "eq12":
        return _formula("eq12-lower")(rho, r), _formula("eq12-upper")(rho, r)
    if kind in ("eq19", "eq19-corrected"):
        return _formula(kind)(rho, r), None
    if kind == "eq28":
        return _series(2, rho, r)
    if kind == "integer-series":
        return _integer_series(order, rho, r)
    return _series(order, rho, r)


class ComparisonTable(dict):
    """The dict :func:`comparison` and :func:`scene_comparison` return (its keys unchanged),
    which a notebook shows as a table: one row per omega0/omega, one column per method, each
    cell "lower, upper" of a/l at 4 decimals ("---": no limit), as the product "stability"
    rounds its LaTeX table."""

    def _rows(self):
        def cell(v):
            return "---" if v is None else f"{v:.4f}"
        return [[f"{rho:.3f}"] + [f"{cell(self['limits'][m][i][0])}, {cell(self['limits'][m][i][1])}"
                                  for m in self["methods"]]
                for i, rho in enumerate(self["w0_over_w"])]

    def _caption(self, tex=False):
        ratio = self.get("inertia_ratio")
        if tex:
            from pendulab.latex import text
            return text("limits (lower, upper) of ") + "a/l" + (
                "" if ratio is None else text(" for ") + f"I/(m l^2) = {float(ratio):g}")
        return "limits (lower, upper) of a/l" + (
            "" if ratio is None else f" for I/(m l^2) = {float(ratio):g}")

    #: methods side by side in one array (a cell holds two limits: half the product's 6)
    COLUMNS = 3

    def _repr_latex_(self):
        """The table as display math (:func:`pendulab.latex.math_table`), at most
        :data:`COLUMNS` methods side by side (more go into further arrays below, each
        caption saying which part), so that the LaTeX stays within the line."""
        from pendulab.latex import chunks, math_table, part_note, text
        rows = [[r[0]] + [c.replace("---", r"\text{---}") for c in r[1:]] for r in self._rows()]
        groups = chunks(len(self["methods"]), self.COLUMNS)
        out = []
        for k, group in enumerate(groups):
            header = [r"\omega_0/\omega"] + [text(self["methods"][j]) for j in group]
            caption = self._caption(tex=True) + (text(part_note(k, len(groups)))
                                                 if len(groups) > 1 else "")
            out.append(math_table(caption, header, [[r[0]] + [r[1 + j] for j in group]
                                                    for r in rows]))
        return "\n".join(out)

    def _repr_html_(self):
        """The table in HTML (:func:`pendulab.latex.html_table`), one row per omega0/omega."""
        from pendulab.latex import html_table
        return html_table(self._caption(), ["omega0/omega"] + list(self["methods"]), self._rows())


#: Digits at which the exact method computes a band again, in ball arithmetic, when its two
#: limits are one double (:func:`report`); past the last the band is reported as unresolved.
RESOLVE_DIGITS = (30, 100)


def _none_reasons(method, ratio, inertia_ratio, lower, upper):
    """{"lower"/"upper": why the method gives no such limit} for each limit that is None."""
    kind, order = parse_method(method)
    why = {}
    missing = [name for name, value in (("lower", lower), ("upper", upper)) if value is None]
    if not missing:
        return why
    theta0, _ = map_point(ratio, inertia_ratio)
    if kind in ("eq19", "eq19-corrected"):
        for name in missing:
            why[name] = ("the averaging gives only a lower limit (000 eq. 19)" if name == "upper"
                         else "the averaging gives no lower limit at this ratio")
        return why
    if kind in ("series", "eq28"):
        n = 2 if kind == "eq28" else order
        if "lower" in missing:
            why["lower"] = (f"at order {n} no theta1 > 0 gives nu = 0 at theta0 = {theta0:.6g}: "
                            "the truncated series theta0 = nu^2 + sum alpha_n theta1^n (000 eq. 27) "
                            "has no positive root theta1 at nu^2 = 0")
        if "upper" in missing:
            why["upper"] = (f"at order {n} the truncated series has no fold before its pole at "
                            f"nu = 1 (the branch nu^2(theta1) from nu^2 = theta0 = {theta0:.6g} "
                            "reaches no largest theta1; docs/series.md; integer-series:N reaches "
                            "the upper limit)")
        return why
    if kind == "integer-series":
        import warnings

        from pendulab.analyses.series import interval_integer_series_theta1
        from pendulab.errors import AccuracyWarning
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always", AccuracyWarning)
            found = interval_integer_series_theta1(order, theta0, on_domain="warn")
        beyond = {str(w.message).split(":", 1)[0]: str(w.message) for w in said
                  if issubclass(w.category, AccuracyWarning)}
        for name, curve, root in (("lower", "a0", found[0]), ("upper", "b1", found[1])):
            if name not in missing:
                continue
            if curve in beyond:
                why[name] = f"order {order}: {beyond[curve]}"
            elif root is None:
                from pendulab.analyses.series import characteristic_series
                # the range interval_integer_series_theta1 searches for the first crossing
                top = 3.0 * float(characteristic_series(curve, order).radius) + 2 * abs(theta0)
                why[name] = (f"order {order}: the truncated {curve} series does not reach "
                             f"theta0 = {theta0:.6g} for 0 < theta1 <= {top:.6g}")
        for name in missing:
            why.setdefault(name, f"order {order}: the series gives no {name} limit here")
        return why
    for name in missing:
        why[name] = f"method {method!r} gives no {name} limit at omega0/omega = {ratio!r}"
    return why


def _resolved(ratio, inertia_ratio, digits=RESOLVE_DIGITS):
    """The exact band at the first of ``digits`` where its two ends differ, certified by
    :func:`pendulab.analyses.floquet.stability_limits` (ball arithmetic where the inputs are
    rational: a float is its exact binary value).  Returns (dps, lower text, upper text,
    relative width, certified digits, None) or, when the ends agree at every dps, (last dps,
    None, None, None, certified digits, the digits both ends share)."""
    import mpmath

    from pendulab.analyses.floquet import stability_limits
    for dps in digits:
        band = stability_limits(ratio, inertia_ratio, dps=dps)
        with mpmath.workdps(dps + 10):
            lo, up = mpmath.mpf(band[0]), mpmath.mpf(band[1])
            if mpmath.nstr(lo, dps) != mpmath.nstr(up, dps):
                width = float((up - lo) / up)
                return (dps, mpmath.nstr(lo, dps), mpmath.nstr(up, dps), width,
                        band.certified_digits, None)
            shared = mpmath.nstr(lo, dps)
    return digits[-1], None, None, None, band.certified_digits, shared


def report(ratio, inertia_ratio=1, method="exact", exact_ratio=None, exact_inertia_ratio=None):
    """:func:`limits` with the reason of every missing limit and, for the exact method, a band
    too narrow for double precision computed again with more digits.

    Returns a dict: ``lower``, ``upper`` (floats or None), ``why`` ({"lower"/"upper": one
    line} for each None), and, when the exact limits are one double, ``band``:
    {"digits": d, "certified_digits": c, "near": the double,
    "lower", "upper" (decimal texts of d digits), "relative_width"} where d digits separate
    the ends (``both_ends`` None), else the same with lower, upper, relative_width None and
    ``both_ends`` the d digits the two ends share ("not resolvable": the band is narrower than
    about 10^(1-d) of a/l); ``lower`` and ``upper`` are then None, with that reason.  ``exact_ratio`` and
    ``exact_inertia_ratio`` (Fraction or decimal text) are used for the digits when given.
    """
    lower, upper = limits(ratio, inertia_ratio, method)
    out = {"lower": lower, "upper": upper, "why": {}}
    if parse_method(method)[0] == "exact" and lower is not None and lower == upper:
        dps, lo, up, width, proved, shared = _resolved(
            ratio if exact_ratio is None else exact_ratio,
            inertia_ratio if exact_inertia_ratio is None else exact_inertia_ratio)
        out["band"] = {"digits": dps, "certified_digits": proved, "near": lower, "lower": lo,
                       "upper": up, "relative_width": width, "both_ends": shared}
        out["lower"] = out["upper"] = None
        if lo is None:
            text = (f"not resolvable in double precision: the stable band lies at a/l = "
                    f"{lower!r} and its two ends agree in all {dps} "
                    f"{'certified ' if proved else ''}digits (narrower than about 1e-{dps - 1} of a/l)")
        else:
            text = (f"not resolvable in double precision: both ends round to {lower!r}; the "
                    f"band's relative width is {width:.3g}, its ends at {dps} "
                    f"{'certified ' if proved else ''}digits are given in band")
        out["why"] = {"lower": text, "upper": text}
        return out
    out["why"] = _none_reasons(method, check_ratio(ratio), check_inertia_ratio(inertia_ratio),
                               lower, upper)
    if (lower is not None and upper is not None
            and abs(upper - lower) <= 4 * math.ulp(max(abs(lower), abs(upper)))):
        # a closed form's two curves that meet (eq. 28 at omega0/omega = 1/2): not two limits
        out["closes"] = (f"the method's lower and upper limits meet at this ratio (they agree "
                         f"within rounding, at a/l = {lower!r}): its stable band is empty or "
                         "a single point here")
    return out


def comparison(ratios, inertia_ratio=1, methods=DEFAULT_METHODS, series_order=None):
    """Limits of a/l on a grid of omega0/omega for several methods (table data).

    ``methods`` may contain "series" (plain), which then means
    "series:<series_order>".  Returns a dict::

        {"inertia_ratio": r, "w0_over_w": [...], "methods": [...],
         "limits": {method: [[lower, upper], ...]}}

    with None where a method has no limit (a :class:`ComparisonTable`, a dict that a
    notebook shows as a table).  All input problems are reported at once.
    """
    problems = []
    if isinstance(ratios, (str, bytes)) or not hasattr(ratios, "__iter__"):
        raise InputError(f"ratios must be a sequence of numbers, got {ratios!r}")
    ratios = list(ratios)
    if not ratios:
        problems.append("ratios is empty")
    grid = []
    for value in ratios:
        try:
            grid.append(check_ratio(value))
        except InputError as exc:
            problems.append(str(exc))
    try:
        r = check_inertia_ratio(inertia_ratio)
    except InputError as exc:
        problems.append(str(exc))
    if isinstance(methods, str):
        methods = [methods]
    names = []
    for method in methods:
        if method == "series":
            if series_order is None:
                problems.append("method 'series' needs series_order")
                continue
            method = f"series:{series_order}"
        try:
            parse_method(method)
        except InputError as exc:
            problems.append(str(exc))
            continue
        if method not in names:
            names.append(method)
    if not names and not problems:
        problems.append("no methods given")
    if problems:
        raise InputError("; ".join(problems))
    table = {m: [list(limits(rho, r, m)) for rho in grid] for m in names}
    return ComparisonTable(inertia_ratio=r, w0_over_w=grid, methods=names, limits=table)


# ---------------------------------------------------------------------------
# The map (a/l, omega0/omega, ...) -> (theta0, theta1), read from the derivation
# ---------------------------------------------------------------------------

class ParameterMap:
    """The dimensionless groups of a driven-pivot derivation and what they map to.

    Built from the equations and canonical stages (never typed in):

    * ``kind`` - the canonical stage's "mathieu", "hill" or "linear";
    * Mathieu: ``theta0``, ``theta1`` - SymPy expressions in ``symbols``
      (a_over_l, w0_over_w, and inertia_ratio when I is symbolic), from
      :func:`pendulab.numerics.model.mathieu_parameters`; ``slope`` =
      theta1/(a/l) when theta1 is proportional to a/l and theta0 does not
      involve a/l (every drive of the form c(t) a), else None;
    * Hill: ``system`` - the first-order system in tau
      (:func:`pendulab.numerics.model.pivot_system`), whose linear part the
      monodromy and Hill-determinant routes use.

    ``values`` (scene numbers) are substituted after the groups, as in
    :mod:`pendulab.numerics.model`.  The numeric functions are lambdified once.
    """

    def __init__(self, equations, form, values=None, drive=None):
        import sympy as sp

        from pendulab import symbols as S
        from pendulab.numerics.model import mathieu_parameters, pivot_system

        self.kind = form.kind
        self.form = form
        self.drive = drive if drive is not None else equations.system.drive
        self.note = form.note
        self.theta0 = self.theta1 = self.slope = self.scale = None
        self.system = None
        if form.kind == "mathieu":
            self.theta0, self.theta1 = mathieu_parameters(equations, form, values=values)
            names = self.theta0.free_symbols | self.theta1.free_symbols
            slope = sp.simplify(self.theta1 / S.a_over_l)
            if (not self.theta0.has(S.a_over_l) and not slope.has(S.a_over_l)
                    and slope != 0):
                self.slope = slope
                self.scale = sp.simplify(1 / slope)  # a/l per unit theta1
        elif form.kind == "hill":
            self.system = pivot_system(equations, form, values=values)
            names = set(self.system.params)
        else:
            names = set()
        self.symbols = tuple(sorted(names | {S.a_over_l, S.w0_over_w}, key=lambda s: s.name))
        self._fns = {}

    def refuse(self, product, what):
        """A one-line InputError: ``product`` cannot do ``what`` for this drive."""
        raise InputError(f"{product}: no {what} for the drive {self.drive}: it gives a "
                         f"{self.kind} equation (a periodic drive is needed)"
                         + (f"; {self.note}" if self.note else ""))

    def _fn(self, which, module):
        import sympy as sp
        key = (which, module)
        if key not in self._fns:
            expr = {"theta0": self.theta0, "theta1": self.theta1, "slope": self.slope,
                    "scale": self.scale}[which]
            self._fns[key] = sp.lambdify(self.symbols, expr, module)
        return self._fns[key]

    def _args(self, point):
        names = {s.name for s in self.symbols}
        unknown = sorted(set(point) - names)
        if unknown:
            raise InputError(f"unknown group(s) {', '.join(unknown)} (the map has "
                             f"{', '.join(sorted(names))})")
        # a/l may be left out where only theta0 or the scale is asked for (they do not
        # involve it); every other group must be given
        missing = sorted(names - set(point) - {"a_over_l"})
        if missing:
            raise InputError(f"the map needs a value for {', '.join(missing)}")
        return [point.get(s.name, 0) for s in self.symbols]

    def evaluate(self, which, point, module="numpy"):
        """theta0, theta1 or slope at ``point`` ({group name: value}) with NumPy or mpmath."""
        if self.kind != "mathieu":
            raise InputError(f"the drive gives a {self.kind} equation: it has no {which}")
        if which in ("slope", "scale") and self.slope is None:
            raise InputError(f"theta1 = {self.theta1} is not proportional to a/l")
        return self._fn(which, module)(*self._args(point))

    def is_source_map(self, inertia_ratio):
        """True when theta0, theta1 equal those of the drive a cos(omega t) for this body."""
        if self.kind != "mathieu":
            return False
        ref = body_map()
        import sympy as sp
        from pendulab import symbols as S
        sub = {S.inertia_ratio: sp.nsimplify(inertia_ratio)}
        return (sp.simplify(self.theta0 - ref.theta0.subs(sub)) == 0
                and sp.simplify(self.theta1.subs(sub) - ref.theta1.subs(sub)) == 0)


@functools.lru_cache(maxsize=None)
def body_map():
    """The map of the source's drive a cos(omega t) with I symbolic (derived once, cached).

    theta0 and theta1 are then functions of a_over_l, w0_over_w and
    inertia_ratio = I/(m l^2); every public function taking (ratio,
    inertia_ratio) evaluates it.

    >>> m = body_map()
    >>> m.theta0, m.theta1
    (-4*w0_over_w**2, 2*a_over_l/inertia_ratio)
    """
    from pendulab.equations import derive
    from pendulab.pipeline import canonical_form
    from pendulab.systems import DrivenPivot

    eqs = derive(DrivenPivot(body="explicit"))
    return ParameterMap(eqs, canonical_form(eqs))


def scene_map(ctx):
    """The ParameterMap of a scene's pipeline context (its equations and canonical stages)."""
    return ParameterMap(ctx.get("equations"), ctx.get("canonical"))


def map_point(ratio, inertia_ratio, pmap=None):
    """(theta0, scale) in double precision at omega0/omega = ratio for ``pmap`` (default the body map).

    ``scale`` = (a/l)/theta1 (inertia_ratio/2 for the source's drive): a limit
    theta1* of the Mathieu plane is the limit a/l = scale theta1*.
    """
    pmap = body_map() if pmap is None else pmap
    point = {"w0_over_w": ratio, "inertia_ratio": inertia_ratio}
    point = {k: v for k, v in point.items()
             if v is not None and k in {s.name for s in pmap.symbols}}
    return float(pmap.evaluate("theta0", point, "math")), float(pmap.evaluate("scale", point, "math"))


#: Methods that live in the Mathieu plane (functions of theta0 and theta1 only):
#: they apply to any Mathieu drive through its derived map.
MATHIEU_PLANE = ("exact", "eq12", "eq28", "series", "integer-series")
#: Scan of a/l for a Hill drive's first stable interval (see :func:`hill_limits`).
HILL_SCAN_TOP = 2.0
HILL_SCAN_STEP = 0.005


@functools.lru_cache(maxsize=None)
def _eq12_theta1():
    """theta1(theta0) at the ends of eq. 12's interval, from the Mathieu-plane eq. 11."""
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.analyses import phelps_hunter as ph

    rhs = ph.small_parameter_exponent(mathieu=True).rhs
    out = []
    for level in (0, 1):
        roots = [r for r in sp.solve(sp.Eq(rhs, level), S.theta1)
                 if r.subs(S.theta0, -sp.Rational(1, 100)).is_positive]
        (root,) = roots
        out.append(sp.lambdify(S.theta0, root, "math"))
    return tuple(out)


def _mathieu_plane(kind, order, theta0):
    """(lower, upper) |theta1| of the first stable interval at theta0 by a Mathieu-plane method."""
    if kind == "exact":
        from pendulab.analyses.floquet import first_band
        return first_band(theta0)
    if kind == "eq12":
        lo, up = _eq12_theta1()
        return lo(theta0) if theta0 <= 0 else 0.0, up(theta0)
    from pendulab.analyses import series
    if kind in ("eq28", "series"):
        return series.interval_series_theta1(2 if kind == "eq28" else order, theta0)
    return series.interval_integer_series_theta1(order, theta0, on_domain="omit")


def _applicable(pmap, method):
    """(kind, order) of ``method`` if it applies to this drive; a one-line refusal otherwise."""
    kind, order = parse_method(method)
    if pmap.kind == "linear":
        pmap.refuse("stability limits", f"limits of a/l by method {method!r}")
    if pmap.kind == "hill":
        if kind != "exact":
            raise InputError(f"method {method!r} is derived for Mathieu's equation; the drive "
                             f"{pmap.drive} gives Hill's equation (only 'exact' applies)")
    elif kind not in MATHIEU_PLANE:
        raise InputError(f"method {method!r} is derived by averaging the drive a*cos(omega*t); "
                         f"this scene's drive is {pmap.drive} (use the Mathieu-plane methods "
                         f"{', '.join(MATHIEU_PLANE)})")
    elif pmap.slope is None:
        raise InputError(f"theta1 = {pmap.theta1} is not proportional to a/l: the limits of a/l "
                         "are not defined by one band edge each")
    return kind, order


def scene_limits(pmap, ratio, method="exact", groups=None):
    """(lower, upper) of a/l at omega0/omega = ``ratio`` for a scene's ParameterMap.

    Mathieu drive: the Mathieu-plane methods (:data:`MATHIEU_PLANE`) at the
    map's theta0, divided by theta1/(a/l); eq19 and eq19-corrected, derived by
    averaging the source's drive a cos(omega t), only when the map is that
    drive's.  Hill drive: ``"exact"`` only, by :func:`hill_limits`.  Other
    drives: a one-line refusal.  ``groups`` fixes further groups (e.g.
    {"inertia_ratio": 1}) when the body's inertia is symbolic.
    """
    rho = check_ratio(ratio)
    kind, order = _applicable(pmap, method)
    groups = dict(groups or {})
    if pmap.kind == "hill":
        return hill_limits(pmap, rho, groups)
    theta0, scale = map_point(rho, groups.get("inertia_ratio"), pmap)
    if theta0 >= 1:
        raise InputError(f"theta0 = {theta0:.6g} >= 1 at omega0/omega = {rho}: the first stable "
                         "band is not the one that starts at a/l = 0")
    lo, up = _mathieu_plane(kind, order, theta0)
    scale = abs(scale)
    return (None if lo is None else float(lo) * scale), (None if up is None else float(up) * scale)


def scene_comparison(pmap, ratios, methods, groups=None):
    """:func:`comparison`'s table for a scene's ParameterMap (see :func:`scene_limits`)."""
    grid = [check_ratio(r) for r in ratios]
    names = []
    for method in methods:
        _applicable(pmap, method)
        if method not in names:
            names.append(method)
    table = {m: [list(scene_limits(pmap, rho, m, groups)) for rho in grid] for m in names}
    return ComparisonTable(w0_over_w=grid, methods=names, limits=table)


def hill_limits(pmap, ratio, groups=None, top=HILL_SCAN_TOP, step=HILL_SCAN_STEP):
    """First stable interval (lower, upper) of a/l for a Hill drive at omega0/omega = ``ratio``.

    Bisection on the Floquet verdict along a/l: the traces of the monodromy
    matrix (:func:`pendulab.numerics.monodromy.traces_along`, DOP853 at rtol
    1e-13 on the derived linear system) on a/l = 0, step, ..., top bracket the
    first a/l where |tr M| < 2 and the first after it where |tr M| >= 2; each
    end is then refined by Brent's method on |tr M| - 2 to 1e-12.  An
    interval narrower than ``step`` can be missed; ``upper`` is None when the
    interval reaches beyond ``top``; (None, None) when no stable a/l is found
    up to ``top``.
    """
    import numpy as np

    from pendulab.numerics.monodromy import traces_along
    from pendulab.numerics.roots import brent_root

    fos = pmap.system
    params = {"w0_over_w": ratio, **(groups or {})}
    names = {s.name for s in fos.params}
    params = {k: v for k, v in params.items() if k in names}
    xs = np.linspace(0.0, top, int(round(top / step)) + 1)
    tr = traces_along(fos, params, "a_over_l", xs)
    stable = np.abs(tr) < 2

    def g(x):
        return abs(float(traces_along(fos, params, "a_over_l", [x])[0])) - 2

    first = np.nonzero(stable)[0]
    if first.size == 0:
        return None, None
    i = int(first[0])
    lower = 0.0 if i == 0 else brent_root(g, xs[i - 1], xs[i], xtol=1e-12, rtol=1e-13)
    after = np.nonzero(~stable[i:])[0]
    if after.size == 0:
        return float(lower), None
    j = i + int(after[0])
    upper = brent_root(g, xs[j - 1], xs[j], xtol=1e-12, rtol=1e-13)
    return float(lower), float(upper)
