"""Deterministic text and crash-safe, concurrent-safe publishing of outputs.

Every product is text built in memory.  :func:`write_tree` publishes a whole
set of files as the new content of one directory (``generated/<scene>/``):

1. the new set is written into a hidden sibling ``.<name>.tmp-<16 hex>/``
   and made durable (one ``syncfs`` of the file system on Linux, else an
   ``fsync`` of each file and of the directory);
2. that sibling and ``<name>/`` are swapped in one step by
   ``renameat2(RENAME_EXCHANGE)`` (Linux; ``renamex_np(RENAME_SWAP)`` on
   macOS), so ``<name>/`` is at every moment a plain directory holding the
   complete old set or the complete new set; if the directory did not exist
   yet, a plain ``rename`` puts the new one in place;
3. the sibling, which now holds the old set, is removed.

Where the exchange is not available (other systems, file systems that refuse
it with EINVAL), the fallback renames ``<name>/`` to ``.<name>.old-<hex>/``
and the new directory in its place; between those two renames the directory
is missing, and a process killed there leaves the old set in the ``.old-``
sibling, which :func:`clean_leftovers` puts back.

All of it runs under an exclusive ``flock`` of ``<root>/.pendulab.lock``
(:func:`publish_lock`), so two publishers into one root take turns, and a
``.tmp-``/``.old-`` sibling seen by the lock holder can only be a leftover of a
killed run: :func:`clean_leftovers` removes it (or restores an ``.old-`` set
whose directory is missing).  Readers take no lock.
"""

import contextlib
import errno
import functools
import json
import os
import re
import secrets
import sys
from pathlib import Path

#: Name of the lock file in an output root.
LOCK_NAME = ".pendulab.lock"
#: Hidden siblings made by a publish: ".<name>.tmp-<token>" (new set, or the old
#: one after the exchange) and ".<name>.old-<token>" (old set, fallback only),
#: with a token of 16 hex digits.  Other tokens are the names of pendulab 0.2.0
#: (mkdtemp's eight characters, ".old-<pid>"); such a directory counts as a
#: leftover only when it holds a manifest.json written by pendulab, since a
#: name like ".vim.old-1" may be a user's own.
_LEFTOVER = re.compile(r"\.(?P<name>[A-Za-z0-9][A-Za-z0-9_.-]*?)\.(?P<kind>tmp|old)-"
                       r"(?P<token>[A-Za-z0-9_]{1,32})\Z")
_TOKEN = re.compile(r"[0-9a-f]{16}\Z")
#: errno values by which an exchange says "not supported here": use the fallback.
_UNSUPPORTED = {errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP}


class Kept:
    """A product file that cannot be made on this machine (the PDF of the lecture notes
    without TeX): the build keeps the copy it published before, if that copy was made
    from the same ``inputs`` (the other files of the product, compared by the hashes
    in manifest.json), and leaves the file out otherwise; it says which in one line
    that ends with ``reason``.  ``product`` names the product, whose module's
    ``can_make(name)`` tells a later build whether the file can be made there."""

    def __init__(self, name, inputs, reason, product=None):
        self.name, self.inputs, self.reason, self.product = name, tuple(inputs), reason, product

    def __repr__(self):
        return f"Kept({self.name!r}, inputs={list(self.inputs)!r})"


def canonical_json(obj):
    """JSON text with sorted keys, two-space indent and a final newline.

    Byte-identical for equal input on every run and machine.
    """
    return json.dumps(obj, sort_keys=True, indent=2, ensure_ascii=False,
                      allow_nan=False) + "\n"


def _write_file(path, text, sync=True):
    """Create ``path`` (it must not exist) with ``text`` as UTF-8 (bytes as they are); fsync'ed if ``sync``."""
    data = text if isinstance(text, bytes) else text.encode("utf-8")
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        if sync:
            os.fsync(fd)
    finally:
        os.close(fd)


