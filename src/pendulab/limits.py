"""One table of the ranges of every numeric option (scenes, command line, API).

``LIMITS`` maps an option's name, ``<product or command>.<option>``, to
``(type, min, max, default, help)``:

* ``int`` / ``float``: the value itself lies in [min, max];
* ``list``: the number of entries lies in [min, max];
* ``"fraction"``: a decimal or fraction given as text (``"1/2"``), whose value
  lies in (min, max] (an open minimum: 0 itself is not a ratio to scale by).

``default`` is the value a scene gets when it leaves the option out (``None``:
the command line's own default, or required).  The ranges are chosen so that
the worst accepted value finishes in about a minute or less on one core; the
measurements are in docs/scenes.md ("Limits").

Scene validation (:func:`pendulab.scene.validate_options`) checks every
product option listed here with the scene's other problems; the products and
the commands check the same entries (:func:`check`) when called directly.

>>> check("series.order", 12)
12
>>> check("series.order", 0)
Traceback (most recent call last):
...
pendulab.errors.InputError: series.order must be an integer from 1 to 60, got 0
>>> describe("floquet.points")
'1 to 100 entries'
"""

import re
from fractions import Fraction

#: Largest decimal exponent accepted in number text ("1e4000"): beyond it every range is
#: passed by far, and the exact value would take minutes to expand (1e99999999999 hangs Fraction).
MAX_EXPONENT = 4000
_NUMBER_TEXT = re.compile(r"^[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE]([+-]?[0-9]+))?$")


def fraction(text):
    """The exact value of decimal or fraction text ("-0.002", "1e-3", "-1/5").

    ASCII digits only; exponents beyond +-MAX_EXPONENT are refused before any expansion.
    Raises ValueError (with a short reason) or ZeroDivisionError.

    >>> fraction("-1/5"), fraction("2.5e-1")
    (Fraction(-1, 5), Fraction(1, 4))
    """
    parts = str(text).strip().split("/")
    if len(parts) > 2:
        raise ValueError("not a decimal or a fraction")
    values = []
    for part in parts:
        part = part.strip()
        m = _NUMBER_TEXT.match(part)
        if not m:
            raise ValueError("not a decimal or a fraction")
        if m.group(3) is not None and abs(int(m.group(3))) > MAX_EXPONENT:
            raise ValueError(f"exponent {m.group(3)} is beyond +-{MAX_EXPONENT}")
        values.append(Fraction(part))
    return values[0] if len(values) == 1 else values[0] / values[1]


from pendulab.errors import InputError

#: Most distinct frequencies a drive (a trigonometric polynomial in t) may have:
#: 64 harmonics derive in about 6 s (docs/scenes.md, "Limits").
MAX_HARMONICS = 64

#: Largest |a/l|, |theta(0)|, |dtheta/dtau(0)| a sweep or a simulation takes (beyond it RK4
#: at the source's 100 steps per period only measures its own overflow).
MAX_MAGNITUDE = 1e4

