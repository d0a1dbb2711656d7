"""No worker outlives the process that started it, whatever kills that process.

A real ``python -m pendulab build`` (and ``pendulab sweep --processes 2``) runs in
its own session, so that everything it starts is in its process group; once its
workers exist the parent gets SIGKILL (which runs no cleanup), and within
:data:`GRACE` seconds no process it started, and nothing in its group, may be
alive.  Without :func:`pendulab.procs.die_with_parent` the build's worker goes
on computing its map for tens of seconds and the sweep's workers wait for ever.
The processes are found in /proc (ppid, process group and start time of each
one in /proc/<pid>/stat), so these tests run on Linux only.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[1] / "src")

#: Seconds the former children have to end once the parent is killed: the watchdog looks
#: every 0.25 s; SIGKILL through PR_SET_PDEATHSIG is immediate.
GRACE = 5.0

#: Seconds to wait for the workers to appear (the parent imports, reads the scene, derives).
START = 60.0

pytestmark = pytest.mark.skipif(not os.path.isdir("/proc/self/task"),
                                reason="finds processes through Linux's /proc")

# A scene whose three maps each keep a process busy for tens of seconds on a loaded machine
# (a 20 x 20 map, 300 periods x 100 steps, on the NumPy integrator): the build's workers are
# surely computing when their parent is killed.
SLOW_SCENE = """\
name = "slow"
system = "kapitza"
[parameters]
body = "rod"
[products.experiments]
maps = ["text", "caption", "fig4"]
grid = 20
periods = 300
steps_per_period = 100
criteria = ["mean"]
fig5 = false
fig2 = false
figures = false
backend = "numpy"
"""


def _stat(pid):
    """(ppid, process group, state, start time) of ``pid`` from /proc/<pid>/stat, or None."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            text = fh.read().decode("ascii", "replace")
    except OSError:
        return None
    fields = text[text.rindex(")") + 2:].split()  # after "pid (comm) "
    return int(fields[1]), int(fields[2]), fields[0], int(fields[19])


def _table():
    """{pid: (ppid, process group, state, start time)} of every process now."""
    table = {}
    for name in os.listdir("/proc"):
        if name.isdigit():
            st = _stat(int(name))
            if st is not None:
                table[int(name)] = st
    return table


def _descendants(root, table):
    """{pid: start time} of the processes below ``root`` in ``table``."""
    found, frontier = {}, [root]
    while frontier:
        parent = frontier.pop()
        for pid, (ppid, _, _, start) in table.items():
            if ppid == parent and pid not in found:
                found[pid] = start
                frontier.append(pid)
    return found


def _alive(pid, start):
    """Whether the process ``pid`` that started at ``start`` is still running (a zombie is not)."""
    st = _stat(pid)
    return st is not None and st[3] == start and st[2] not in ("Z", "X")


def _survivors(group, seen):
    """The processes of ``seen`` still running, and the running members of process ``group``."""
    table = _table()
    left = {pid for pid, start in seen.items() if _alive(pid, start)}
    left |= {pid for pid, (_, pgrp, state, _) in table.items()
             if pgrp == group and state not in ("Z", "X")}
    return sorted(left)


def _kill_parent_and_check(argv, env, tmp_path, workers):
    """Start ``argv`` in a new session, wait for ``workers(descendants)`` to be true, SIGKILL
    the parent and return the processes it started that are still alive after GRACE s."""
    log = open(tmp_path / "stderr.txt", "w+b")
    proc = subprocess.Popen(argv, env=env, cwd=tmp_path, stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=log, start_new_session=True)
    group, seen = proc.pid, {}
    try:
        deadline = time.monotonic() + START
        while True:
            seen.update(_descendants(proc.pid, _table()))
            if workers(seen):
                break
            if proc.poll() is not None or time.monotonic() > deadline:
                log.seek(0)
                pytest.fail(f"no workers seen (status {proc.poll()}): {log.read().decode()[-2000:]}")
            time.sleep(0.05)
        time.sleep(0.5)  # the workers are under way (and a last look for any started meanwhile)
        seen.update(_descendants(proc.pid, _table()))
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        deadline = time.monotonic() + GRACE
        while time.monotonic() < deadline:
            left = _survivors(group, seen)
            if not left:
                return [], seen
            time.sleep(0.1)
        return _survivors(group, seen), seen
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for pid, start in seen.items():  # this test leaves nothing behind, even when it fails
            if _alive(pid, start):
                try:
                    os.kill(pid, signal.SIGKILL)
                except OSError:
                    pass
        log.close()


def _cmdline(pid):
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as fh:
            return fh.read().replace(b"\0", b" ").decode("utf-8", "replace")
    except OSError:
        return ""


