"""Time of the main job, one command:

    python benchmarks/bench_build.py [--repeat N] [--jobs J] [--reference-job | --reference-scale]

Runs ``python -m pendulab build derivations/ --force --out <temporary>``
on the committed scenes twice per round, in fresh interpreters:

* ours - the source tree this script sits in;
* baseline - the same command on pendulab as it was at commit BASELINE
  (the commit before the main-job work: one scene after another, the
  stability-interval scan point by point), extracted with ``git archive``
  into a temporary directory and run by the same Python.

One untimed build of each comes first (bytecode caches written, as on a user's
machine; PYTHONDONTWRITEBYTECODE is dropped from the children's environment).
Prints the wall time and the CPU time (user + system of the build and of
the worker processes it forks) of each, the ratios, and whether the two
builds wrote the same bytes.  Products changed since BASELINE (the version in every
header and manifest, the floquet product's certified digits in 0.4.0, the figures'
labels and layout in 0.5.0; no number changed), so the files that differ are listed;
the reproducibility of our own build is tests/test_build.py's job.  The machine is
shared and noisy: with ``--repeat`` the fastest round of each counts, and a fixed
pure-Python loop is timed between the rounds to show how fast the machine was.
``--jobs`` sets PENDULAB_JOBS for ours (1 = the serial path); ``--serial`` times the
serial path as well.  ``--breakdown`` prints instead the CPU time of the imports and
of every stage and product of each scene, computed one after another in one process.

``--reference-job`` times the job that set the main job's target: on a 2-core
machine the committed scenes of commit bd3f9c5 (kapitza-rod with equations,
series, floquet and stability, kapitza-point with equations and stability,
variable-length with equations and quarter_periods) took 14 s idle and 25 s
loaded with pendulab at bd3f9c5, and the target is 3 s.  They are built by
ours and by pendulab at bd3f9c5 in alternating rounds.  The same scene files,
not quite the same work: bd3f9c5's quarter_periods also checked the
cross-product identity at 160 points (about 0.5 s of CPU; now part of the
bessel product's identities, which these scenes do not ask for), and its
floquet product used Hill's determinant where ours proves its digits in arb
balls; the files that differ are listed.  The committed scenes have gained
products since (the experiments scene with Figs. 2-5, the motion, kernels,
bessel and notes products), which the default mode times: the 3 s target is
for the committed scenes, so that is the measure of it.

``--reference-scale`` puts the committed scenes on the scale of that
measurement.  It gives one time, 14 s idle for pendulab at bd3f9c5 on its
scenes, so each round builds that job, the committed scenes with ours, and
the committed scenes with every figure turned off (copies with ``figures =
false`` / ``figure = false`` wherever a product has that option), one after
another; each of ours is then scaled by 14 s / bd3f9c5's time of the same
round: the wall time that idle machine would have shown.  The no-figure
copies show how much of the 3 s the computations alone take.
"""

import argparse
import contextlib
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: The commit before the main-job work (the baseline the ratio is taken against).
BASELINE = "730850c"
#: The commit whose scenes and code set the target (that job took 14 s on an idle machine).
FILED = "bd3f9c5"


def calibration():
    """Seconds of a fixed pure-Python loop (the sum of i*i for i < 10**7): how fast the
    shared machine is right now (it changes by half within minutes)."""
    start = time.perf_counter()
    sum(i * i for i in range(10**7))
    return time.perf_counter() - start


def _child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_build(src, out, jobs=None, scenes=None):
    """(wall s, CPU s) of one ``pendulab build <scenes> --force`` with ``src`` first on the path
    (``scenes``: derivations/ by default)."""
    env = dict(os.environ, PYTHONPATH=str(src))
    # a user's Python caches the bytecode of pendulab's modules; some sandboxes turn that off
    # (PYTHONDONTWRITEBYTECODE), which would add the compilation of every module to each run
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if jobs is not None:
        env["PENDULAB_JOBS"] = str(jobs)
    scenes = ROOT / "derivations" if scenes is None else scenes
    cmd = [sys.executable, "-m", "pendulab", "build", str(scenes), "--force", "--out", str(out)]
    cpu, start = _child_cpu(), time.perf_counter()
    subprocess.run(cmd, env=env, cwd=str(ROOT), check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start, _child_cpu() - cpu


def tree(root):
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(Path(root).rglob("*"))
            if p.is_file() and not p.name.startswith(".")}