LIMITS = {
    # product "floquet" (and ``pendulab floquet --dps``)
    "floquet.dps": (int, 1, 1000, 30,
                    "decimal digits of every number written"),
    "floquet.points": (list, 1, 100, [["-0.002", "0.2"]],
                       "[theta0, theta1] pairs (strings such as \"-0.002\" or \"1/5\", or numbers)"),
    "floquet.ratios": (list, 0, 20, ["0", "0.05", "0.1", "0.2"],
                       "omega0/omega values for the exact limits of a/l"),
    # product "quarter_periods"
    "quarter_periods.count": (int, 1, 10000, 8,
                              "how many quarter periods (growing: of each kind; shortening: in all)"),
    "quarter_periods.dps": (int, 1, 1000, 30, "significant digits of the zeros and durations"),
    # product "notes" (the lecture notes)
    "notes.series_order": (int, 1, 20, 8, "order of the series section (000 eqs. 20-24; beyond 20 "
                                          "the coefficients' integers are wider than a line)"),
    "notes.grid": (int, 2, 12, 10, "points per axis of the simulated stability maps (the RK4 "
                                   "work of the three maps is bounded as in the experiments product)"),
    "notes.dps": (int, 15, 100, 30, "significant digits of the Bessel zeros and identities"),
    # product "series" (and ``pendulab series --order``)
    "series.order": (int, 1, 60, 8,
                     "highest power of theta1 (and of q for the integer kinds)"),
    "series.kinds": (list, 1, 12, ["nu", "a0", "b1"],
                     "'nu' for 000 eqs. 20-22, and integer kinds 'a0', 'a1', 'b1', 'b2', ... "
                     "(DLMF 28.6)"),
    # ``pendulab latex series``: the nu series of 000 eqs. 20-22 grows fast in print (order 30:
    # 1.1 MB of LaTeX, about 560 pages of a bare article, 20 s of pdflatex); a_m, b_m take series.order
    "latex.nu_order": (int, 1, 30, None, "highest order of the nu series in a LaTeX fragment"),
    # product "stability"
    "stability.points": (int, 2, 401, 21,
                         "number of omega0/omega values, evenly spaced in [0, max_ratio]"),
    "stability.max_ratio": ("fraction", 0, 10, "1",
                            "largest omega0/omega of the grid (a decimal or fraction)"),
    "stability.methods": (list, 1, 12, ["exact", "eq12", "eq19", "eq19-corrected", "eq28",
                                        "series:4"],
                          "methods to compare (exact, eq12, eq19, eq19-corrected, eq28, "
                          "series:N, integer-series:N)"),
    # ``pendulab stability`` and the stability methods (pendulab.analyses.stability)
    "stability.ratio": (float, 0, 1000, None, "omega0/omega"),
    "stability.inertia_ratio": (float, 1, 1000, None,
                                "I/(m l^2) (I = m l^2 + I0 with I0 >= 0)"),
    "stability.series_order": (int, 2, 40, None, "N of the method series:N"),
    "stability.integer_series_order": (int, 1, 40, None, "N of the method integer-series:N"),
    # product "bessel" (the work of zeros, count, start and dps together: bessel_work below)
    "bessel.zeros": (int, 1, 10000, 8, "how many zeros of J1 and of J2 to list"),
    "bessel.count": (int, 1, 10000, 6,
                     "how many quarter periods (growing: of each kind; shortening: in all)"),
    "bessel.dps": (int, 1, 1000, 30, "significant digits of every number"),
    "bessel.start": (int, 0, 10000, 0,
                     "z0 = j_2,start (0: the source's 1 for a growing string, the smallest that "
                     "fits count for a shortening one)"),
    "bessel.nmax": (int, 0, 20, 2, "identities for n = 0..nmax"),
    "bessel.points": (int, 2, 400, 40,
                      "log-spaced z in [1e-30, 1e6] for the identities (plus 9 near zeros)"),
    # product "motion" (SI units; the periods integrated are bounded by motion_periods below)
    "motion.g": ("positive", 0, 1000, 9.81, "gravitational acceleration g (m/s^2)"),
    "motion.L0": ("positive", 0, 1e6, 1.0, "the length's parameter L0 (m)"),
    "motion.v0": ("positive", 0, 1e6, 0.01,
                  "the rate v0 in L(t) (m/s); L0 - v0*t shortens the string"),
    "motion.theta_0": (float, -3.14159, 3.14159, 0.05,
                       "initial angle theta(0) (rad), not 0; theta'(0) = 0"),
    "motion.t_end": ("positive", 0, 1e6, 100.0,
                     "end of the integration (s), before L(t) reaches 0"),
    "motion.points": (int, 11, 100001, 1001, "output times, equally spaced in [0, t_end]"),
    # product "experiments" (the RK4 work of all maps together: experiments_seconds below)
    "experiments.maps": (list, 0, 3, ["text", "caption", "fig4"],
                         "initial conditions of the maps: text (0.06, 0.01), caption (0.01, 0.06), "
                         "fig4 (0.1, 0.1)"),
    "experiments.grid": (int, 1, 400, 10,
                         "points of a/l and of omega0/omega on linspace(0, 1, grid)"),
    "experiments.periods": (int, 1, 100000, 300, "drive periods per trajectory"),
    "experiments.steps_per_period": (int, 1, 10000, 100, "RK4 steps per drive period"),
    "experiments.criteria": (list, 1, 4, ["mean", "mean-abs", "bounded", "floquet"],
                             "criteria drawn and counted (mean, mean-abs, bounded, floquet)"),
    "experiments.first_grid": (int, 1, 100, 10,
                               "parameter grid of the first experiment (per axis)"),
    "experiments.fig5_orders": (list, 1, 8, [2, 8],
                                "orders of the series solution in Fig. 5 (each 2 to 40)"),
    "experiments.fig5_periods": (int, 1, 10000, 40, "drive periods shown in Fig. 5"),
    "experiments.fig2_periods": (int, 1, 10000, 40, "drive periods shown in Fig. 2"),
    # ``pendulab floquet --theta0/--theta1`` (and the floquet product's points): the widest
    # method's size (Hill, |theta0| + 2|theta1| <= 4e6); each method's own size limit and the
    # work budget (floquet_seconds) narrow it
    "floquet.theta0": (float, -4e6, 4e6, None, "theta0 = -4 omega0^2/omega^2 (000 eq. 5)"),
    "floquet.theta1": (float, -2e6, 2e6, None, "theta1 = 2 a l m / I (000 eq. 6)"),
    # ``pendulab bessel zeros --order`` (--count is bessel.zeros, --dps bessel.dps;
    # --z of ``bessel identities`` is one point of bessel.points' grid range)
    "bessel.order": (float, 0, 300, None, "the order n of J_n, a real number (1, 2.5, 1/3)"),
    "bessel.z": ("positive", 0, 1e6, None, "a point z of the identities (z > 0)"),
    # ``pendulab sweep`` and ``pendulab simulate`` (--grid, --periods, --steps-per-period are
    # experiments.grid, .periods, .steps_per_period; --inertia-ratio is stability.inertia_ratio;
    # the work of all options together: sweep_seconds, simulate_problem below)
    "sweep.theta_init": (float, -MAX_MAGNITUDE, MAX_MAGNITUDE, None, "theta(0) in rad"),
    "sweep.omega_init": (float, -MAX_MAGNITUDE, MAX_MAGNITUDE, None, "dtheta/dtau at tau = 0"),
    "sweep.processes": (int, 1, 16, None, "local worker processes (1 runs in this process)"),
    # ``pendulab simulate`` (--w0-over-w is stability.ratio)
    "simulate.a_over_l": (float, 0, MAX_MAGNITUDE, None, "pivot amplitude over l, a/l"),
    "simulate.every": (int, 1, 10**7, None, "print every K-th step"),
    # ``pendulab animate`` and the product "animation" (the frames of all options together:
    # at most ANIMATION_MAX_FRAMES)
    "animation.a_over_l": (float, 0, 10, 0.1, "pivot amplitude over l, a/l"),
    "animation.w0_over_w": (float, 0, 10, 0.02, "omega0/omega"),
    "animation.theta_init": (float, -3.14159, 3.14159, 0.3, "theta(0) in rad (0: upright)"),
    "animation.omega_init": (float, -100, 100, 0.0, "dtheta/dtau at tau = 0"),
    "animation.periods": (int, 1, 400, 20, "drive periods shown"),
    "animation.frames_per_period": (int, 4, 64, 16,
                                    "frames per drive period (per small swing for the string)"),
    "animation.L0": ("positive", 0, 1e6, 1.0, "the length's parameter L0 (m)"),
    "animation.v0": ("positive", 0, 1e6, 0.02,
                     "the rate v0 in L(t) (m/s); L0 - v0*t shortens the string"),
    "animation.g": ("positive", 0, 1000, 9.81, "gravitational acceleration g (m/s^2)"),
    "animation.theta_0": (float, -3.14159, 3.14159, 0.3,
                          "initial angle theta(0) (rad), not 0; theta'(0) = 0"),
    "animation.t_end": ("positive", 0, 1e6, 20.0, "the time shown (s), before L(t) reaches 0"),
}

