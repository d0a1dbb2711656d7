"""The ``pendulab`` command line.

Each sub-command lives in ``pendulab.commands.<name>`` with ``add_parser``
and ``run``.  Errors a user can cause print one line per problem,
``pendulab: error: ...``, and exit with status 2; nothing is written.
"""

import argparse
import importlib
import sys

from pendulab import __version__

COMMANDS = ("derive", "build", "series", "floquet", "stability", "sweep", "simulate")


def available_commands():
    """The names in COMMANDS whose modules are installed (tests require all of them)."""
    import importlib.util
    return [n for n in COMMANDS if importlib.util.find_spec(f"pendulab.commands.{n}")]


def make_parser():
    parser = argparse.ArgumentParser(
        prog="pendulab",
        description="Symbolic-numeric derivations for parametrically driven pendulums.",
        epilog="Run 'pendulab COMMAND --help' for the options of each command.",
    )
    parser.add_argument("--version", action="version", version=f"pendulab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in available_commands():
        importlib.import_module(f"pendulab.commands.{name}").add_parser(sub)
    return parser


def main(argv=None):
    from pendulab.errors import PendulabError
    parser = make_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except PendulabError as exc:
        for line in str(exc).splitlines() or [type(exc).__name__]:
            print(f"pendulab: error: {line}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 1


if __name__ == "__main__":
    sys.exit(main())
