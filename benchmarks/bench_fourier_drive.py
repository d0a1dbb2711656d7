"""Speed of deriving a Fourier drive, one command:

    python benchmarks/bench_fourier_drive.py [--baseline-timeout SECONDS]

`pendulab derive kapitza --drive 'a1*cos(omega*t) + ... + aN*cos(N*omega*t)'`
for N = 3, 8, 12, 40, each in a fresh interpreter (wall and CPU time of the
whole command).  Targets: N = 12 under 2 s, N = 40 under 10 s.

Baseline: the same command with the code before the bounded-work changes (git revision
BASELINE, extracted with ``git archive`` into a temporary directory; it
rewrote the coefficient as exponentials, expanded and simplified it, and
trigsimp'ed the whole Lagrangian).  A baseline run longer than the timeout
(default 150 s) is stopped and reported as "> timeout"; the ratio is then a
lower bound.  Needs a git checkout of pendulab.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
#: the last revision before the bounded-work changes
BASELINE = "995e9c2"


def drive(n):
    return " + ".join(f"a{k}*cos({k}*omega*t)" for k in range(1, n + 1))


def run(src, n, timeout):
    """(wall s, cpu s or None, finished) of `pendulab derive kapitza --drive ...` with ``src``."""
    env = dict(os.environ, PYTHONPATH=src)
    start = time.perf_counter()
    before = os.times()
    try:
        subprocess.run([sys.executable, "-m", "pendulab", "derive", "kapitza", "--drive", drive(n)],
                       env=env, check=True, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return timeout, None, False
    after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system
                                                          - before.children_system)
    return time.perf_counter() - start, cpu, True


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline-timeout", type=float, default=150)
    args = parser.parse_args()
    ours = os.path.join(ROOT, "src")
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", ROOT, "archive", BASELINE, "src"],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        base = os.path.join(tmp, "src")
        print(f"{'N':>3} {'ours wall':>10} {'ours cpu':>9} {'baseline wall':>14} {'ratio':>8}")
        for n in (3, 8, 12, 40):
            wall, cpu, _ = run(ours, n, 600)
            if n <= 12:
                bwall, _bcpu, done = run(base, n, args.baseline_timeout)
                btext = f"{bwall:13.1f}s" if done else f"> {bwall:.0f} s".rjust(14)
                ratio = f"{'>' if not done else ''}{bwall / wall:.0f}x"
            else:
                btext, ratio = "(not run)".rjust(14), ""
            target = {12: " (target < 2 s)", 40: " (target < 10 s)"}.get(n, "")
            print(f"{n:>3} {wall:9.2f}s {cpu:8.2f}s {btext} {ratio:>8}{target}")


if __name__ == "__main__":
    main()