#: Most frames of one animation (periods x frames_per_period, or the string's t_end in frames):
#: about 80 s of film, 2-4 MB of GIF and 30-40 s of drawing.
ANIMATION_MAX_FRAMES = 2000


def animation_frames_problem(frames):
    """The one-line problem of an animation of ``frames`` frames, or None."""
    if frames > ANIMATION_MAX_FRAMES:
        return (f"the animation would have {frames} frames; at most {ANIMATION_MAX_FRAMES} "
                "(fewer periods, or fewer frames per period)")
    return None


def _show(value):
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def ascii_digits(text):
    """Whether ``text`` is a whole number written with the digits 0-9 only (str.isdigit
    also takes superscripts and other scripts' digits, which int() then refuses or reads).

    >>> ascii_digits("12"), ascii_digits("\u00b3"), ascii_digits("\u0663"), ascii_digits("")
    (True, False, False, False)
    """
    return text.isascii() and text.isdigit()


def spec(name):
    """``(type, min, max, default, help)`` of option ``name`` (KeyError if unknown)."""
    return LIMITS[name]


def describe(name):
    """The range of ``name`` in words: '1 to 60', '1 to 100 entries', 'above 0, at most 10'."""
    kind, low, high, _default, _help = LIMITS[name]
    if kind is list:
        return f"{low} to {high} entries"
    if kind == "fraction":
        return f"above {low}, at most {high}"
    if kind == "positive":
        return f"above {low:g}, at most {high:g}"
    return f"{low:g} to {high:g}" if kind is float else f"{low} to {high}"


def option(name):
    """The product OPTIONS entry ``(type, default, help)`` of ``name``, its range in the help."""
    kind, _low, _high, default, text = LIMITS[name]
    kind = {"fraction": str, "positive": float}.get(kind, kind)
    return (kind, default, f"{text} ({describe(name)})")


def parse(name, text, label=None):
    """The command-line text ``text`` read as option ``name`` and checked (:func:`check`).

    Integers are ASCII digits with an optional sign; numbers decimals or fractions ("1e-3", "-1/5"),
    exactly, and returned as floats once in range.  A text that is not such a number is
    refused with the range and the text as given:

    >>> parse("sweep.theta_init", "-1/5", "--theta-init")
    -0.2
    >>> parse("experiments.grid", "2.5", "--grid")
    Traceback (most recent call last):
    ...
    pendulab.errors.InputError: --grid must be an integer from 1 to 400, got '2.5'
    """
    kind = LIMITS[name][0]
    if not isinstance(text, str):
        return check(name, text, label)
    if kind is int:
        # int() would also read other scripts' digits ("\u0663", fullwidth "\uff13"):
        # ASCII digits only, as fraction() does for numbers
        value = text
        if _INTEGER_TEXT.match(text.strip()):
            try:
                value = int(text.strip())
            except ValueError:  # more digits than Python converts (sys.set_int_max_str_digits)
                pass
        return _ascii_hint(name, value, label, text)
    if kind in (float, "positive"):
        try:
            value = fraction(text)
        except (ValueError, ZeroDivisionError):
            value = text
        try:
            check(name, value, label)
        except InputError:
            # the same message, showing the text as given
            _ascii_hint(name, text, label, text)
        return float(value)
    return _ascii_hint(name, text, label, text)