def _syncfs(path):
    """Flush the file system holding ``path`` in one call (Linux syncfs); False if unavailable.

    One syncfs costs about as much as one fsync, so a set of N files is made
    durable for the price of one file instead of N.
    """
    if not sys.platform.startswith("linux"):  # pragma: no cover
        return False
    try:
        ctypes, libc = _libc()
        fn = libc.syncfs
    except (OSError, AttributeError):  # pragma: no cover
        return False
    fd = os.open(path, os.O_RDONLY)
    try:
        if fn(fd) != 0:
            err = ctypes.get_errno()
            raise OSError(err, os.strerror(err), os.fsdecode(path))
    finally:
        os.close(fd)
    return True


def _fsync_dir(path):
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:  # pragma: no cover - systems that cannot open directories
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - file systems without directory fsync
        pass
    finally:
        os.close(fd)


def write_text_atomic(path, text):
    """Write ``text`` to ``path`` through a temporary sibling and one rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp-{secrets.token_hex(8)}")
    try:
        _write_file(tmp, text)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _remove_tree(path):
    """Remove the directory ``path`` and everything in it (symlinks are not followed)."""
    with os.scandir(path) as entries:
        for entry in list(entries):
            if entry.is_dir(follow_symlinks=False):
                _remove_tree(entry.path)
            else:
                os.unlink(entry.path)
    os.rmdir(path)


@functools.lru_cache(maxsize=1)
def _libc():
    """ctypes and the C library (the process's own symbols: no library search)."""
    import ctypes
    return ctypes, ctypes.CDLL(None, use_errno=True)


@functools.lru_cache(maxsize=1)
def _has_syncfs():
    """Linux: the new files are made durable by one syncfs before the swap, not one fsync each."""
    try:
        return sys.platform.startswith("linux") and hasattr(_libc()[1], "syncfs")
    except OSError:  # pragma: no cover
        return False


def _rename_exchange(a, b):
    """Swap the paths ``a`` and ``b`` in one step (both must exist).

    Linux: renameat2(AT_FDCWD, a, AT_FDCWD, b, RENAME_EXCHANGE); macOS:
    renamex_np(a, b, RENAME_SWAP).  Raises OSError; errno EINVAL, ENOSYS or
    ENOTSUP means the system or file system cannot do it.
    """
    a, b = os.fsencode(a), os.fsencode(b)
    try:
        ctypes, libc = _libc()
    except OSError:  # pragma: no cover - no C library to call
        raise OSError(errno.ENOSYS, "no C library for an atomic exchange") from None
    if sys.platform.startswith("linux") and hasattr(libc, "renameat2"):
        fn = libc.renameat2
        fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
        result = fn(-100, a, -100, b, 2)  # AT_FDCWD, RENAME_EXCHANGE
    elif sys.platform == "darwin" and hasattr(libc, "renamex_np"):  # pragma: no cover
        fn = libc.renamex_np
        fn.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint]
        result = fn(a, b, 2)  # RENAME_SWAP
    else:  # pragma: no cover
        raise OSError(errno.ENOSYS, "no atomic exchange of two paths on this system")
    if result != 0:
        err = ctypes.get_errno()
        raise OSError(err, os.strerror(err), os.fsdecode(a), None, os.fsdecode(b))


