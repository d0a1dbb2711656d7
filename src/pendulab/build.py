"""``pendulab build``: scenes in, generated/<scene>/ out.

The input hash covers the validated scene table and pendulab's version.  When
generated/<scene>/manifest.json records the same hash and the same scene file
(``source``, see :func:`source_name`) and every file it lists is present with
the recorded SHA-256, the scene is skipped; ``force=True`` rebuilds.  A code
change that alters products without a version bump needs ``--force`` (CI
rebuilds everything with force and compares byte for byte).
"""

import hashlib
import json
import os
from pathlib import Path

from pendulab import __version__
from pendulab.errors import InputError, PendulabError, SceneError
from pendulab.io import canonical_json, clean_leftovers, publish_lock, write_tree
from pendulab.procs import die_with_parent
from pendulab.scene import load_scene

MANIFEST = "manifest.json"


def _sha(text):
    """SHA-256 of a product file: text as UTF-8, bytes (figures) as they are."""
    return hashlib.sha256(text if isinstance(text, bytes) else text.encode("utf-8")).hexdigest()


def input_hash(scene):
    return _sha(canonical_json({"scene": scene.raw, "pendulab": __version__}))


def _up_to_date(directory, digest, source):
    data = _read_manifest(directory)
    if data is None or data.get("input_sha256") != digest or data.get("source") != source:
        return False
    files = data.get("files")
    if not isinstance(files, dict):
        return False
    for name, sha in files.items():
        try:
            if _sha((directory / name).read_bytes()) != sha:
                return False
        except OSError:
            return False
    # a file left out because this machine could not make it (pendulab.io.Kept): out of date
    # as soon as its product can make it here (TeX installed since, for the notes' PDF)
    missing = data.get("not_written")
    if isinstance(missing, dict):
        from pendulab.pipeline import PRODUCTS, product_module
        for name, product in missing.items():
            if product in PRODUCTS and getattr(product_module(product), "can_make", lambda n: False)(name):
                return False
    return True


def scene_paths(target):
    """The scene files named by ``target`` (a file, or a directory of *.toml)."""
    if not isinstance(target, (str, os.PathLike)) or not str(target).strip():
        raise InputError(f"name a scene file or a directory of them, got {target!r}")
    target = Path(target)
    if target.is_dir():
        paths = sorted(target.glob("*.toml"))
        if not paths:
            raise SceneError(target, None, "no *.toml scene files in this directory")
        return paths
    return [target]


def check_out_root(out_root, what="output directory"):
    """Refuse an output root that cannot be used, before any work; return it as a Path.

    Refused: an empty name, a path that exists and is not a directory, and a
    missing one whose nearest existing ancestor is not a writable directory.
    """
    if out_root is None or not str(out_root).strip():
        raise InputError(f"{what} is empty: name a directory (the default is 'generated')")
    text = str(out_root)
    if "\0" in text:
        raise InputError(f"{what} {text!r} contains a NUL character")
    root = Path(text)
    probe = root
    while not os.path.lexists(probe):
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        if probe == root:
            raise InputError(f"{what} {text} exists and is not a directory")
        raise InputError(f"{what} {text}: {probe} is not a directory, so it cannot be created")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(f"{what} {text}: {probe} is not writable")
    name_max = _name_max(probe)
    for part in root.parts:
        if len(os.fsencode(part)) > name_max:
            raise InputError(f"{what} {text}: the name {part[:20]}... is longer than "
                             f"{name_max} bytes")
    # os.access says yes to root in /proc or /sys, where nothing can be created: try it, with
    # a file that has no name (O_TMPFILE on Linux; elsewhere one unlinked as it is made), so
    # that a build killed here leaves nothing in the directory
    import tempfile
    try:
        with tempfile.TemporaryFile(dir=probe):
            pass
    except OSError as exc:
        raise InputError(f"{what} {text}: cannot create anything in {probe} "
                         f"({exc.strerror or exc})") from None
    return root


