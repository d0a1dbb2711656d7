"""Start-up time of ``pendulab`` commands that compute little (target: at most 0.5 s).

One command:  python benchmarks/bench_startup.py [--runs 5]

Each command runs ``--runs`` times as a fresh subprocess (``python -m pendulab ...``,
the same interpreter as the console script); the figure is the median wall time.
The baselines, measured in the same run the same way, are an empty interpreter
(``python -c pass``) and one that imports what the numeric commands need
(``python -c "import sympy, scipy, numpy"``).  Printed per command: our median,
the ratio to each baseline (/pass, /imports, /sympy), and whether it meets the 0.5 s target (only for
the commands marked "little": the others compute something on purpose and are
shown for comparison).  Commands that compute with SymPy (series) cannot start
faster than ``import sympy`` alone, the third baseline.

The subprocesses run without PYTHONDONTWRITEBYTECODE (as a user's shell would),
so that pendulab's own modules are read from their bytecode caches like the
installed libraries; the first run of each command may write those caches.
"""

import os

import argparse
import statistics
import subprocess
import sys
import time

TARGET = 0.5

#: (label, argv after "python -m pendulab", kind): "little" commands have the 0.5 s target;
#: "sympy" ones compute with SymPy and are compared with ``import sympy`` alone; "computes"
#: ones are shown for comparison.
COMMANDS = [
    ("pendulab --help", ["--help"], "little"),
    ("pendulab floquet --help", ["floquet", "--help"], "little"),
    ("pendulab sweep --help", ["sweep", "--help"], "little"),
    ("usage error (sweep --grid 0)", ["sweep", "--grid", "0"], "little"),
    ("usage error (unknown command)", ["nope"], "little"),
    ("usage error (series --order 61)", ["series", "--order", "61"], "little"),
    ("usage error (floquet --dps 0)", ["floquet", "--theta0", "1", "--theta1", "0", "--dps", "0"],
     "little"),
    ("usage error (stability --ratio 2000)", ["stability", "--ratio", "2000"], "little"),
    ("usage error (simulate, three bad values)",
     ["simulate", "--a-over-l", "-1", "--w0-over-w", "x", "--every", "0"], "little"),
    ("bessel zeros --order 1 --count 3", ["bessel", "zeros", "--order", "1", "--count", "3"], "little"),
    ("floquet --theta0 -1/5 --theta1 0.2", ["floquet", "--theta0", "-1/5", "--theta1", "0.2"], "little"),
    ("series --order 2 --kind a0", ["series", "--order", "2", "--kind", "a0"], "little"),
    ("series --order 2 (nu)", ["series", "--order", "2"], "little"),
    ("series --order 2 --latex", ["series", "--order", "2", "--latex"], "little"),
    ("stability --ratio 0.1 --method eq12 --json",
     ["stability", "--ratio", "0.1", "--method", "eq12", "--json"], "computes"),
    ("stability --ratio 0.1 --json (exact)", ["stability", "--ratio", "0.1", "--json"], "computes"),
]

BASELINES = [
    ("python -c pass", ["-c", "pass"]),
    ("python -c 'import sympy, scipy, numpy'", ["-c", "import sympy, scipy, numpy"]),
    ("python -c 'import sympy'", ["-c", "import sympy"]),
]

ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def wall(args, runs):
    """Median wall seconds of ``runs`` runs of ``python args`` (output discarded)."""
    subprocess.run([sys.executable, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   env=ENV)  # warm-up (bytecode caches, file system), not counted
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run([sys.executable, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       env=ENV)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=5, help="runs per command (median)")
    args = p.parse_args()
    base = {label: wall(argv, args.runs) for label, argv in BASELINES}
    empty, heavy, sympy_alone = (base[label] for label, _ in BASELINES)
    for label, seconds in base.items():
        print(f"baseline {label:45s} {seconds:6.3f} s")
    print(f"{'command':52s} {'ours':>7s} {'/pass':>6s} {'/imports':>8s} {'/sympy':>7s}  "
          f"target {TARGET} s")
    ok = True
    for label, argv, little in COMMANDS:
        seconds = wall(["-m", "pendulab", *argv], args.runs)
        if little == "little":
            verdict = "meets" if seconds <= TARGET else "MISSES"
            ok &= seconds <= TARGET
        else:
            verdict = "(SymPy-bound)" if little == "sympy" else "(computes)"
        print(f"{label:52s} {seconds:6.3f}s {seconds / empty:6.1f} {seconds / heavy:8.2f} "
              f"{seconds / sympy_alone:7.2f}  {verdict}")
    print("all commands that do little meet the target" if ok else
          "some commands that do little miss the target")


if __name__ == "__main__":
    main()
