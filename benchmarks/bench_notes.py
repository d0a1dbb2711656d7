"""Time of the lecture notes' build, beside the other committed scenes', one command:

    python benchmarks/bench_notes.py [--repeat N]

Each round runs, in fresh interpreters, with bytecode caches already written (one untimed
build of each first):

* ours - ``pendulab build derivations/lecture-notes.toml --force --out <temporary>``
  (PDF included where pdflatex or latexmk is installed);
* baseline - the same command on the other committed scenes (every ``derivations/*.toml``
  but the notes), the rest of ``pendulab build derivations/``.

It prints the wall and CPU time (user + system, the build's worker processes and pdfTeX
included) of each, their ratio, and the target: the notes within 20 s of wall time on the
shared 2-core machine.  With ``--repeat`` the fastest round of each counts (the machine is
shared and noisy).  Then it says where the time goes: each section of the notes and the
assembly (the PDF's two pdfTeX runs), computed one after another in this process, CPU time.
"""

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTES = ROOT / "derivations" / "lecture-notes.toml"
TARGET_WALL = 20.0


def _children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed_build(scenes, out):
    """(wall s, CPU s) of one ``pendulab build`` of ``scenes`` (a file or a directory)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    cpu, wall = _children_cpu(), time.perf_counter()
    subprocess.run([sys.executable, "-m", "pendulab", "build", str(scenes), "--force", "--out", str(out)],
                   check=True, cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
    return time.perf_counter() - wall, _children_cpu() - cpu


def breakdown():
    """[(part, CPU s)] of the notes' sections and assembly, one after another in this process."""
    from pendulab.pipeline import Context
    from pendulab.products import notes
    from pendulab.scene import parse_scene
    scene = parse_scene(tomllib.loads(NOTES.read_text()), str(NOTES.relative_to(ROOT)))
    ctx, options = Context(scene), scene.products["notes"]
    rows, results = [], {}
    start = time.process_time()
    ctx.get("canonical")
    rows.append(("derivation (system, equations, canonical)", time.process_time() - start))
    for section in notes.parts(options):
        start = time.process_time()
        results[section] = notes.produce_part(ctx, options, section)
        rows.append((f"section {section}", time.process_time() - start))
    start = time.process_time()
    cpu = _children_cpu()
    notes.assemble(scene, options, results)
    rows.append(("assembly (notes.tex; notes.pdf: pdfTeX, CPU of the children)",
                 time.process_time() - start + _children_cpu() - cpu))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1, help="rounds (the fastest counts)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    with tempfile.TemporaryDirectory(prefix="pendulab-bench-notes-") as tmp:
        others = Path(tmp) / "others"
        others.mkdir()
        for scene in sorted((ROOT / "derivations").glob("*.toml")):
            if scene != NOTES:
                shutil.copy(scene, others / scene.name)
        timed_build(NOTES, Path(tmp) / "warm-notes")
        timed_build(others, Path(tmp) / "warm-others")
        ours, base = [], []
        for k in range(args.repeat):
            ours.append(timed_build(NOTES, Path(tmp) / f"notes{k}"))
            base.append(timed_build(others, Path(tmp) / f"others{k}"))
        pdf = (Path(tmp) / "notes0" / "lecture-notes" / "notes.pdf").exists()
    (ow, oc), (bw, bc) = min(ours), min(base)
    print(f"ours:     lecture-notes.toml   wall {ow:6.2f} s   CPU {oc:6.2f} s"
          f"   (PDF {'compiled' if pdf else 'not compiled: no TeX here'})")
    count = len([p for p in (ROOT / "derivations").glob("*.toml") if p != NOTES])
    print(f"baseline: the other {count} scenes     wall {bw:6.2f} s   CPU {bc:6.2f} s")
    print(f"ratio ours/baseline: wall {ow / bw:.2f}, CPU {oc / bc:.2f}")
    print(f"target: the notes within {TARGET_WALL:.0f} s of wall time: "
          f"{'met' if ow <= TARGET_WALL else 'NOT met'} ({ow / TARGET_WALL:.2f} of it)")
    print("where the time goes (CPU, one process, one after another):")
    for part, seconds in breakdown():
        print(f"  {part:62s} {seconds:6.2f} s")


if __name__ == "__main__":
    main()