_INTEGER_TEXT = re.compile(r"[+-]?[0-9]+\Z")


def _ascii_hint(name, value, label, text):
    """:func:`check` of ``value``; when it is refused and ``text`` is not ASCII, the message
    says how numbers are written (other scripts' digits are not read)."""
    try:
        return check(name, value, label)
    except InputError as exc:
        if text.isascii():
            raise
        how = ("an integer is written with the ASCII digits 0-9" if LIMITS[name][0] is int
               else "a number is written in ASCII: the digits 0-9, '-', '.', 'e', '/'")
        raise InputError(f"{exc} ({how})") from None


def argument(parser, flag, name, text=None, **kwargs):
    """``parser.add_argument(flag, ...)`` for a numeric option whose range is ``LIMITS[name]``.

    The help is ``text`` (default: the entry's own) followed by the range in words;
    the argparse action remembers ``name`` (``action.limit``), so that a test can find
    every numeric option of the command line and its entry.  The value stays text:
    the command reads it with :func:`parse` (through :class:`Problems`).
    """
    kwargs.setdefault("help", f"{text or LIMITS[name][4]}, {describe(name)}")
    action = parser.add_argument(flag, **kwargs)
    action.limit = name
    return action


class Problems:
    """Collects every problem of one command line; :meth:`raise_any` raises them as one line.

    >>> p = Problems()
    >>> p.parse("experiments.grid", "0", "--grid"), p.parse("experiments.periods", "3", "--periods")
    (None, 3)
    >>> p.add("give --dask or --processes, not both")
    >>> p.raise_any()
    Traceback (most recent call last):
    ...
    pendulab.errors.InputError: --grid must be an integer from 1 to 400, got 0; give --dask or --processes, not both
    """

    def __init__(self):
        self.messages = []

    def add(self, message):
        """Record one problem (a line without the ``pendulab: error:`` prefix)."""
        self.messages.append(str(message))

    def parse(self, name, text, label):
        """:func:`parse` of ``text``; None (and the problem recorded) when it is refused."""
        return self.call(parse, name, text, label)

    def call(self, fn, *args, prefix="", **kwargs):
        """``fn(*args, **kwargs)``, or None with its InputError recorded (after ``prefix``)."""
        try:
            return fn(*args, **kwargs)
        except InputError as exc:
            self.add(f"{prefix}{exc}")
            return None

    def __bool__(self):
        return bool(self.messages)

    def raise_any(self):
        """Raise one InputError listing every problem recorded, in order ("; " between)."""
        raise_problems(self.messages)


def raise_problems(problems, prefix=""):
    """Raise one InputError listing ``problems`` ("; " between, after ``prefix``), or nothing.

    Its ``problems`` attribute keeps them apart, so that scene validation reports each
    under the product's key (:func:`pendulab.scene.validate_options`).
    """
    if problems:
        err = InputError(prefix + "; ".join(problems))
        err.problems = list(problems)
        raise err


def check(name, value, label=None):
    """Return ``value`` if it is of the type and in the range of ``name``; else InputError.

    ``label`` names the value in the message (default ``name``; ``""``: no
    name, for a scene's problem that already names the key).  The message is
    one line: ``<label> must be an integer from 1 to 60, got 0``.
    """
    if name not in LIMITS:
        raise InputError(f"no limit named {name!r} (see pendulab.limits.LIMITS)")
    kind, low, high, _default, _help = LIMITS[name]
    label = name if label is None else label
    label = label + " " if label else ""
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            raise InputError(f"{label}must be an integer from {low} to {high}, got {_show(value)}")
        return value
    if kind is float:
        if (isinstance(value, bool) or not isinstance(value, (int, float, Fraction))
                or not value == value or not low <= value <= high):
            raise InputError(f"{label}must be a number from {low:g} to {high:g}, got {_show(value)}")
        return value
    if kind == "positive":
        if (isinstance(value, bool) or not isinstance(value, (int, float, Fraction))
                or not value == value or not low < value <= high):
            raise InputError(f"{label}must be a number above {low:g} and at most {high:g}, "
                             f"got {_show(value)}")
        return value
    if kind is list:
        if not isinstance(value, list):
            raise InputError(f"{label}must be a list, got {_show(value)}")
        if not low <= len(value) <= high:
            raise InputError(f"{label}must have {low} to {high} entries, got {len(value)}")
        return value
    if kind == "fraction":
        try:
            number = fraction(value) if isinstance(value, (str, int)) and \
                not isinstance(value, bool) else None
        except (ValueError, ZeroDivisionError):
            number = None
        if number is None:
            raise InputError(f"{label}must be a decimal or a fraction, got {_show(value)}")
        if not low < number <= high:
            raise InputError(f"{label}must be above {low} and at most {high}, got {_show(value)}")
        return value
    raise TypeError(f"unknown kind {kind!r} in pendulab.limits")  # a bug in this table


