"""Text forms of Floquet results shared by the floquet command and product.

Numbers become strings at full precision: reals as mpmath prints them,
complex values as ``re+imj`` (readable by Python's ``complex`` and by
``mpmath.mpmathify``).
"""

import mpmath


def number_text(x, dps):
    """Full-precision text of a real or complex number (float/complex or mpf/mpc)."""
    if dps is None:
        z = complex(x)
        if z.imag == 0:
            return repr(z.real)
        sign = "+" if z.imag >= 0 else "-"
        return f"{z.real!r}{sign}{abs(z.imag)!r}j"
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
    }
