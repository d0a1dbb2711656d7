"""Deterministic text and atomic writes.

Every product is text built in memory; :func:`write_tree` puts a whole set of
files in place at once (temporary directory, then rename), so a failed build
leaves the previous outputs untouched.
"""

import json
import os
import shutil
import tempfile
from pathlib import Path


def canonical_json(obj):
    """JSON text with sorted keys, two-space indent and a final newline.

    Byte-identical for equal input on every run and machine.
    """
    return json.dumps(obj, sort_keys=True, indent=2, ensure_ascii=False,
                      allow_nan=False) + "\n"


def write_text_atomic(path, text):
    """Write ``text`` to ``path`` through a temporary file and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_tree(directory, files):
    """Replace ``directory`` by exactly ``files`` (relative name -> text, or bytes for figures).

    The files are written into a sibling temporary directory which then takes
    the place of ``directory``; if anything fails before the swap, the old
    directory is left as it was.
    """
    directory = Path(directory)
    directory.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{directory.name}.tmp-", dir=directory.parent))
    old = None
    try:
        for name, text in sorted(files.items()):
            target = tmp / name
            if target.resolve().parent != tmp.resolve() and tmp.resolve() not in target.resolve().parents:
                raise ValueError(f"product file name {name!r} leaves the output directory")
            target.parent.mkdir(parents=True, exist_ok=True)
            if isinstance(text, bytes):  # figures (PNG, PDF)
                with open(target, "wb") as fh:
                    fh.write(text)
            else:
                with open(target, "w", encoding="utf-8", newline="\n") as fh:
                    fh.write(text)
        if directory.exists():
            old = directory.with_name(f".{directory.name}.old-{os.getpid()}")
            if old.exists():
                shutil.rmtree(old)
            os.replace(directory, old)
        os.replace(tmp, directory)
    except BaseException:
        if tmp.exists():
            shutil.rmtree(tmp)
        if old is not None and old.exists() and not directory.exists():
            os.replace(old, directory)
        raise
    if old is not None and old.exists():
        shutil.rmtree(old)
