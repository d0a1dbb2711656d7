"""The C kernel of a first-order system: compiled on first use, cached, loaded with ctypes.

:func:`load` prints the C99 text of :func:`pendulab.numerics.codegen.c_kernel`,
compiles it with the system C compiler into a shared library and loads it with
:mod:`ctypes`.  The library is cached in a user cache directory under a name
that is the SHA-256 of the source text, the compiler's identity (its path and
``--version``), the flags and the machine (the flags include
``-march=native``, so the CPU's feature flags are part of the key).  A second
use, in this or any later process, loads the cached library without compiling.

* Compiler: ``$PENDULAB_CC``, else ``$CC``, else ``cc``.
* Cache directory: ``$PENDULAB_CACHE_DIR``, else ``$XDG_CACHE_HOME/pendulab``,
  else ``~/.cache/pendulab``; libraries go to its ``kernels`` subdirectory.
  Each is written to a temporary file in that directory and renamed into place,
  so concurrent processes never load a half-written library.
* Flags (:data:`FLAG_SETS`, the first that compiles): ``-O3 -std=c99
  -fno-math-errno -ffp-contract=off -fopenmp-simd -march=native
  -mprefer-vector-width=512``, then without the vector width, then without
  ``-march=native``.  No ``-ffast-math``: no reassociation, no flush to zero, NaN
  and infinity kept; ``-fno-math-errno`` only stops library functions from
  setting errno.  ``-ffp-contract=off`` forbids fusing a*b + c into an FMA: with
  it, and the kernel's own sine and cosine (:mod:`pendulab.numerics.codegen`),
  every operation is an IEEE double operation in the order printed, so the
  results are the same bits on every machine and vector width (an AVX-512 build
  and an SSE2 build are compared bit for bit in the tests) as long as the
  right-hand side has only arithmetic, integer powers, sin and cos (exp, log, a
  real power are as the C library rounds them, and so is a block rerun with the
  library sine).  FMA contraction was measured
  1.7x faster but changes the bits with the machine, and chaotic trajectories
  then change the verdicts of a few cells in 10^4 (see docs/numerics.md).
  The 512-bit vectors take AVX-512 where present (measured 1.6x faster).
  Threads are POSIX threads created and joined in each call, so the library is
  safe in forked worker processes.
* No compiler, or every compile failing: ``load`` prints one line on stderr
  (once per process and system) and returns None, and the callers take the
  NumPy path; ``load(required=True)`` raises :class:`~pendulab.errors.InputError`
  instead.
* :func:`load_source` builds a hand-written C source the same way (the band
  Newton kernel of :mod:`pendulab.analyses.floquet._vectorised`) and returns the
  :class:`ctypes.CDLL`, or None with the same one-line notice.
"""

import ctypes
import hashlib
import os
import platform
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from pendulab.errors import InputError

#: tried in this order; the first that compiles is used
FLAG_SETS = (
    ("-O3", "-std=c99", "-fno-math-errno", "-ffp-contract=off", "-fopenmp-simd", "-march=native",
     "-mprefer-vector-width=512"),
    ("-O3", "-std=c99", "-fno-math-errno", "-ffp-contract=off", "-fopenmp-simd", "-march=native"),
    ("-O3", "-std=c99", "-fno-math-errno", "-ffp-contract=off"),
)
_LINK = ("-shared", "-fPIC", "-pthread")
COMPILE_TIMEOUT = 120

_LOADED = {}     # key of the source text -> Kernel or the reason it failed
_NOTIFIED = set()
_IDENTITY = {}


def compiler_command():
    """The C compiler as an argument list (``$PENDULAB_CC``, ``$CC`` or ``cc``)."""
    text = os.environ.get("PENDULAB_CC") or os.environ.get("CC") or "cc"
    return shlex.split(text)


def compiler_found():
    """The path of the C compiler :func:`compiler_command` names where it is found on this
    machine (on the PATH, or as given), else None: whether the "auto" backend can expect C
    (a found compiler may still fail; :func:`available` compiles a probe to know)."""
    cmd = compiler_command()
    return shutil.which(cmd[0]) if cmd else None


def cache_dir():
    """The directory compiled kernels are cached in (see the module docstring)."""
    base = os.environ.get("PENDULAB_CACHE_DIR")
    if base:
        return Path(base) / "kernels"
    xdg = os.environ.get("XDG_CACHE_HOME")
    root = Path(xdg) if xdg else Path.home() / ".cache"
    return root / "pendulab" / "kernels"


