"""Worker processes that die with the process that started them.

A process killed by SIGKILL (or by the kernel's out-of-memory killer) runs no
cleanup, so the workers it forked or spawned are adopted by init and go on:
computing for nothing, then blocked for ever writing a result nobody reads.
:func:`die_with_parent`, called first thing in every worker
(:func:`pendulab.build.compute_scenes` forks them, the local-process executor of
:mod:`pendulab.numerics.sweep` spawns them), closes that door twice:

* Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` (through :mod:`ctypes`): the
  kernel kills the worker when the thread that started it ends, the process's
  death included, however it died.  The parent may already have died between
  the fork and the ``prctl`` call (then no signal ever comes): the worker
  compares ``os.getppid()`` with the parent's pid right after and ends itself
  if they differ.
* Everywhere (the fallback where ``prctl`` is missing or refused): a daemon
  thread that wakes every :data:`WATCH_INTERVAL` seconds and ends the process
  (``os._exit``) as soon as ``os.getppid()`` is no longer the parent's pid (an
  orphan's parent becomes init or a subreaper).  It ends the worker even while
  its main thread is blocked writing to a pipe.

The signal is tied to the *thread* that started the worker: start workers in
a thread that waits for them (both callers do).
"""

import os
import sys
import threading
import time

#: Seconds between two looks of the watchdog thread at the parent's pid.
WATCH_INTERVAL = 0.25

#: prctl option that sets the signal a process gets when its parent dies (linux/prctl.h).
PR_SET_PDEATHSIG = 1

#: Exit status of a worker that ended itself because its parent was gone.
ORPHANED = 70


def die_with_parent(parent_pid):
    """Make this process (a worker just started by ``parent_pid``) end when its parent ends.

    Returns the means in place, a tuple out of ``("pdeathsig", "watchdog")``;
    ends the process at once (status :data:`ORPHANED`) when the parent is
    already gone.  Never raises: a worker's start must not fail on it.
    """
    means = []
    if _set_pdeathsig():
        means.append("pdeathsig")
    if os.getppid() != parent_pid:  # the parent died before the signal was armed
        os._exit(ORPHANED)
    watch = threading.Thread(target=_watch, args=(parent_pid,), name="pendulab-parent-watch",
                             daemon=True)
    watch.start()
    means.append("watchdog")
    return tuple(means)


def parent_death_signal():
    """For ``subprocess``'s ``preexec_fn``: the child (an external program, which can watch no
    pid) is killed when the thread that started it ends (Linux; elsewhere nothing is armed)."""
    _set_pdeathsig()


def _set_pdeathsig():
    """Arm PR_SET_PDEATHSIG with SIGKILL; False where there is no such call (not Linux)
    or it is refused."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes
        import signal
        libc = ctypes.CDLL(None, use_errno=True)
        prctl = libc.prctl
        prctl.restype = ctypes.c_int
        prctl.argtypes = [ctypes.c_int, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong,
                          ctypes.c_ulong]
        return prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError, ImportError):
        return False


def _watch(parent_pid):
    while True:
        time.sleep(WATCH_INTERVAL)
        if os.getppid() != parent_pid:
            os._exit(ORPHANED)