def differing(root_a, root_b):
    """(the files whose bytes differ between two output trees, sorted; how many files in all)."""
    a, b = tree(root_a), tree(root_b)
    names = set(a) | set(b)
    return sorted(k for k in names if a.get(k) != b.get(k)), len(names)


def baseline_source(into, commit=BASELINE, paths=("src",), quiet=False):
    """Extract ``paths`` (src/) of ``commit`` into ``into``; the path of its src/, or None
    when git cannot (saying so unless ``quiet``)."""
    try:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit, *paths],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    except (OSError, subprocess.CalledProcessError) as exc:
        if not quiet:
            print(f"baseline: cannot extract {commit} ({exc}); ours only")
        return None
    return Path(into) / "src"


@contextlib.contextmanager
def filed_tree(mode):
    """(a temporary directory, the src/ of FILED extracted into it with its derivations/),
    removed afterwards; exits naming ``mode`` when git cannot extract FILED."""
    tmp = Path(tempfile.mkdtemp(prefix=f"bench{mode[1:]}-"))
    try:
        old_src = baseline_source(tmp, FILED, ("src", "derivations"), quiet=True)
        if old_src is None:
            sys.exit(f"{mode}: cannot extract {FILED} with git (a shallow clone?): nothing timed")
        yield tmp, old_src
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def reference_job(repeat, jobs=None):
    """Time the reference job: the scenes committed at FILED, built by ours and by FILED."""
    with filed_tree("--reference-job") as (tmp, old_src):
        scenes = tmp / "derivations"
        names = ", ".join(p.stem for p in sorted(scenes.glob("*.toml")))
        print(f"the reference job: the scenes committed at {FILED} ({names})")
        print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores shared: wall times are noisy)")
        run_build(ROOT / "src", tmp / "warm-ours", jobs, scenes)
        run_build(old_src, tmp / "warm-filed", scenes=scenes)
        ours, filed, loops = [], [], [calibration()]
        for k in range(repeat):
            ours.append(run_build(ROOT / "src", tmp / f"ours{k}", jobs, scenes))
            filed.append(run_build(old_src, tmp / f"filed{k}", scenes=scenes))
            loops.append(calibration())
            print(f"round {k + 1}: ours {ours[-1][0]:6.2f} s wall, {ours[-1][1]:6.2f} s CPU; "
                  f"pendulab at {FILED} {filed[-1][0]:6.2f} s wall, {filed[-1][1]:6.2f} s CPU; "
                  f"calibration loop {loops[-1]:.2f} s")
        wall, cpu = min(w for w, _ in ours), min(c for _, c in ours)
        fwall, fcpu = min(w for w, _ in filed), min(c for _, c in filed)
        ratios = [f / o for (f, _), (o, _) in zip(filed, ours)]
        print(f"machine: the calibration loop took {min(loops):.2f}-{max(loops):.2f} s before and "
              "between the rounds (smaller is faster)")
        print(f"ours:     fastest {wall:6.2f} s wall, slowest {max(w for w, _ in ours):.2f} s; "
              f"{cpu:6.2f} s CPU  (target: wall <= 3 s)")
        print(f"filed:    fastest {fwall:6.2f} s wall, {fcpu:6.2f} s CPU  (pendulab at {FILED}; "
              "measured at 14 s idle)")
        print(f"ratio filed/ours: fastest/fastest wall {fwall / wall:.2f}x, CPU {fcpu / cpu:.2f}x; "
              f"round by round {min(ratios):.2f}-{max(ratios):.2f}x")
        differ, total = differing(tmp / "ours0", tmp / "filed0")
        print(f"files that differ from {FILED}'s: {len(differ)} of {total} "
              f"({', '.join(differ)}); the work differs too: {FILED}'s quarter_periods also checked "
              "J1 Y2 - J2 Y1 = -2/(pi z) at 160 points (30 digits; now the bessel product's "
              "identities), and its floquet product used Hill's determinant, not arb balls")


#: The time of the reference job (pendulab at FILED on FILED's scenes) on an idle machine.
REFERENCE_SECONDS = 14.0