# ---------------------------------------------------------------------------
# Work that depends on several options at once
# ---------------------------------------------------------------------------

#: The most work (in estimated seconds of one core) a product or command may ask for.
WORK_BUDGET_SECONDS = 60

#: The cost model of one Floquet point: seconds ~ BASE + COEF * sqrt(1 + S) * max(1, dps/30)**EXP
#: with S = |theta0| + 2|theta1|; (COEF, EXP) per method.  Fitted from above to the
#: measurements in docs/scenes.md ("Limits"): the estimate is at least the time measured.
FLOQUET_POINT_MODEL = {"hill": (1e-3, 0.5), "cf": (0.025, 0.5), "monodromy": (0.14, 1.5),
                       "arb": (3e-3, 1.0)}  # arb: 0.5 s at S = 3e4, 0.07 s at 1000 digits
#: One exact stability limit (first band at omega0/omega = r): 0.1 + 0.2*sqrt(r)*max(1, dps/30)**0.6.
FLOQUET_RATIO_MODEL = (0.1, 0.2, 0.6)
_POINT_BASE = 0.02


def _size(value):
    """|x| of a number given as text or number (None when it is not one; its own check says so)."""
    if isinstance(value, bool):
        return None
    try:
        return abs(float(fraction(value))) if isinstance(value, (str, int)) else \
            abs(float(value)) if isinstance(value, float) \
            else None
    except (ValueError, ZeroDivisionError, OverflowError):
        return None


#: Largest |theta0| + 2|theta1| of method "arb" (pendulab.analyses.floquet.SIZE_LIMITS["arb"],
#: not imported here so that the command line starts without mpmath; a test checks they agree).
ARB_SIZE = 3e4


def floquet_seconds(points, ratios, dps, method):
    """Estimated seconds of Floquet work: ``points`` [theta0, theta1] pairs, ``ratios`` omega0/omega.

    ``method`` "auto" (or None) is the API's own choice, point by point: "arb" with ``dps``
    up to |theta0| + 2|theta1| <= ARB_SIZE, "hill" otherwise."""
    scale = max(1.0, (dps or 16) / 30)
    total = 0.0
    for pt in points:
        if isinstance(pt, (list, tuple)) and len(pt) == 2:
            x0, x1 = _size(pt[0]), _size(pt[1])
            if x0 is not None and x1 is not None:
                used = method
                if method in (None, "auto"):
                    used = "arb" if dps is not None and x0 + 2 * x1 <= ARB_SIZE else "hill"
                coef, exp = FLOQUET_POINT_MODEL.get(used, FLOQUET_POINT_MODEL["monodromy"])
                total += _POINT_BASE + coef * (1 + x0 + 2 * x1) ** 0.5 * scale ** exp
    base, rcoef, rexp = FLOQUET_RATIO_MODEL
    for r in ratios:
        x = _size(r)
        if x is not None:
            total += base + rcoef * x ** 0.5 * scale ** rexp
    return total


#: Seconds per grid point of each stability method (fitted from above to measurements,
#: docs/scenes.md): fixed methods, then series:N ~ 0.005 + 0.0025 N**1.4 and
#: integer-series:N ~ 0.002 + 0.0002 N.
STABILITY_METHOD_SECONDS = {"exact": 0.08, "eq12": 0.002, "eq19": 0.002, "eq19-corrected": 0.002,
                            "eq28": 0.002}


def stability_seconds(points, methods):
    """Estimated seconds of the stability product: ``points`` grid values times each method."""
    per_point = 0.0
    for method in methods:
        if not isinstance(method, str):
            continue
        kind, _, order = method.partition(":")
        n = int(order) if ascii_digits(order) else 0
        if kind == "series":
            per_point += 0.005 + 0.0025 * n ** 1.4
        elif kind == "integer-series":
            per_point += 0.002 + 0.0002 * n
        else:
            per_point += STABILITY_METHOD_SECONDS.get(method, 0.0)
    return points * per_point


#: Largest count x dps of the certified zeros behind quarter periods (docs/bessel.md, benchmarks).
QUARTER_PERIOD_WORK = 1_000_000


#: Most oscillations (t_end sqrt(g/L0) / (2 pi), or t_end / T of a periodic L(t)) the motion
#: product integrates: three DOP853 runs at rtol 1e-13 of about 7 ms a period each (docs/scenes.md).
MOTION_MAX_PERIODS = 2000

