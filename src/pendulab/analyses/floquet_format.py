"""Text forms of Floquet results shared by the floquet command and product.

Numbers become strings at full precision: reals as mpmath prints them,
complex values as ``re+imj`` (Python's ``complex`` reads them in double
precision; :func:`parse_number` reads them at the current mpmath precision).
"""

import re

import mpmath

_COMPLEX = re.compile(r"^(?P<re>[+-]?[0-9.]+(?:e[+-]?\d+)?)(?P<im>[+-][0-9.]+(?:e[+-]?\d+)?)j$")


def parse_number(text):
    """Inverse of :func:`number_text` at the current mpmath precision."""
    m = _COMPLEX.match(text.strip())
    if m:
        return mpmath.mpc(mpmath.mpf(m.group("re")), mpmath.mpf(m.group("im")))
    return mpmath.mpf(text)


def number_text(x, dps):
    """Full-precision text of a real or complex number (float/complex or mpf/mpc)."""
    if dps is None:
        z = complex(x)
        if z.imag == 0:
            return repr(z.real)
        sign = "+" if z.imag >= 0 else "-"
        return f"{z.real!r}{sign}{abs(z.imag)!r}j"
    with mpmath.workdps(dps + 10):
        z = mpmath.mpmathify(x)
        if isinstance(z, mpmath.mpf) or mpmath.im(z) == 0:
            return mpmath.nstr(mpmath.re(z), dps)
        im = mpmath.im(z)
        sign = "+" if im >= 0 else "-"
        return f"{mpmath.nstr(mpmath.re(z), dps)}{sign}{mpmath.nstr(abs(im), dps)}j"


def result_record(result, theta0_text, theta1_text):
    """JSON-ready dict of a FloquetResult (keys as documented in docs/floquet.md)."""
    dps = result.dps
    return {
        "theta0": str(theta0_text),
        "theta1": str(theta1_text),
        "lambda": number_text(result.lam, dps),
        "multipliers": [number_text(m, dps) for m in result.multipliers],
        "stable": bool(result.stable),
        "on_boundary": bool(result.on_boundary),
        "depth": int(result.depth),
        "method": result.method,
        "dps": dps,
        "certified_digits": getattr(result, "certified_digits", None),
    }