def figure_free_scenes(into):
    """Copies of the committed scenes in ``into`` with every figure turned off: ``KEY = false``
    under each product whose option table has a boolean "figures" or "figure"; the names of
    the options turned off ("scene: product.KEY")."""
    import re
    sys.path.insert(0, str(ROOT / "src"))
    from pendulab.build import scene_paths
    from pendulab.pipeline import product_module
    from pendulab.scene import load_scene
    off = []
    for path in scene_paths(ROOT / "derivations"):
        text = path.read_text(encoding="utf-8")
        for name in sorted(load_scene(path).products):
            options = getattr(product_module(name), "OPTIONS", {})
            for key in ("figures", "figure"):
                if key in options and options[key][0] is bool:
                    header = re.compile(rf"^\[products\.{re.escape(name)}\][^\n]*\n", re.M)
                    found = header.search(text)
                    table = text[found.end():] if found else ""
                    nxt = re.search(r"^\[", table, re.M)  # the product's own table ends there
                    table = table[:nxt.start()] if nxt else table
                    if found is None or re.search(rf"^{key}\s*=", table, re.M):
                        sys.exit(f"--reference-scale: cannot turn off {name}.{key} in {path.name}")
                    text = text[:found.end()] + f"{key} = false\n" + text[found.end():]
                    off.append(f"{path.stem}: {name}.{key}")
        (Path(into) / path.name).write_text(text, encoding="utf-8")
    return off


def reference_scale(repeat, jobs=None):
    """The committed scenes, with and without figures, on the reference job's scale (REFERENCE_SECONDS
    for FILED's job): each of ours times REFERENCE_SECONDS / FILED's time in the same round."""
    with filed_tree("--reference-scale") as (tmp, old_src):
        plain = tmp / "no-figures"
        plain.mkdir()
        off = figure_free_scenes(plain)
        print(f"the reference scale: pendulab at {FILED} on its scenes took {REFERENCE_SECONDS:g} s on "
              "an idle machine; each round times it next to ours")
        print(f"ours without figures: {', '.join(off)} set to false")
        print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores shared: wall times are noisy)")
        builds = {"ours": (ROOT / "src", None, jobs), "no figures": (ROOT / "src", plain, jobs),
                  "filed": (old_src, tmp / "derivations", None)}
        for label, (src, scenes, j) in builds.items():  # untimed: bytecode, compiled kernels
            run_build(src, tmp / f"warm-{label}", j, scenes)
        scaled = {"ours": [], "no figures": []}
        loops = [calibration()]
        for k in range(repeat):
            wall = {label: run_build(src, tmp / f"{label}{k}", j, scenes)[0]
                    for label, (src, scenes, j) in builds.items()}
            loops.append(calibration())
            for label in scaled:
                scaled[label].append(wall[label] * REFERENCE_SECONDS / wall["filed"])
            print(f"round {k + 1}: ours {wall['ours']:5.2f} s, without figures "
                  f"{wall['no figures']:5.2f} s, pendulab at {FILED} {wall['filed']:5.2f} s "
                  f"-> on the reference scale {scaled['ours'][-1]:.2f} s and "
                  f"{scaled['no figures'][-1]:.2f} s; calibration loop {loops[-1]:.2f} s")
        print(f"machine: the calibration loop took {min(loops):.2f}-{max(loops):.2f} s before and "
              "between the rounds (smaller is faster)")
        for label, values in scaled.items():
            print(f"on the reference scale, {'ours' if label == 'ours' else 'ours without figures'}: "
                  f"{min(values):.2f}-{max(values):.2f} s, median {statistics.median(values):.2f} s "
                  "(target: 3 s)")


