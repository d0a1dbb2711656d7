"""CPU of the variable-length scene's ``motion`` product in the main job, one command:

    python benchmarks/bench_motion.py [--repeat N]

Each round runs, in fresh interpreters, alternately for ours (the source tree
this script sits in) and for the baseline (pendulab at commit BASELINE, the
main branch before this work, extracted with ``git archive``):

* the preparation the build's parent makes before it forks its workers
  (every committed scene loaded, the shared derivations and the heavy imports
  of :func:`pendulab.build.compute_scenes`: SymPy's simplify machinery,
  SciPy's integrators, matplotlib), untimed;
* then the ``motion`` product of derivations/variable-length.toml with
  ``figures = false`` (the figures are drawn by other code), timed:
  process CPU of the product and of the stages it triggers (system,
  equations, canonical form, closed form), as when it is the first task of
  a worker.

Also checks that both give the same motion.json and motion.tex bytes.  The
machine is shared: the fastest of ``--repeat`` rounds counts (CPU time, which
other jobs disturb less than wall time).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: main before the variable-length work (closed form, motion product)
BASELINE = "fba1f7a"

_CHILD = r"""
import hashlib, json, sys, time
from pathlib import Path
from pendulab import build
from pendulab.pipeline import Context, product_parts, run_part
from pendulab.scene import load_scene
root = Path(sys.argv[1])
scenes = [load_scene(p) for p in build.scene_paths(root / "derivations")]
for sc in scenes:
    for name in sc.products:
        product_parts(name, sc.products[name])
build._share_derivations(scenes)
build._preload(scenes)
scene = next(sc for sc in scenes if sc.name == "variable-length")
scene.products["motion"] = dict(scene.products["motion"], figures=False)
ctx = Context(scene)
start = time.process_time()
files = run_part(ctx, "motion", None)
cpu = time.process_time() - start
digest = hashlib.sha256(repr(sorted(files.items())).encode()).hexdigest()
print(json.dumps({"cpu": cpu, "digest": digest}))
"""


def run(src):
    env = dict(os.environ, PYTHONPATH=str(src))
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # bytecode caches, as on a user's machine
    out = subprocess.run([sys.executable, "-c", _CHILD, str(ROOT)], env=env, cwd=str(ROOT),
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="rounds (the fastest counts)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench-motion-") as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", BASELINE, "src"],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        base_src = Path(tmp) / "src"
        print(f"load average before: {os.getloadavg()[0]:.2f}")
        run(ROOT / "src"), run(base_src)  # untimed: bytecode caches written
        ours, base = [], []
        for k in range(args.repeat):
            ours.append(run(ROOT / "src"))
            base.append(run(base_src))
            print(f"round {k + 1}: ours {ours[-1]['cpu']:.3f} s CPU, baseline {base[-1]['cpu']:.3f} s CPU")
        o, b = min(r["cpu"] for r in ours), min(r["cpu"] for r in base)
        print(f"motion product (figures off) after the build's preparation, fastest round:")
        print(f"ours:     {o:.3f} s CPU")
        print(f"baseline: {b:.3f} s CPU  (pendulab at {BASELINE})")
        print(f"ratio baseline/ours: {b / o:.2f}x")
        same = len({r["digest"] for r in ours + base}) == 1
        print(f"same motion.json and motion.tex as the baseline: {'yes' if same else 'NO'}")


if __name__ == "__main__":
    main()