@pytest.mark.parametrize("jobs", ["2", "3"])
def test_build_workers_die_with_a_killed_build(tmp_path, jobs):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    (scenes / "slow.toml").write_text(SLOW_SCENE)
    env = dict(os.environ, PYTHONPATH=SRC, PENDULAB_JOBS=jobs)
    # the build forks jobs - 1 workers (four tasks: three maps and the summary); with two,
    # the second inherits the read end of the first one's pipe
    want = int(jobs) - 1
    left, seen = _kill_parent_and_check(
        [sys.executable, "-m", "pendulab", "build", str(scenes), "--force",
         "--out", str(tmp_path / "out")], env, tmp_path, lambda kids: len(kids) >= want)
    assert len(seen) >= want
    assert left == [], f"alive after {GRACE} s: {[_cmdline(p) for p in left]}"
    assert not (tmp_path / "out" / "slow").exists()  # nothing published by a killed build


def test_sweep_workers_die_with_a_killed_sweep(tmp_path):
    # no compiler: the NumPy integrator, slow enough for each chunk to take seconds
    env = dict(os.environ, PYTHONPATH=SRC, PENDULAB_CC=str(tmp_path / "no-such-compiler"),
               PENDULAB_CACHE_DIR=str(tmp_path / "cache"))

    def spawned(kids):  # both workers of the pool (the resource tracker is one more child)
        return sum("spawn_main" in _cmdline(pid) for pid in kids) >= 2

    left, seen = _kill_parent_and_check(
        [sys.executable, "-m", "pendulab", "sweep", "--processes", "2", "--grid", "20",
         "--periods", "300", "--quiet"], env, tmp_path, spawned)
    assert left == [], f"alive after {GRACE} s: {[_cmdline(p) for p in left]}"


def test_a_worker_whose_parent_is_gone_ends_itself():
    """die_with_parent called with a pid that is not the parent's (the parent died before the
    signal was armed) ends the process at once, with its own status."""
    from pendulab import procs
    code = ("import os, sys; from pendulab.procs import die_with_parent; "
            "die_with_parent(os.getppid() + 1); print('went on')")
    run = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=SRC),
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == procs.ORPHANED and "went on" not in run.stdout, run


def test_the_watchdog_ends_an_orphan_without_the_signal():
    """The portable fallback alone (no PR_SET_PDEATHSIG, as on a system without prctl): a
    grandchild whose parent is killed ends itself within GRACE s, while blocked in a sleep."""
    code = """\
import os, sys, time
from pendulab import procs
procs._set_pdeathsig = lambda: False
pid = os.fork()
if pid == 0:
    print(procs.die_with_parent(os.getppid()), os.getpid(), flush=True)
    time.sleep(120)
    os._exit(0)
time.sleep(120)
"""
    proc = subprocess.Popen([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=SRC),
                            stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        line = proc.stdout.readline().split()
        assert line[0] == "('watchdog',)", line
        child = int(line[1])
        start = _stat(child)[3]
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        deadline = time.monotonic() + GRACE
        while _alive(child, start) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not _alive(child, start)
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except OSError:
            pass
        proc.wait()


def test_die_with_parent_arms_the_signal_and_one_watchdog_thread():
    code = ("import os, threading; from pendulab.procs import die_with_parent; "
            "n = threading.active_count(); means = die_with_parent(os.getppid()); "
            "print(' '.join(means), threading.active_count() - n)")
    run = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=SRC),
                         capture_output=True, text=True, timeout=60)
    # the parent (this test) lives: the watchdog stays quiet and the process ends normally
    assert run.returncode == 0, run
    want = "pdeathsig watchdog" if sys.platform.startswith("linux") else "watchdog"
    assert run.stdout.split() == [*want.split(), "1"], run


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
def test_an_external_program_started_with_the_death_signal_dies_with_its_parent():
    """procs.parent_death_signal as subprocess's preexec_fn (the animation runs ffmpeg so): a
    program that can watch no pid (here sleep, as an ffmpeg waiting on its input) is killed
    when the Python process that started it is SIGKILLed."""
    code = """\
import subprocess, sys
from pendulab.procs import parent_death_signal
child = subprocess.Popen(["sleep", "120"], preexec_fn=parent_death_signal)
print(child.pid, flush=True)
child.wait()
"""
    proc = subprocess.Popen([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=SRC),
                            stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        child = int(proc.stdout.readline())
        start = _stat(child)[3]
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        deadline = time.monotonic() + GRACE
        while _alive(child, start) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not _alive(child, start), _cmdline(child)
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except OSError:
            pass
        proc.wait()