def breakdown():
    """Print the CPU time of the imports, of each scene's stages and of each product,
    computed one after another in this process (where the main job's time goes)."""
    sys.path.insert(0, str(ROOT / "src"))
    clock = time.process_time
    c = clock()
    # what every build imports; SciPy's modules (scipy.linalg for the Floquet verdicts,
    # scipy.special for the closed form's values) count with the products that import them
    import numpy, sympy, mpmath  # noqa: F401,E401
    print(f"breakdown (CPU s, one process, serial): imports NumPy/SymPy/mpmath {clock() - c:.2f}")
    from pendulab.figures import pyplot
    c = clock()
    pyplot("breakdown")
    import matplotlib.backends.backend_pdf  # noqa: F401
    print(f"    import matplotlib (Agg, PDF) {clock() - c:.2f}")
    from pendulab.build import scene_paths
    from pendulab.pipeline import STAGES, Context, product_module
    from pendulab.scene import load_scene
    total = 0.0
    for path in scene_paths(ROOT / "derivations"):
        sc = load_scene(path)
        ctx = Context(sc)
        parts = []
        for name in STAGES:
            c = clock()
            ctx.get(name)
            parts.append((name, clock() - c))
        for name in sorted(sc.products):
            c = clock()
            product_module(name).produce(ctx, sc.products[name])
            parts.append((f"product {name}", clock() - c))
        scene_total = sum(t for _, t in parts)
        total += scene_total
        print(f"    {sc.name}: {scene_total:.2f} = "
              + ", ".join(f"{n} {t:.2f}" for n, t in parts if t >= 0.005))
    print(f"    scenes in all: {total:.2f} s CPU (on 2 cores the wall time is at least half of "
          "that plus the imports)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=1,
                    help="rounds, at least 1 (the fastest counts; --reference-scale also gives the median)")
    ap.add_argument("--jobs", type=int, default=None, help="PENDULAB_JOBS for ours (the older code has none)")
    ap.add_argument("--serial", action="store_true",
                    help="also time ours with PENDULAB_JOBS=1 (the default mode only)")
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--breakdown", action="store_true",
                      help="only print the CPU time of each scene's stages and products (serial)")
    mode.add_argument("--reference-job", action="store_true",
                      help=f"time the reference job (the scenes committed at {FILED}) against "
                           f"pendulab at {FILED}")
    mode.add_argument("--reference-scale", action="store_true",
                      help=f"the committed scenes, with and without figures, scaled to the reference job's "
                           f"{REFERENCE_SECONDS:g} s for pendulab at {FILED} (timed in the same rounds)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error(f"--repeat must be at least 1, got {args.repeat}")
    if args.serial and (args.reference_job or args.reference_scale or args.breakdown):
        ap.error("--serial goes with the default mode only")
    if args.breakdown:
        breakdown()
        return
    if args.reference_job:
        reference_job(args.repeat, args.jobs)
        return
    if args.reference_scale:
        reference_scale(args.repeat, args.jobs)
        return
    tmp = Path(tempfile.mkdtemp(prefix="bench-build-"))
    try:
        old_src = baseline_source(tmp)
        print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores shared: wall times are noisy)")
        ours, serial, base, loops = [], [], [], [calibration()]
        # one untimed build of each first: bytecode caches written, the C kernels compiled
        run_build(ROOT / "src", tmp / "warm-ours", args.jobs)
        if old_src is not None:
            run_build(old_src, tmp / "warm-base")
        for k in range(args.repeat):
            ours.append(run_build(ROOT / "src", tmp / f"ours{k}", args.jobs))
            print(f"round {k + 1}: ours           {ours[-1][0]:6.2f} s wall, {ours[-1][1]:6.2f} s CPU")
            if args.serial:
                serial.append(run_build(ROOT / "src", tmp / f"serial{k}", 1))
                print(f"round {k + 1}: ours, 1 job    {serial[-1][0]:6.2f} s wall, {serial[-1][1]:6.2f} s CPU")
            if old_src is not None:
                base.append(run_build(old_src, tmp / f"base{k}"))
                print(f"round {k + 1}: baseline       {base[-1][0]:6.2f} s wall, {base[-1][1]:6.2f} s CPU")
            loops.append(calibration())
        print(f"machine: the calibration loop took {min(loops):.2f}-{max(loops):.2f} s before and "
              "between the rounds (smaller is faster)")
        wall, cpu = min(w for w, _ in ours), min(c for _, c in ours)
        print(f"ours:     {wall:6.2f} s wall, {cpu:6.2f} s CPU  (every committed scene; "
              "target: wall <= 3 s)")
        if serial:
            swall, scpu = min(w for w, _ in serial), min(c for _, c in serial)
            print(f"ours, PENDULAB_JOBS=1: {swall:6.2f} s wall, {scpu:6.2f} s CPU")
            if tree(tmp / "serial0") != tree(tmp / "ours0"):
                print("the serial build wrote OTHER bytes than the parallel one")
        if base:
            bwall, bcpu = min(w for w, _ in base), min(c for _, c in base)
            print(f"baseline: {bwall:6.2f} s wall, {bcpu:6.2f} s CPU  (pendulab at {BASELINE})")
            print(f"ratio baseline/ours: wall {bwall / wall:.2f}x, CPU {bcpu / cpu:.2f}x")
            differ, total = differing(tmp / "ours0", tmp / "base0")
            print(f"same bytes as the baseline: {'yes' if not differ else 'no'}"
                  + (f" ({len(differ)} of {total} files differ: "
                     f"{', '.join(differ[:8])}{' ...' if len(differ) > 8 else ''})" if differ else ""))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