#: Largest (zeros computed) x dps of the bessel product, as for quarter periods.
BESSEL_ZERO_WORK = QUARTER_PERIOD_WORK
#: How many times dearer a zero of J_nu can be for a non-integer order (arb's expansions need
#: much more precision there): measured on 2026-12-03 with ``pendulab bessel zeros --count 100
#: --dps 1000``, 9.96 s at order 299.99 against 1.82 s at order 300 (5.5x); orders just off an
#: integer (2.01) are slow at 1000 digits too.  The budget of a non-integer order is
#: BESSEL_ZERO_WORK / this.
BESSEL_NON_INTEGER_FACTOR = 6
#: Largest (nmax + 1) x (points + 9) x dps of the bessel product's identity checks (docs/scenes.md).
BESSEL_IDENTITY_WORK = 4_000_000

#: Seconds per RK4 step per trajectory of the experiments' sweeps: NumPy (the default backend,
#: also the fallback of "auto" without a compiler) and the C kernel, fitted from above to
#: docs/scenes.md ("Limits").
RK4_SECONDS = {"numpy": 1.5e-6, "c": 30e-9}


def backend_run(backend, compiler):
    """The RK4 backend a sweep asked for ``backend`` runs: "c" or "numpy"; "auto" runs the C
    kernel where a C compiler is found (``compiler``: the caller's look-up, e.g.
    :func:`pendulab.numerics.ckernel.compiler_found`, not made here: this module imports no
    numerics)."""
    return "c" if backend == "c" or (backend == "auto" and compiler) else "numpy"


def experiments_seconds(options, compiler=False):
    """Estimated seconds of the experiments product's trajectories (maps, first experiment,
    Figs. 5, 2); ``compiler``: whether a C compiler was found (the cost of backend "auto")."""
    per = RK4_SECONDS[backend_run(options.get("backend"), compiler)]
    steps = options["periods"] * options["steps_per_period"]
    nonlinear = [c for c in options["criteria"] if c != "floquet"]
    cells = 0
    if nonlinear:
        runs = len(nonlinear) if options.get("prune") else 1
        cells += len(options["maps"]) * options["grid"] ** 2 * runs
    if options.get("first_experiment"):
        cells += 100 * options["first_grid"] ** 2
    seconds = cells * steps * per
    # Figs. 5 and 2: single trajectories (the DOP853 reference dominates: ~1 ms per period)
    seconds += 1e-3 * ((options["fig5_periods"] if options.get("fig5") else 0)
                       + (options["fig2_periods"] if options.get("fig2") else 0))
    return seconds


def bessel_work_problems(options):
    """The one-line problems of the bessel product's work (an empty list when it fits): the
    zeros and the identities, each from its own options where they are ints (a bad nmax does
    not hide the zeros' work)."""
    z, c, st, dps = (options.get(k) for k in ("zeros", "count", "start", "dps"))
    problems = []
    need = max(z, c + max(st, 1) + 2) if _ints(z, c, st, dps) else 0
    if need and need * dps > BESSEL_ZERO_WORK:
        problems.append(f"about {need} zeros at dps = {dps} (zeros, or count + start + 2) is "
                        f"more than {BESSEL_ZERO_WORK} digits in all (about a minute): ask for "
                        "fewer or shorter numbers")
    n, pts = options.get("nmax"), options.get("points")
    if _ints(n, pts, dps) and (n + 1) * (pts + 9) * dps > BESSEL_IDENTITY_WORK:
        problems.append(f"the identities for n = 0..{n} at {pts} points and dps = {dps} are "
                        f"(nmax + 1) (points + 9) dps = {(n + 1) * (pts + 9) * dps} > "
                        f"{BESSEL_IDENTITY_WORK} (about a minute): ask for fewer points or digits")
    return problems


def _ints(*values):
    """Whether every one of ``values`` is an int (not a bool): an option checked in range."""
    return all(isinstance(v, int) and not isinstance(v, bool) for v in values)


