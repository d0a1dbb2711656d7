"""CPU time of the build's figures, ours against BASELINE, one command:

    python benchmarks/bench_figures.py [--repeat N] [--baseline COMMIT]

For each source tree (ours: the tree this script sits in; baseline: pendulab
at commit BASELINE or ``--baseline``, extracted with ``git archive``; the
rounds alternate between the two) a fresh interpreter
builds the committed scenes' products one after another, as the build's
workers do, with the figure functions wrapped to measure their CPU time
(time.process_time): the maps of the experiments (figure_map, three
calls), Fig. 5, Fig. 2, motion's theta and envelope figures and the two
stability.svg.  "first" is the time inside the build (first use of
mathtext, fonts and PDF subsets in the process included); "again" calls
each figure once more with the same arguments (steady state).  With
``--repeat`` the fastest round of each counts.  Prints each figure, the
totals and the ratio baseline / ours.
"""

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: main's commit before the second round of figure work (one drawing for PDF and PNG, the
#: garbage collector paused while saving, PNG zlib level 3); 4b84647 is the one before the first
BASELINE = "fba1f7a"

WORKER = r"""
import functools, importlib, json, sys, time
sys.path.insert(0, sys.argv[1])
clock = time.process_time
import numpy, scipy.integrate, scipy.special, sympy, mpmath  # noqa: E401 (imports outside the timing)
from pendulab.figures import pyplot
pyplot("bench")
import matplotlib.backends.backend_pdf  # noqa: F401  (the build preloads matplotlib too)
first, calls = {}, []

def wrap(modname, fname, key):
    m = importlib.import_module(modname)
    f = getattr(m, fname)

    @functools.wraps(f)
    def g(*a, **k):
        c = clock()
        try:
            return f(*a, **k)
        finally:
            first[key] = first.get(key, 0.0) + clock() - c
            calls.append((key, f, a, k))
    setattr(m, fname, g)

for mod, fname, key in [("pendulab.products.experiments", "figure_map", "experiments: 3 maps"),
                        ("pendulab.products.experiments", "figure_fig5", "experiments: fig5"),
                        ("pendulab.products.experiments", "figure_fig2", "experiments: fig2"),
                        ("pendulab.products.motion", "figure_theta", "motion: theta"),
                        ("pendulab.products.motion", "figure_envelope", "motion: envelope"),
                        ("pendulab.products.stability", "figure_svg", "stability: 2 svg")]:
    wrap(mod, fname, key)
from pendulab.build import scene_paths
from pendulab.pipeline import STAGES, Context, product_module
from pendulab.scene import load_scene
for path in scene_paths(sys.argv[2]):
    sc = load_scene(path)
    ctx = Context(sc)
    for name in STAGES:
        ctx.get(name)
    for name in sorted(sc.products):
        product_module(name).produce(ctx, sc.products[name])
again = {}
for key, f, a, k in calls:
    c = clock()
    f(*a, **k)
    again[key] = again.get(key, 0.0) + clock() - c
print(json.dumps({"first": first, "again": again}))
"""


def run(src, derivations):
    out = subprocess.run([sys.executable, "-c", WORKER, str(src), str(derivations)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def best(rounds):
    return {part: {k: min(r[part][k] for r in rounds) for k in rounds[0][part]}
            for part in ("first", "again")}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--baseline", default=BASELINE, help=f"commit to compare with ({BASELINE})")
    args = parser.parse_args(argv)
    baseline = args.baseline
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", baseline, "src"],
                                 check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        old, new = [], []
        for _ in range(args.repeat):
            old.append(run(Path(tmp) / "src", ROOT / "derivations"))
            new.append(run(ROOT / "src", ROOT / "derivations"))
    old, new = best(old), best(new)
    for part in ("first", "again"):
        print(f"{part:>5} (CPU s)       baseline {baseline:>9}      ours   ratio")
        for k in old[part]:
            print(f"  {k:<22} {old[part][k]:9.3f} {new[part][k]:9.3f} {old[part][k] / new[part][k]:6.2f}x")
        to, tn = sum(old[part].values()), sum(new[part].values())
        print(f"  {'all figures':<22} {to:9.3f} {tn:9.3f} {to / tn:6.2f}x")


if __name__ == "__main__":
    main()
