"""The ``pendulab`` command line.

Each sub-command lives in ``pendulab.commands.<name>`` with ``add_parser``
and ``run``.  Errors a user can cause print one line per problem,
``pendulab: error: ...``, and exit with status 2; nothing is written.

Option values may start with '-' (``--theta0 -1/5``, ``--drive -a*cos(omega*t)``):
:func:`join_negative_values` attaches such a value to its option before
argparse sees it.  Help texts show a default only where there is one
(:class:`HelpFormatter`).
"""

import argparse
import importlib
import sys

from pendulab import __version__

COMMANDS = ("derive", "build", "series", "floquet", "stability", "bessel", "sweep", "simulate", "latex",
            "animate")


def available_commands():
    """The names in COMMANDS whose modules are installed (tests require all of them)."""
    import importlib.util
    return [n for n in COMMANDS if importlib.util.find_spec(f"pendulab.commands.{n}")]


class ArgumentParser(argparse.ArgumentParser):
    """argparse with its usage errors as one line, ``pendulab: error: ...``, exit status 2.

    argparse prints the usage text before its message; here the message says
    where to look instead (sub-command parsers are of this class too).
    """

    def error(self, message):
        print(f"pendulab: error: {self.prog}: {message} (see '{self.prog} --help')",
              file=sys.stderr)
        raise SystemExit(2)


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Show "(default: X)" only for a real default the help does not already state.

    No "(default: None)" on required options or options without a default,
    no "(default: False)" on flags, no second default after one in the text.
    """

    def _get_help_string(self, action):
        text = action.help or ""
        if (action.default in (None, False, argparse.SUPPRESS) or action.required
                or "default" in text or not action.option_strings):
            return text
        return text + " (default: %(default)s)"


def _format_everywhere(parser):
    """Give ``parser`` and every sub-command parser the :class:`HelpFormatter`."""
    stack = [parser]
    while stack:
        p = stack.pop()
        p.formatter_class = HelpFormatter
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())


def _option_strings(parser):
    """(all option strings, those that take a value) of ``parser`` and its sub-commands."""
    every, valued = set(), set()
    stack = [parser]
    while stack:
        p = stack.pop()
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())
            elif action.option_strings:
                every.update(action.option_strings)
                if action.nargs != 0:
                    valued.update(action.option_strings)
    return every, valued


def join_negative_values(argv, value_options, known_options=()):
    """``["--theta0", "-1/5"]`` -> ``["--theta0=-1/5"]`` for options that take a value.

    argparse reads a token that starts with '-' (other than a plain negative
    decimal) as an option, so ``--theta0 -1/5`` would fail with "expected one
    argument".  After an option that takes a value, a token that starts with
    '-' and is not one of ``known_options`` (nor ``--``) is that value.
    """
    known = set(known_options)
    out = []
    i = 0
    while i < len(argv):
        tok = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if (tok in value_options and nxt is not None and nxt.startswith("-") and nxt != "--"
                and nxt.split("=", 1)[0] not in known and len(nxt) > 1):
            out.append(f"{tok}={nxt}")
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def make_parser():
    parser = ArgumentParser(
        prog="pendulab",
        description="Symbolic-numeric derivations for parametrically driven pendulums.",
        epilog="Run 'pendulab COMMAND --help' for the options of each command.",
    )
    parser.add_argument("--version", action="version", version=f"pendulab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in available_commands():
        importlib.import_module(f"pendulab.commands.{name}").add_parser(sub)
    _format_everywhere(parser)
    return parser


_INTERRUPTED = []


def _on_interrupt(signum, frame):
    # remembered, so that an import torn by Ctrl-C (ImportError: initialization failed)
    # is reported as the interruption it is
    _INTERRUPTED.append(signum)
    raise KeyboardInterrupt


def main(argv=None):
    import signal
    import threading

    from pendulab.errors import PendulabError
    parser = make_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    every, valued = _option_strings(parser)
    args = parser.parse_args(join_negative_values(argv, valued, every))
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, _on_interrupt)
    try:
        return int(args.func(args) or 0)
    except PendulabError as exc:
        for line in str(exc).splitlines() or [type(exc).__name__]:
            print(f"pendulab: error: {line}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 1
    except (KeyboardInterrupt, Exception):
        if not _INTERRUPTED and not isinstance(sys.exc_info()[1], KeyboardInterrupt):
            raise
        print("pendulab: error: interrupted (outputs are published whole or not at all)",
              file=sys.stderr)
        return 130


#: Python's int-to-text limit in the ``pendulab`` command (sys.set_int_max_str_digits; the
#: default is 4300): numbers of a derivation print whole, reading a number stays quick.
MAX_INT_DIGITS = 100_000

#: gc.set_threshold of the ``pendulab`` command (see :func:`console`).
GC_THRESHOLDS = (20000, 50, 100)


def console(argv=None):
    """The ``pendulab`` command: :func:`main`, then exit at once with its status.

    A build leaves a large heap (SymPy's caches, matplotlib, NumPy arrays);
    tearing it down object by object takes a quarter of a second that
    nobody waits for, so the process ends with ``os._exit`` once standard
    output and standard error are flushed.  Everything the command writes is
    closed before :func:`main` returns (outputs are published by rename,
    the lock released), and no pendulab code relies on exit handlers.  An
    exception that :func:`main` lets through (a bug: a traceback) takes the
    ordinary exit.

    The cyclic garbage collector runs less often than Python's default (a
    young collection every 20000 net allocations of containers instead of
    700): SymPy allocates millions of short-lived containers, few of them in
    cycles, and with the default the collector took about 10% of a build's
    CPU (0.68 s of one serial build, measured with ``gc.callbacks``; 0.2 s
    with these thresholds, for 5% more peak memory).
    """
    import gc
    import os
    gc.set_threshold(*GC_THRESHOLDS)
    # numbers in expressions have at most pendulab.exprs.MAX_NUMBER_DIGITS digits, but a
    # derivation multiplies them (a series to order 12 of a drive with a 1000-digit amplitude)
    # beyond the 4300 digits Python prints by default; a bound is kept (MAX_INT_DIGITS) so that
    # a scene or an argument with a number of millions of digits is refused at once, not read
    # for a minute (the conversion takes time quadratic in the digits)
    sys.set_int_max_str_digits(MAX_INT_DIGITS)
    status = main(argv)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe (pendulab ... | head)
            status = status or 1
    os._exit(status)


if __name__ == "__main__":
    console()