def work_problem(product, options, what="the points and ratios asked", drive_period=None,
                 compiler=False):
    """A one-line problem when ``options`` of ``product`` would pass :data:`WORK_BUDGET_SECONDS`
    (``compiler``: whether a C compiler was found, for the experiments' backend "auto")."""
    import math
    if product == "motion":
        try:
            periods = options["t_end"] * math.sqrt(options["g"] / options["L0"]) / (2 * math.pi)
            if drive_period:
                periods = max(periods, options["t_end"] / drive_period)
        except (TypeError, ValueError, ZeroDivisionError, KeyError):
            return None
        if periods <= MOTION_MAX_PERIODS:
            return None
        return (f"t_end = {options['t_end']:g} s is about {periods:.0f} oscillations "
                f"({'of L(t), ' if drive_period else ''}t_end sqrt(g/L0) / (2 pi)); at most "
                f"{MOTION_MAX_PERIODS} (about a minute of DOP853 at rtol 1e-13): ask for a "
                "shorter t_end")
    if product == "bessel":
        return "; ".join(bessel_work_problems(options)) or None
    if product == "experiments":
        try:
            seconds = experiments_seconds(options, compiler)
        except (TypeError, KeyError):
            return None
        if seconds <= WORK_BUDGET_SECONDS:
            return None
        backend = options.get("backend")
        runs = backend_run(backend, compiler)
        ways = ["a smaller grid", "fewer periods or steps", "fewer maps"]
        ways += [] if options.get("prune") else ["prune = true"]
        ways += [] if runs == "c" else ['backend = "c" (with a C compiler)' if backend == "auto"
                                        else 'backend = "c"']
        how = ("" if backend != "auto" else ", the C kernel: a C compiler is found" if runs == "c"
               else ", NumPy: no C compiler found")
        return (f"these maps would take about {seconds:.0f} s of RK4 by the cost model of "
                f"pendulab.limits (limit {WORK_BUDGET_SECONDS} s with backend "
                f"{backend!r}{how}): ask for {', '.join(ways[:-1])} or {ways[-1]}")
    if product == "stability":
        points, methods = options.get("points"), options.get("methods")
        if not isinstance(points, int) or not isinstance(methods, list):
            return None
        seconds = stability_seconds(points, methods)
        if seconds <= WORK_BUDGET_SECONDS:
            return None
        return (f"{points} points with these methods would take about {seconds:.1f} s by the "
                f"cost model of pendulab.limits (limit {WORK_BUDGET_SECONDS} s): ask for fewer "
                "points or lower series orders")
    if product == "quarter_periods":
        count, dps = options.get("count"), options.get("dps")
        if isinstance(count, int) and isinstance(dps, int) and count * dps > QUARTER_PERIOD_WORK:
            return (f"count x dps = {count * dps} is more than {QUARTER_PERIOD_WORK} (10000 zeros "
                    "at 100 digits, or 1000 at 1000, take about a minute): ask for fewer or "
                    "shorter numbers")
        return None
    if product != "floquet":
        return None
    points, ratios = options.get("points") or [], options.get("ratios") or []
    if not isinstance(points, list) or not isinstance(ratios, list):
        return None
    dps = options.get("dps")
    dps = dps if isinstance(dps, int) and not isinstance(dps, bool) else None
    seconds = floquet_seconds(points, ratios, dps, options.get("method", "hill"))
    if seconds <= WORK_BUDGET_SECONDS:
        return None
    ways = ["fewer points or ratios"] if len(points) + len(ratios) > 1 else []
    ways += ["a lower dps", "a smaller |theta0| + 2|theta1|"]
    ways += [] if options.get("method", "hill") == "hill" else ["method 'hill'"]
    return (f"{what} would take about {seconds:.1f} s by the cost model of pendulab.limits "
            f"(limit {WORK_BUDGET_SECONDS} s): ask for {', '.join(ways[:-1])} or {ways[-1]}")


# ---------------------------------------------------------------------------
# ``pendulab sweep`` and ``pendulab simulate``: the work of the options together
# ---------------------------------------------------------------------------

#: Seconds per cell of the floquet criterion (no integration): Mathieu's equation (the
#: vectorised exact verdict) and any other drive (one monodromy matrix per cell), fitted from
#: above to the grid-400 sweeps of docs/scenes.md ("Limits").
FLOQUET_CELL_SECONDS = {"mathieu": 1e-4, "hill": 1e-3}


def sweep_seconds(cells, steps, backend, criterion="mean", drive=False):
    """Estimated seconds of a sweep: RK4 for ``cells`` trajectories of ``steps`` steps
    (RK4_SECONDS of ``backend``), or the floquet criterion's verdicts (``drive``: a drive
    other than the source's, possibly not Mathieu's)."""
    if criterion == "floquet":
        return cells * FLOQUET_CELL_SECONDS["hill" if drive else "mathieu"]
    return cells * steps * RK4_SECONDS["c" if backend == "c" else "numpy"]


def sweep_problem(cells, steps, backend, criterion="mean", drive=False):
    """A one-line problem when a sweep's work passes :data:`WORK_BUDGET_SECONDS` (else None)."""
    seconds = sweep_seconds(cells, steps, backend, criterion, drive)
    if seconds <= WORK_BUDGET_SECONDS:
        return None
    if criterion == "floquet":
        return (f"{cells} Floquet verdicts{' of this drive' if drive else ''} would take about "
                f"{seconds:.0f} s by the cost model of pendulab.limits (limit "
                f"{WORK_BUDGET_SECONDS} s): ask for a smaller --grid")
    return (f"{cells} trajectories x {steps} RK4 steps would take about {seconds:.0f} s by the "
            f"cost model of pendulab.limits (limit {WORK_BUDGET_SECONDS} s with the "
            f"{'C kernel' if backend == 'c' else 'NumPy backend (no C compiler found)'}): "
            "ask for a smaller --grid, fewer --periods or --steps-per-period")


