"""Exceptions and warnings raised by pendulab.

Every error a user can provoke is a ``ValueError`` subclass carrying a
one-line message that names what is wrong and where.
"""


class PendulabError(ValueError):
    """Base class of all pendulab errors (a ValueError: bad input or domain)."""


class InputError(PendulabError):
    """A bad argument to an API call or the command line."""


class ParameterError(InputError):
    """Bad parameters of a system; ``problems`` lists (parameter, message) pairs.

    The message is every problem, ``parameter: message``, joined by "; ".
    """

    def __init__(self, problems):
        self.problems = list(problems)
        super().__init__("; ".join(f"{key}: {msg}" for key, msg in self.problems))


class SceneError(PendulabError):
    """A scene file that cannot be used; the message names file and key."""

    def __init__(self, path, key, problem):
        self.path = str(path)
        self.key = key
        self.problem = problem
        where = f"{self.path}: {key}" if key else self.path
        super().__init__(f"{where}: {problem}")


class PrecisionError(PendulabError):
    """The requested working precision cannot resolve the requested answer."""


class ConvergenceError(PendulabError):
    """An iteration or a truncation did not converge to the requested accuracy."""


class SeriesDomainError(PendulabError):
    """A series was asked for outside its domain (near integer nu, beyond its radius)."""


class DerivationOrderError(PendulabError):
    """A derivation result was read before the step that computes it ran."""


class AccuracyWarning(UserWarning):
    """A result is returned, but with less accuracy than asked for (estimate attached)."""
