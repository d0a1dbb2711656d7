"""Figures as deterministic PNG and PDF bytes (the products ``motion`` and ``experiments``).

matplotlib writes the date and its own version into PNG and PDF metadata;
:func:`save` removes them, so the same figure gives the same bytes on every
run (``pendulab build`` must reproduce generated/ byte for byte).

* :func:`pyplot` - (matplotlib, matplotlib.pyplot) on the Agg backend, or a
  one-line :class:`~pendulab.errors.InputError` naming the product when
  matplotlib (the "figures" extra) is not installed;
* :func:`save` - {".png": bytes, ".pdf": bytes} of a figure at ``dpi``.

>>> matplotlib, plt = pyplot("demo")
>>> fig, ax = plt.subplots()
>>> _ = ax.plot([0, 1], [1, 0])
>>> first, second = save(fig), save(fig)
>>> plt.close(fig)
>>> first == second, first[".png"][:4], first[".pdf"][:5]
(True, b'\\x89PNG', b'%PDF-')
"""

from pendulab.errors import InputError

#: metadata keys matplotlib fills with a date or its version, removed (None) on save
PNG_METADATA = {"Software": None}
PDF_METADATA = {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None}


def pyplot(what):
    """(matplotlib, matplotlib.pyplot) with the Agg backend; ``what`` names the product."""
    try:
        import matplotlib
    except ImportError:
        raise InputError(f"the {what} figures need matplotlib: pip install 'pendulab[figures]' "
                         "(or set figures = false)") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401  (matplotlib.ticker for the callers)
    return matplotlib, plt


def save(fig, dpi=150):
    """{".png": bytes, ".pdf": bytes} of ``fig`` (PNG at ``dpi``), no dates or versions inside."""
    import io
    out = {}
    for ext, meta, kw in ((".png", PNG_METADATA, {"dpi": dpi}), (".pdf", PDF_METADATA, {})):
        buf = io.BytesIO()
        fig.savefig(buf, format=ext[1:], metadata=meta, **kw)
        out[ext] = buf.getvalue()
    return out