@contextlib.contextmanager
def publish_lock(root, log=None):
    """Hold the exclusive lock of the output root ``root`` (blocks while another holds it).

    The lock is an ``flock`` of ``root/.pendulab.lock`` (created if missing,
    never removed: removing a lock file races with its next user).  It is
    released when the block ends or the process dies.  Where ``fcntl`` does not
    exist (Windows), publishing is not serialised.
    """
    root = Path(root)
    root.mkdir(parents=True, exist_ok=True)
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    fd = os.open(root / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            if log is not None:
                log(f"waiting for another build publishing into {root}")
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        with contextlib.suppress(OSError):
            os.close(fd)


def leftovers(root, name=None):
    """The hidden siblings in ``root`` that a publish leaves only when it is killed.

    A list of (path, directory name, kind "tmp" | "old"), sorted; only
    directories whose names have the publisher's pattern.  ``name`` restricts
    to one directory.
    """
    root = Path(root)
    found = []
    try:
        entries = sorted(os.listdir(root))
    except FileNotFoundError:
        return found
    for entry in entries:
        m = _LEFTOVER.match(entry)
        if not m or (name is not None and m["name"] != name):
            continue
        path = root / entry
        if not path.is_dir() or path.is_symlink():
            continue
        if _TOKEN.match(m["token"]) or _written_by_pendulab(path):
            found.append((path, m["name"], m["kind"]))
    return found


def _written_by_pendulab(directory):
    try:
        data = json.loads((directory / "manifest.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(data, dict) and str(data.get("generator", "")).startswith("pendulab ")


def clean_leftovers(root, name=None):
    """Restore or remove what killed publishes left in ``root``; call with the lock held.

    An ``.<name>.old-*`` set whose ``<name>`` is missing is renamed back (the
    fallback was killed between its two renames); every other leftover is
    removed.  Returns the number of entries cleaned.
    """
    root = Path(root)
    count = 0
    for path, target, kind in leftovers(root, name):
        final = root / target
        if kind == "old" and not os.path.lexists(final):
            os.rename(path, final)
        else:
            _remove_tree(path)
        count += 1
    return count


def _check_names(files):
    for name in files:
        parts = Path(name).parts if isinstance(name, str) else ()
        if (not parts or Path(name).is_absolute()
                or any(p in ("..", ".") for p in parts) or "\\" in name or "\0" in name):
            raise ValueError(f"product file name {name!r} leaves the output directory")


def write_tree(directory, files, have_lock=False):
    """Make ``directory`` hold exactly ``files`` (relative name -> text), crash-safely.

    See the module docstring for the steps.  A failure before the exchange
    leaves the old directory as it was (the new sibling is removed); a failure
    after it leaves the new set in place (removing the old set is best effort;
    the next publish into the same root cleans what is left).  ``directory``
    must be a directory or missing; a file or a symlink there is refused.
    ``have_lock=True``: the caller holds :func:`publish_lock` of
    ``directory.parent`` (a second flock from the same process would wait for
    itself).
    """
    directory = Path(directory)
    _check_names(files)
    if not have_lock:
        with publish_lock(directory.parent):
            return write_tree(directory, files, have_lock=True)
    clean_leftovers(directory.parent, directory.name)
    if os.path.islink(directory) or (os.path.lexists(directory) and not directory.is_dir()):
        raise NotADirectoryError(errno.ENOTDIR, "exists and is not a directory", str(directory))
    token = secrets.token_hex(8)
    tmp = directory.with_name(f".{directory.name}.tmp-{token}")
    os.mkdir(tmp, 0o777)
    try:
        sync_each = not _has_syncfs()
        for name, text in sorted(files.items()):
            target = tmp / name
            if target.parent != tmp:
                os.makedirs(target.parent, exist_ok=True)
            _write_file(target, text, sync_each)
        if sync_each or not _syncfs(tmp):
            _fsync_dir(tmp)
        if not os.path.lexists(directory):
            os.rename(tmp, directory)
        else:
            try:
                _rename_exchange(tmp, directory)
            except OSError as exc:
                if exc.errno not in _UNSUPPORTED:
                    raise
                _swap_by_two_renames(tmp, directory, token)
    except BaseException:  # not published: the old set is in place, the new one goes
        with contextlib.suppress(OSError):
            _remove_tree(tmp)
        raise
    # Published.  What follows is best effort: an error here is not reported
    # (the new set is in place); the next publish removes what is left.
    with contextlib.suppress(OSError):
        _fsync_dir(directory.parent)
    with contextlib.suppress(OSError):
        if os.path.lexists(tmp):
            _remove_tree(tmp)  # the old set, after the exchange


def _swap_by_two_renames(tmp, directory, token):
    """Fallback: directory -> .<name>.old-<token>, tmp -> directory; the old set is removed.

    If the second rename fails, the old set is renamed back.  Afterwards ``tmp``
    does not exist.
    """
    old = directory.with_name(f".{directory.name}.old-{token}")
    os.rename(directory, old)
    try:
        os.rename(tmp, directory)
    except BaseException:
        with contextlib.suppress(OSError):
            if not os.path.lexists(directory):
                os.rename(old, directory)
        raise
    with contextlib.suppress(OSError):
        _remove_tree(old)