def _name_max(directory):
    try:
        return os.pathconf(directory, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return 255


def source_name(path):
    """The scene file as recorded in manifest.json: '<its directory's name>/<file name>'.

    The same however the file was named on the command line (relative or
    absolute) and without any path of the machine: derivations/kapitza-rod.toml.
    """
    p = Path(path).resolve()
    return f"{p.parent.name}/{p.name}" if p.parent.name else p.name


def _read_manifest(directory):
    try:
        data = json.loads((directory / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _check_claim(scene, directory, source, replace):
    """Refuse to replace ``directory`` when it holds another scene file's outputs (or foreign files)."""
    if replace or not os.path.lexists(directory):
        return
    if directory.is_symlink() or not directory.is_dir():
        raise SceneError(scene.path, "name", f"the output {directory} exists and is not a directory")
    data = _read_manifest(directory)
    if data is None:
        if any(True for _ in directory.iterdir()):
            raise SceneError(scene.path, "name",
                             f"the output {directory} holds files that pendulab build did not write "
                             "(no readable manifest.json); move them away or give --replace")
        return
    owner = data.get("source")
    if owner is not None and owner != source:
        # the scene is named as the user gave it (SceneError's prefix); the owner only as its
        # manifest records it ('<directory name>/<file name>', no path of the machine)
        raise SceneError(scene.path, "name",
                         f"{directory} holds the outputs of another scene file, recorded as "
                         f"{owner} in its {MANIFEST}; rename this scene or give --replace to "
                         "replace them")


def build(target, out_root="generated", force=False, log=print, replace=False, jobs=None):
    """Build every scene named by ``target`` into ``out_root``/<scene name>/.

    The output root is checked first, then all scenes are read and validated,
    then computed; only then are the outputs published, each scene's directory
    replaced crash-safely (:func:`pendulab.io.write_tree`) while holding the
    root's lock (:func:`pendulab.io.publish_lock`), after removing what killed
    builds left there.  A scene whose name is already built in ``out_root``
    from another scene file (manifest.json records it) is refused unless
    ``replace=True``.  ``jobs`` - processes computing scenes side by side
    (None: the environment variable PENDULAB_JOBS, else one per available
    core, at most :data:`MAX_JOBS`; see :func:`compute_scenes`).  Returns
    {scene name: status}.
    """
    root = check_out_root(out_root)
    jobs = job_count(jobs)
    scenes = [load_scene(p) for p in scene_paths(target)]
    names = {}
    for sc in scenes:
        if sc.name in names:
            raise SceneError(sc.path, "name", f"scene name {sc.name!r} is also used by {names[sc.name]}")
        names[sc.name] = sc.path
    sources = {sc.name: source_name(sc.path) for sc in scenes}
    for sc in scenes:
        _check_claim(sc, root / sc.name, sources[sc.name], replace)
    # Compute every scene first, write afterwards: a scene that fails to build
    # leaves every output directory as it was (no partial output).
    status, todo = {}, []
    for sc in scenes:
        directory = root / sc.name
        digest = input_hash(sc)
        if not force and _up_to_date(directory, digest, sources[sc.name]):
            status[sc.name] = "up to date"
            log(f"{sc.name}: up to date ({directory}){_headlines(sc, directory)}")
            continue
        todo.append((sc, directory, digest))
    pending = []
    for (sc, directory, digest), (files, ran) in zip(todo, compute_scenes([t[0] for t in todo], jobs)):
        not_written = _resolve_kept(sc, directory, files, log)
        manifest = {
            "scene": sc.name,
            "source": sources[sc.name],
            "system": sc.system,
            "products": sorted(sc.products),
            "generator": f"pendulab {__version__}",
            "input_sha256": digest,
            "files": {name: _sha(text) for name, text in sorted(files.items())},
            "note": "generated by pendulab build from the scene file; do not edit",
        }
        if not_written:
            manifest["not_written"] = not_written
        files[MANIFEST] = canonical_json(manifest)
        pending.append((sc, directory, files, ran))
    try:
        with publish_lock(root, log):
            cleaned = clean_leftovers(root)
            if cleaned:
                log(f"removed {cleaned} leftover(s) of interrupted builds in {root}")
            # another build may have published meanwhile: check the claims again, under the lock
            for sc, directory, files, ran in pending:
                _check_claim(sc, directory, sources[sc.name], replace)
            for sc, directory, files, ran in pending:
                write_tree(directory, files, have_lock=True)
                status[sc.name] = "built"
                log(f"{sc.name}: built {len(files)} files in {directory} "
                    f"(stages: {', '.join(ran) or 'none'}){_headlines(sc, directory)}")
    except OSError as exc:
        where = exc.filename or root
        raise PendulabError(f"cannot write {where}: {exc.strerror or exc}") from None
    return status


def _headlines(scene, directory):
    """"; <what>: <path>" for each file a product of ``scene`` names as the one a reader
    opens first (a product module's ``HEADLINE``, e.g. the notes' PDF), where it exists."""
    from pendulab.pipeline import PRODUCTS, product_module
    said = []
    for name in sorted(scene.products):
        if name not in PRODUCTS:
            continue
        what, filename = getattr(product_module(name), "HEADLINE", (None, None))
        if filename and (directory / filename).is_file():
            said.append(f"; {what}: {directory / filename}")
    return "".join(said)


def _resolve_kept(scene, directory, files, log):
    """Replace each :class:`pendulab.io.Kept` in ``files`` by the bytes published before in
    ``directory`` when the manifest there shows they were made from the same inputs;
    otherwise leave the file out.  One line of ``log`` for each.  Returns {file left out:
    the product that could not make it}, for the manifest (see :func:`_up_to_date`)."""
    from pendulab.io import Kept
    kept = [name for name, text in files.items() if isinstance(text, Kept)]
    left_out = {}
    if not kept:
        return left_out
    old = (_read_manifest(directory) or {}).get("files")
    old = old if isinstance(old, dict) else {}
    for name in kept:
        wanted = files.pop(name)
        same = all(old.get(k) == _sha(files[k]) for k in wanted.inputs if k in files) \
            and all(k in files for k in wanted.inputs)
        data = None
        if same and name in old:
            try:
                data = (directory / name).read_bytes()
            except OSError:
                data = None
            if data is not None and _sha(data) != old[name]:
                data = None
        if data is not None:
            files[name] = data
            log(f"{scene.name}: {wanted.reason}; {name} kept as built before from the same inputs")
        else:
            left_out[name] = wanted.product
            log(f"{scene.name}: {wanted.reason}; {name} not written (none was built before "
                "from these inputs)")
    return left_out


def _run(scene):
    """Run the scene's products; a problem met on the way names the file and the product."""
    from pendulab.pipeline import run_products
    try:
        return run_products(scene)
    except SceneError:
        raise
    except PendulabError as exc:
        key = getattr(exc, "product", None)
        where = f"products.{key}" if key else "products"
        raise SceneError(scene.path, where, str(exc)) from None


# ---------------------------------------------------------------------------
# computing scenes side by side
# ---------------------------------------------------------------------------

#: Most processes a build starts by default (more cores than scenes buy nothing).
MAX_JOBS = 8


def job_count(jobs=None):
    """Processes for computing scenes: ``jobs``, else $PENDULAB_JOBS, else the cores available
    to this process (at most :data:`MAX_JOBS`).  1 computes in this process."""
    where = "jobs"
    if jobs is None:
        text = os.environ.get("PENDULAB_JOBS", "").strip()
        if text:
            where, jobs = "PENDULAB_JOBS", text
    if jobs is None:
        try:
            cores = len(os.sched_getaffinity(0))
        except (AttributeError, OSError):
            cores = os.cpu_count() or 1
        return max(1, min(cores, MAX_JOBS))
    try:
        value = int(jobs) if not isinstance(jobs, bool) else None
    except (TypeError, ValueError):
        value = None
    if value is None or not 1 <= value <= 64 or (isinstance(jobs, float) and jobs != value):
        raise InputError(f"{where} must be a whole number of processes between 1 and 64, got {jobs!r}")
    return value


#: Relative cost of a product, or of one part of a product made in parts ("product:part"),
#: in the committed scenes (CPU of the main job), used only to start the dearest first so
#: that the processes finish together; any order gives the same files.  Not listed: 1.
WEIGHTS = {"motion": 10, "experiments:map:text": 6, "experiments:first": 6, "bessel": 3,
           "stability": 2.5, "experiments:fig5": 2.2, "experiments:map:caption": 1.6,
           "experiments:map:fig4": 1.6, "experiments:fig2": 1.8, "kernels": 1,
           "experiments:summary": 0.3, "series": 0.3, "floquet": 0.3, "equations": 0.2,
           "quarter_periods": 0.2}


#: Weight below which a task of a scene that only other processes have worked on is left to
#: them (its scene's stages cost more than the task: the variable length's derivation and
#: closed form, about 0.3 s, against its equations product, 0.01 s).
SMALL = 1.0


def _weight(task):
    _, name, part = task
    return WEIGHTS.get(name if part is None else f"{name}:{part}", 1)


def compute_scenes(scenes, jobs=1):
    """[(files, stages that ran)] of every scene, in order; the products side by side in ``jobs`` processes.

    The outputs do not depend on ``jobs``: each product is computed by the same
    code from the same inputs, whichever process runs it.  With ``jobs`` > 1,
    two or more products in all and ``fork`` available:

    * the derivations that several scenes share (same
      :func:`pendulab.equations.derivation_key`) are done here first, and so
      are the imports of the heavy modules that the products of several
      scenes declare (``preload(options)`` of a product module: matplotlib);
    * then ``jobs`` - 1 worker processes are forked (they inherit both), and
      this process and the workers take the tasks one at a time, dearest
      first (:data:`WEIGHTS`; :meth:`_Shared.take`): a task is a product,
      or one part of a product that is made in parts
      (:func:`pendulab.pipeline.product_parts`; the experiments' maps and
      figures), whose results this process assembles at the end; a process
      keeps the stages of the scenes it has worked on, so a scene's tasks
      that land in one process share them;
    * a scene whose products did not all succeed (an error, a worker that
      died) is computed again here, in order, after the scenes before it, so
      that the error is the one a serial build reports (one line naming the
      scene file and the product) and nothing is published.  After the first
      error no process starts another product.
    """
    if not scenes:
        return []
    import multiprocessing as mp

    from pendulab.pipeline import STAGES, finish_product, merge_files, product_parts
    try:
        tasks = [(i, name, part) for i, sc in enumerate(scenes) for name in sorted(sc.products)
                 for part in product_parts(name, sc.products[name])]
    except PendulabError:
        tasks = []  # the serial run reports it
    if jobs <= 1 or len(tasks) < 2 or "fork" not in mp.get_all_start_methods():
        return [_run_serial(sc) for sc in scenes]
    _share_derivations(scenes)
    _preload(scenes)
    tasks.sort(key=lambda t: -_weight(t))  # stable: scene order within a weight
    import gc
    fork = mp.get_context("fork")
    workers = []
    done = {}
    frozen = gc.get_freeze_count() == 0  # a caller's own frozen objects are left as they are
    try:
        state = _Shared(fork.Array("b", len(tasks)), fork.Array("i", len(scenes)), fork.Value("b", 0),
                        [_weight(t) for t in tasks])
        if frozen:
            gc.freeze()  # the shared heap stays out of the collections (the workers' pages stay shared)
        parent = os.getpid()
        for me in range(1, min(jobs, len(tasks))):
            receive, send = fork.Pipe(duplex=False)
            others = [r for _, r in workers]  # inherited by the fork: the worker closes them
            proc = fork.Process(target=_worker, args=(scenes, tasks, state, send, me, parent, others),
                                daemon=True)
            proc.start()
            send.close()
            workers.append((proc, receive))
        done.update(_take_products(scenes, tasks, state, 0))
        for proc, receive in workers:
            try:
                done.update(receive.recv())
            except (EOFError, OSError):
                pass  # the worker died (killed, out of memory): its products are computed here
            proc.join()
    finally:
        for proc, receive in workers:  # an error here, or Ctrl-C: no worker goes on computing
            if proc.is_alive():
                proc.terminate()
            proc.join()
            receive.close()
        if frozen:
            gc.unfreeze()  # this process goes on (an API caller's): its objects are collectable again
    out = []
    for i, sc in enumerate(scenes):
        mine = [k for k, (j, _, _) in enumerate(tasks) if j == i]
        try:
            if any(done.get(k) is None for k in mine):
                raise LookupError
            results = {}
            for k in mine:
                results.setdefault(tasks[k][1], {})[tasks[k][2]] = done[k][0]
            files = merge_files([(name, finish_product(sc, name, results[name]))
                                 for name in sorted(results)])
        except (LookupError, PendulabError):
            out.append(_run_serial(sc))  # raises the scene's own error, as a serial build does
            continue
        ran = set().union(*(done[k][1] for k in mine))
        out.append((files, [name for name in STAGES if name in ran]))
    return out


class _Shared:
    """What the processes share: which tasks are taken, which processes have worked on each
    scene (a bit per process), the flag that stops taking; and the tasks' weights."""

    def __init__(self, taken, touched, stop, weights):
        self.taken, self.touched, self.stop, self.weights = taken, touched, stop, weights

    def take(self, tasks, me):
        """Index of the task process ``me`` computes next (None: all are taken).

        The first task not yet taken, in order (dearest first), unless its scene
        has been worked on by other processes only and a task at least half as
        dear of a scene this process knows, or of one nobody has touched, is
        still free: then that one, so that a scene's stages (the variable
        length's derivation and closed form) are made in fewer processes.  A
        task lighter than :data:`SMALL` of a scene only other processes have
        worked on is never taken: such a process takes one of its own scenes
        or of nobody's, or stops (None), and leaves it to them.
        """
        bit = 1 << (me % 31)  # a shared bit beyond 31 processes only blurs the preference

        def foreign(task):
            seen = self.touched[tasks[task][0]]
            return seen and not seen & bit

        with self.taken.get_lock():
            free = [k for k in range(len(tasks)) if not self.taken[k]]
            if not free:
                return None
            k = free[0]
            if foreign(k):
                for j in free[1:]:
                    if self.weights[j] < self.weights[k] / 2:
                        break
                    if not foreign(j):
                        k = j
                        break
            if foreign(k) and self.weights[k] < SMALL:
                # the rest is small: what is another process's is left to it (made here it
                # would derive that scene's stages again, dearer than the task itself)
                own = [j for j in free if not foreign(j)]
                if not own:
                    return None
                k = own[0]
            self.taken[k] = 1
            self.touched[tasks[k][0]] |= bit
            return k


def _take_products(scenes, tasks, state, me):
    """{task index: (result, stages of its scene that ran in this process) or None (failed)}
    of the products and parts of products this process takes until none is left or one
    has failed (a product's result is its {file: text}, a part's what the part gives)."""
    from pendulab.pipeline import Context, run_part
    contexts, done = {}, {}
    while not state.stop.value:
        k = state.take(tasks, me)
        if k is None:
            break
        i, name, part = tasks[k]
        try:
            ctx = contexts.setdefault(i, Context(scenes[i]))
            done[k] = (run_part(ctx, name, part), list(ctx.ran))
        except Exception:  # reported by the serial run of its scene
            done[k] = None
            state.stop.value = 1
    return done


def _worker(scenes, tasks, state, send, me, parent, others):
    """A forked worker: take products, send what they gave, end without tearing down.

    It dies with ``parent`` however that dies (:func:`pendulab.procs.die_with_parent`),
    and closes ``others``, the read ends of the pipes of the workers forked before it,
    so that a worker whose reader is gone is told so (EPIPE) instead of waiting for ever.
    """
    import signal
    status = 1
    try:
        die_with_parent(parent)
        for receive in others:
            receive.close()
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent stops the workers itself
        send.send(_take_products(scenes, tasks, state, me))
        send.close()
        status = 0
    except BaseException:  # noqa: B036 (nothing may print here; the parent recomputes)
        pass
    finally:
        os._exit(status)


def _run_serial(scene):
    files, ctx = _run(scene)
    return files, list(ctx.ran)


def _share_derivations(scenes):
    """Derive, in this process, the equations that two or more of ``scenes`` have in common,
    and their canonical form (which the analyses of such scenes read; its first simplify
    also imports sympy.physics.units, about 0.1 s that each process would pay again)."""
    from pendulab.equations import derivation_key, derive
    from pendulab.pipeline import Context, canonical_form
    systems = {}
    for sc in scenes:
        try:
            system = Context(sc).get("system")
            key = derivation_key(system)
        except PendulabError:
            continue  # the scene's own computation reports it
        systems.setdefault(key, []).append(system)
    for key, found in systems.items():
        if len(found) > 1:
            try:
                canonical_form(derive(found[0]))
            except PendulabError:
                pass


def _preload(scenes):
    """Import the heavy modules that the products of two or more of ``scenes`` declare."""
    import importlib
    from collections import Counter

    from pendulab.pipeline import product_module
    wanted = Counter()
    for sc in scenes:
        names = set()
        for name, options in sc.products.items():
            hook = getattr(product_module(name), "preload", None)
            if hook is not None:
                names.update(hook(options))
        wanted.update(names)
    for name, count in sorted(wanted.items()):
        if count < 2:
            continue
        try:
            if name == "matplotlib":  # the Agg backend first, as the products choose it
                from pendulab.figures import pyplot
                pyplot("build")
                importlib.import_module("matplotlib.backends.backend_pdf")
            else:
                importlib.import_module(name)
        except (ImportError, PendulabError):
            pass  # the product that needs it reports that, in one line