def _cpu_flags():
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith(("flags", "Features")):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def _identity(cmd):
    """The compiler's path and first line of ``--version`` (None if it cannot run)."""
    key = tuple(cmd)
    if key not in _IDENTITY:
        exe = shutil.which(cmd[0]) if cmd else None
        if exe is None:
            _IDENTITY[key] = None
        else:
            try:
                res = subprocess.run([*cmd, "--version"], capture_output=True, text=True,
                                     timeout=30)
                first = (res.stdout or res.stderr).strip().splitlines()
                _IDENTITY[key] = f"{exe} {' '.join(cmd[1:])} {first[0] if first else ''}"
            except (OSError, subprocess.SubprocessError):
                _IDENTITY[key] = None
    return _IDENTITY[key]


def _key(source, identity, flags):
    h = hashlib.sha256()
    for part in (source, identity, " ".join(flags), platform.machine(), _cpu_flags()):
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()


def _first_line(text):
    for line in (text or "").splitlines():
        if line.strip():
            return line.strip()[:200]
    return "no message"


def _compile(source, cmd, flags, target):
    """Compile ``source`` into ``target`` (atomically); return None or the error's first line."""
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_c = tempfile.mkstemp(dir=target.parent, prefix=".src-", suffix=".c")
    with os.fdopen(fd, "w") as fh:
        fh.write(source)
    fd, tmp_so = tempfile.mkstemp(dir=target.parent, prefix=".lib-", suffix=".so")
    os.close(fd)
    try:
        res = subprocess.run([*cmd, *flags, *_LINK, "-o", tmp_so, tmp_c, "-lm"],
                             capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
        if res.returncode != 0:
            return _first_line(res.stderr or res.stdout)
        os.replace(tmp_so, target)
        os.replace(tmp_c, target.with_suffix(".c"))
        return None
    except (OSError, subprocess.SubprocessError) as exc:
        return _first_line(str(exc))
    finally:
        for p in (tmp_c, tmp_so):
            if os.path.exists(p):
                os.unlink(p)


_D = ctypes.c_double
_PD = ctypes.POINTER(ctypes.c_double)
_L = ctypes.c_long
_I = ctypes.c_int


def _ptr(a):
    return a.ctypes.data_as(_PD)


class Kernel:
    """A loaded C kernel of one first-order system (arguments as in the C interface)."""

    def __init__(self, path, nparams, flags):
        self.library = Path(path)
        self.nparams = nparams
        self.flags = tuple(flags)
        lib = ctypes.CDLL(str(path))
        lib.pendulab_ensemble_rk4.argtypes = [_L, _PD, _PD, _D, _D, _L, _I, _I, _I, _PD, _PD, _PD,
                                              _PD]
        lib.pendulab_ensemble_rk4.restype = _L
        lib.pendulab_rk4_path.argtypes = [_PD, _PD, _D, _D, _L, _I, _PD]
        lib.pendulab_rk4_path.restype = _L
        lib.pendulab_rhs_points.argtypes = [_L, _PD, _PD, _PD, _I, _PD]
        lib.pendulab_rhs_points.restype = None
        lib.pendulab_trig_points.argtypes = [_L, _PD, _I, _PD]
        lib.pendulab_trig_points.restype = None
        self._lib = lib

    def _params(self, p, n):
        p = np.ascontiguousarray(p, dtype=float)
        if self.nparams == 0:
            return np.zeros((max(n, 1), 1))
        return p

    def ensemble(self, y0, p, t0, dt, steps, linear=False, stats=True, threads=1,
                 library_sine=False):
        """(y (n, 2), mean (n,), mean |theta| (n,), max |theta| (n,), blocks rerun with the
        library sine); y0 (n, 2), p (n, k).  ``library_sine``: the C library's sin and cos
        throughout instead of the vectorisable ones (the benchmark compares them)."""
        y0 = np.ascontiguousarray(y0, dtype=float)
        n = y0.shape[0]
        p = self._params(p, n)
        y = np.empty((n, 2))
        mean, mabs, mx = np.empty(n), np.empty(n), np.empty(n)
        status = self._lib.pendulab_ensemble_rk4(
            n, _ptr(y0), _ptr(p), t0, dt, steps, int(linear), int(library_sine), int(threads),
            _ptr(y), _ptr(mean), _ptr(mabs), _ptr(mx))
        if status < 0:
            raise InputError("the C kernel could not start its threads (out of memory?)")
        if not stats:
            mean[:] = mabs[:] = mx[:] = np.nan
        return y, mean, mabs, mx, int(status)

    def path(self, y0, p, t0, dt, steps, linear=False):
        """One trajectory, states (steps + 1, 2) (the library sine if an argument is too big)."""
        y0 = np.ascontiguousarray(y0, dtype=float)
        p = self._params(p, 1).reshape(-1)
        out = np.empty((steps + 1, 2))
        self._lib.pendulab_rk4_path(_ptr(y0), _ptr(p), t0, dt, steps, int(linear), _ptr(out))
        return out

    def rhs_points(self, t, y, p, linear=False):
        """f at n points: t (n,), y (n, 2), p (n, k) -> (n, 2) (the kernel's own sine)."""
        t = np.ascontiguousarray(t, dtype=float)
        y = np.ascontiguousarray(y, dtype=float)
        n = t.shape[0]
        p = self._params(p, n)
        out = np.empty((n, 2))
        self._lib.pendulab_rhs_points(n, _ptr(t), _ptr(y), _ptr(p), int(linear), _ptr(out))
        return out

    def trig(self, x, cosine=False):
        """pendulab_sin (or pendulab_cos) of an array."""
        x = np.ascontiguousarray(x, dtype=float)
        out = np.empty_like(x)
        self._lib.pendulab_trig_points(x.size, _ptr(x), int(cosine), _ptr(out))
        return out


def _notice(key, message):
    if key not in _NOTIFIED:
        _NOTIFIED.add(key)
        sys.stderr.write(f"pendulab: notice: {message}; using the NumPy path\n")
        sys.stderr.flush()


def load(fos, required=False):
    """The compiled kernel of ``fos`` (a :class:`Kernel`), or None with a notice (see above)."""
    from pendulab.numerics.codegen import c_kernel
    source = c_kernel(fos)
    skey = hashlib.sha256(source.encode()).hexdigest()
    if skey not in _LOADED:
        _LOADED[skey] = _build(source, len(fos.params))
    got = _LOADED[skey]
    if isinstance(got, Kernel):
        return got
    message = f"C kernel of system {fos.name!r} unavailable: {got}"
    if required:
        raise InputError(message)
    _notice(skey, message)
    return None


def _compiled(source, load):
    """Compile ``source`` (cached by hash) with the first flag set that works and return
    ``load(path, flags)``, or a one-line reason why no kernel could be built or loaded."""
    cmd = compiler_command()
    if not cmd:
        return "no C compiler"
    identity = _identity(cmd)
    if identity is None:
        return f"C compiler {cmd[0]!r} not found or not runnable (set PENDULAB_CC or CC)"
    errors = []
    for flags in FLAG_SETS:
        target = cache_dir() / f"{_key(source, identity, flags)}.so"
        if not target.exists():
            try:
                err = _compile(source, cmd, flags, target)
            except OSError as exc:
                return f"cannot write the kernel cache {target.parent}: {exc.strerror}"
            if err is not None:
                errors.append(err)
                continue
        try:
            return load(target, flags)
        except OSError as exc:
            errors.append(_first_line(str(exc)))
    return f"{cmd[0]} failed: {errors[0] if errors else 'unknown error'}"


def _build(source, nparams):
    return _compiled(source, lambda target, flags: Kernel(target, nparams, flags))


_PROBE = "int pendulab_probe(void) { return 1; }\n"


def available(fos=None):
    """Whether C kernels can be built here (of ``fos``, or a probe; no notice is printed)."""
    if fos is not None:
        from pendulab.numerics.codegen import c_kernel
        key = hashlib.sha256(c_kernel(fos).encode()).hexdigest()
        if key not in _LOADED:
            _LOADED[key] = _build(c_kernel(fos), len(fos.params))
        return isinstance(_LOADED[key], Kernel)
    key = ("probe", tuple(compiler_command()))
    if key not in _LOADED:
        _LOADED[key] = _probe()
    return _LOADED[key]


def _probe():
    cmd = compiler_command()
    identity = _identity(cmd) if cmd else None
    if identity is None:
        return False
    for flags in FLAG_SETS:
        target = cache_dir() / f"probe-{_key(_PROBE, identity, flags)}.so"
        try:
            if target.exists() or _compile(_PROBE, cmd, flags, target) is None:
                ctypes.CDLL(str(target)).pendulab_probe()
                return True
        except (OSError, AttributeError):
            continue
    return False


def clear_loaded():
    """Forget the kernels loaded by this process (the disk cache stays; tests use this)."""
    _LOADED.clear()
    _NOTIFIED.clear()
    _IDENTITY.clear()


def load_source(name, source, required=False):
    """A C99 ``source`` (no system of its own: a hand kernel) compiled like the system
    kernels (same compiler, flags, cache and key) and loaded as a :class:`ctypes.CDLL`;
    None with the one-line notice when it cannot be built (``required``: InputError)."""
    skey = ("source", hashlib.sha256(source.encode()).hexdigest())
    if skey not in _LOADED:
        _LOADED[skey] = _build_cdll(source)
    got = _LOADED[skey]
    if isinstance(got, ctypes.CDLL):
        return got
    message = f"C kernel {name!r} unavailable: {got}"
    if required:
        raise InputError(message)
    _notice(skey, message)
    return None


def _build_cdll(source):
    return _compiled(source, lambda target, flags: ctypes.CDLL(str(target)))
