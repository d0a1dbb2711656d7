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
    return True


def scene_paths(target):
    """The scene files named by ``target`` (a file, or a directory of *.toml)."""
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
    return root


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
        raise SceneError(scene.path, "name",
                         f"{directory} holds the outputs of the scene file {owner}, not of {source}; "
                         "rename the scene or give --replace to replace them")


def build(target, out_root="generated", force=False, log=print, replace=False):
    """Build every scene named by ``target`` into ``out_root``/<scene name>/.

    The output root is checked first, then all scenes are read and validated,
    then computed; only then are the outputs published, each scene's directory
    replaced crash-safely (:func:`pendulab.io.write_tree`) while holding the
    root's lock (:func:`pendulab.io.publish_lock`), after removing what killed
    builds left there.  A scene whose name is already built in ``out_root``
    from another scene file (manifest.json records it) is refused unless
    ``replace=True``.  Returns {scene name: status}.
    """
    root = check_out_root(out_root)
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
    status, pending = {}, []
    for sc in scenes:
        directory = root / sc.name
        digest = input_hash(sc)
        if not force and _up_to_date(directory, digest, sources[sc.name]):
            status[sc.name] = "up to date"
            log(f"{sc.name}: up to date ({directory})")
            continue
        files, ctx = _run(sc)
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
        files[MANIFEST] = canonical_json(manifest)
        pending.append((sc, directory, files, ctx))
    try:
        with publish_lock(root, log):
            cleaned = clean_leftovers(root)
            if cleaned:
                log(f"removed {cleaned} leftover(s) of interrupted builds in {root}")
            # another build may have published meanwhile: check the claims again, under the lock
            for sc, directory, files, ctx in pending:
                _check_claim(sc, directory, sources[sc.name], replace)
            for sc, directory, files, ctx in pending:
                write_tree(directory, files, have_lock=True)
                status[sc.name] = "built"
                log(f"{sc.name}: built {len(files)} files in {directory} "
                    f"(stages: {', '.join(ctx.ran) or 'none'})")
    except OSError as exc:
        where = exc.filename or root
        raise PendulabError(f"cannot write {where}: {exc.strerror or exc}") from None
    return status


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