#: Seconds per RK4 step of one ``pendulab simulate`` trajectory (every state kept, then the
#: statistics pass): C kernel 1e7 steps in 8 s, NumPy 1e5 steps in 30 s (docs/scenes.md).
TRAJECTORY_STEP_SECONDS = {"c": 1e-6, "numpy": 4e-4}
#: Most RK4 steps (periods x steps per period) of one simulation (the states: 160 MB).
SIMULATE_MAX_STEPS = 10**7
#: Most rows ``pendulab simulate`` prints after the initial state (periods x steps per period / every).
SIMULATE_MAX_ROWS = 10**6
#: With ``--reference``, most RK4 steps (DOP853's dense output is evaluated at every one).
REFERENCE_MAX_STEPS = 10**6
#: DOP853 (rtol 1e-13) right-hand-side evaluations per drive period, estimated from above as
#: 400 (1.5 + sqrt(S)) + 8000 max(0, sqrt(|dtheta/dtau(0)|) - 1), S = |theta0| + 2|theta1|
#: (fitted to the
#: counts in docs/scenes.md, "Limits").
REFERENCE_EVALUATIONS_MODEL = (400, 1.5, 8000)
#: Most DOP853 evaluations of one reference (about 20 us each: about 40 s); the estimate
#: refuses larger runs before any work, and the reference itself stops at this count.
REFERENCE_MAX_EVALUATIONS = 2_000_000


def reference_evaluations(periods, size, rate=0.0):
    """Estimated DOP853 evaluations over ``periods`` drive periods at size S = ``size``
    from the initial rate ``rate`` = dtheta/dtau(0)."""
    coef, base, rate_coef = REFERENCE_EVALUATIONS_MODEL
    return periods * (coef * (base + size ** 0.5) + rate_coef * max(0.0, abs(rate) ** 0.5 - 1))


def simulate_problems(periods, steps, every, size, backend, rate=0.0):
    """The one-line problems of a simulation's work (an empty list when it fits).

    ``size`` is S = |theta0| + 2|theta1| of the point when the DOP853 reference is asked
    for (else None), ``rate`` the initial dtheta/dtau; ``backend`` "c" or "numpy" is the
    RK4 backend expected.
    """
    problems = []
    total = periods * steps
    seconds = total * TRAJECTORY_STEP_SECONDS["c" if backend == "c" else "numpy"]
    if total > SIMULATE_MAX_STEPS:
        problems.append(f"--periods x --steps-per-period must be at most {SIMULATE_MAX_STEPS:.0e}, "
                        f"got {total}")
    elif seconds > WORK_BUDGET_SECONDS:
        problems.append(f"{total} RK4 steps would take about {seconds:.0f} s with the NumPy backend "
                        f"(no C compiler found; limit {WORK_BUDGET_SECONDS} s): ask for fewer "
                        "--periods or --steps-per-period")
    if total // every > SIMULATE_MAX_ROWS:
        problems.append(f"{total // every + 1} rows would be printed (--periods x "
                        f"--steps-per-period / --every + 1); at most {SIMULATE_MAX_ROWS:.0e} + 1: "
                        "ask for a larger --every")
    if size is not None:
        if total > REFERENCE_MAX_STEPS:
            problems.append(f"with --reference, --periods x --steps-per-period must be at most "
                            f"{REFERENCE_MAX_STEPS:.0e} (DOP853 at rtol 1e-13 is evaluated at "
                            f"every step), got {total}")
        evaluations = reference_evaluations(periods, size, rate)
        if evaluations > REFERENCE_MAX_EVALUATIONS:
            problems.append(f"the DOP853 reference would need about {evaluations:.2g} evaluations "
                            f"(|theta0| + 2|theta1| = {size:.3g}, dtheta/dtau(0) = {rate:g}, "
                            f"{periods} periods); at most {REFERENCE_MAX_EVALUATIONS:.2g} (about "
                            "40 s): ask for fewer --periods, a smaller --a-over-l, --w0-over-w "
                            "or --omega-init")
    return problems


#: CPU seconds of ``pendulab bessel identities`` per (order, point) pair (both engines, all
#: rules) measured at these digits (docs/scenes.md, "Limits"); the cost model interpolates
#: them log-log and adds half (IDENTITY_MARGIN).  (The bessel product checks at min(dps, 50)
#: digits: BESSEL_IDENTITY_WORK bounds it.)
IDENTITY_SECONDS_PER_PAIR = ((30, 2.4e-3), (100, 5.5e-3), (300, 0.046), (1000, 1.36))
IDENTITY_MARGIN = 1.5


def identities_seconds(nmax, points, dps):
    """Estimated seconds of the identity checks for n = 0..nmax at ``points`` z (plus 9 near zeros)."""
    import math
    table = IDENTITY_SECONDS_PER_PAIR
    if dps <= table[0][0]:
        per = table[0][1]
    else:
        (d0, c0), (d1, c1) = next((table[k], table[k + 1]) for k in range(len(table) - 1)
                                  if dps <= table[k + 1][0] or k == len(table) - 2)
        x = (math.log(dps) - math.log(d0)) / (math.log(d1) - math.log(d0))
        per = math.exp(math.log(c0) + x * (math.log(c1) - math.log(c0)))
    return IDENTITY_MARGIN * per * (nmax + 1) * (points + 9)
