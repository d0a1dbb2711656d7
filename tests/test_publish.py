"""Publishing outputs (pendulab.io.write_tree): crash-safe, concurrent-safe, no leftovers.

The invariant checked after every fault: the output directory holds exactly
the complete old set or the complete new set, and its manifest.json lists the
SHA-256 of every other file in it.  Faults are injected at every mutating
file-system call of a publish, counted in order (mkdir, open, write, fsync,
close, rename, unlink, rmdir and the atomic exchange): once as an OSError
raised in the process, once as a SIGKILL of a forked child at that call (no
handler, no finally block runs), and once as a SIGKILL of a real
``pendulab build`` process.
"""

import errno
import hashlib
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from pendulab import io as pio
from pendulab.build import build

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork (POSIX)")

_EXCHANGE = {}


def _exchange_supported(where):
    """Whether two directories in ``where`` can be swapped in one step here, asked of the C
    library itself (not through pendulab.io): renameat2(RENAME_EXCHANGE) on Linux (glibc
    2.28 or later, a kernel and file system that support it), renamex_np(RENAME_SWAP) on
    macOS."""
    import ctypes
    import tempfile
    try:
        libc = ctypes.CDLL(None, use_errno=True)
    except OSError:
        return False
    with tempfile.TemporaryDirectory(dir=where) as tmp:
        a, b = os.path.join(tmp, "a"), os.path.join(tmp, "b")
        os.mkdir(a)
        os.mkdir(b)
        open(os.path.join(a, "x"), "w").close()
        if sys.platform.startswith("linux") and hasattr(libc, "renameat2"):
            fn = libc.renameat2
            fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
            result = fn(-100, os.fsencode(a), -100, os.fsencode(b), 2)  # AT_FDCWD, RENAME_EXCHANGE
        elif sys.platform == "darwin" and hasattr(libc, "renamex_np"):
            fn = libc.renamex_np
            fn.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint]
            result = fn(os.fsencode(a), os.fsencode(b), 2)  # RENAME_SWAP
        else:
            return False
        return result == 0 and os.path.exists(os.path.join(b, "x"))


def _needs_exchange(tmp_path):
    """Skip where the atomic exchange is missing: pendulab.io then takes the two renames,
    which the "two-renames" cases test (by simulating the exchange's refusal)."""
    where = tmp_path.parent
    if where not in _EXCHANGE:
        _EXCHANGE[where] = _exchange_supported(where)
    if not _EXCHANGE[where]:
        pytest.skip("no atomic exchange of two directories here (renameat2 RENAME_EXCHANGE / "
                    "renamex_np RENAME_SWAP): the publishing falls back to two renames")

MUTATING = ("mkdir", "makedirs", "open", "write", "fsync", "close", "rename", "replace",
            "unlink", "rmdir")


def _with_manifest(files):
    out = dict(files)
    out["manifest.json"] = pio.canonical_json(
        {"files": {n: hashlib.sha256(t.encode()).hexdigest() for n, t in sorted(files.items())}})
    return out


OLD = _with_manifest({"a.txt": "old a\n", "b.txt": "old b\n" * 100, "sub/c.txt": "old c\n"})
NEW = _with_manifest({"a.txt": "new a\n", "b.txt": "new b\n" * 50, "d.txt": "new d\n",
                      "sub/c.txt": "new c\n"})


def _contents(directory):
    """{relative name: text} of every file under ``directory``; None if it is missing."""
    if not directory.exists():
        return None
    return {str(p.relative_to(directory)): p.read_text() for p in sorted(directory.rglob("*"))
            if p.is_file()}


def _which_set(directory):
    """"old" | "new" | None (missing); fails on anything else (partial, mixed, bad hashes)."""
    got = _contents(directory)
    if got is None:
        return None
    manifest = json.loads(got["manifest.json"])
    listed = manifest["files"]
    assert set(listed) == set(got) - {"manifest.json"}, sorted(got)
    for name, sha in listed.items():
        assert hashlib.sha256(got[name].encode()).hexdigest() == sha, name
    for label, files in (("old", OLD), ("new", NEW)):
        if got == files:
            return label
    raise AssertionError(f"neither the old nor the new set: {sorted(got)}")


def _clean_listing(root):
    return sorted(os.listdir(root)) == [pio.LOCK_NAME, "out"]


class FaultyOS:
    """Stands in for the ``os`` module inside pendulab.io; acts at mutating call ``at``."""

    def __init__(self, at, action):
        self.at, self.action, self.log = at, action, []

    def __getattr__(self, name):
        real = getattr(os, name)
        if name not in MUTATING:
            return real

        def call(*args, **kwargs):
            if name == "close":  # close(2) frees the descriptor even when it reports an error
                result = real(*args, **kwargs)
                self.tick(name)
                return result
            self.tick(name)
            return real(*args, **kwargs)
        return call

    def tick(self, name):
        self.log.append(name)
        if len(self.log) - 1 == self.at:
            self.action(name)


def _raise_eio(name):
    raise OSError(errno.EIO, f"injected failure in {name}")


def _kill_self(name):
    os.kill(os.getpid(), signal.SIGKILL)


def _install(monkeypatch, fake, fallback=False):
    real_exchange = pio._rename_exchange

    def exchange(a, b):
        fake.tick("exchange")
        if fallback:
            raise OSError(errno.EINVAL, "no exchange on this file system (simulated)")
        return real_exchange(a, b)
    monkeypatch.setattr(pio, "os", fake)
    monkeypatch.setattr(pio, "_rename_exchange", exchange)


def _fresh(tmp_path, with_old=True):
    root = tmp_path / "root"
    directory = root / "out"
    if with_old:
        pio.write_tree(directory, OLD)
        assert _which_set(directory) == "old" and _clean_listing(root)
    return root, directory


def _call_log(tmp_path, monkeypatch, fallback=False, with_old=True):
    root, directory = _fresh(tmp_path / "count", with_old)
    fake = FaultyOS(None, None)
    with monkeypatch.context() as m:
        _install(m, fake, fallback)
        pio.write_tree(directory, NEW)
    assert _which_set(directory) == "new" and _clean_listing(root)
    return fake.log


@pytest.mark.parametrize("fallback", [False, True], ids=["exchange", "two-renames"])
@pytest.mark.parametrize("with_old", [True, False], ids=["replace", "first"])
def test_an_oserror_at_every_call_leaves_old_or_new_and_the_next_publish_cleans(
        tmp_path, monkeypatch, fallback, with_old):
    if not fallback and with_old:
        _needs_exchange(tmp_path)
    log = _call_log(tmp_path, monkeypatch, fallback, with_old)
    assert ("exchange" in log) == with_old
    outcomes = []
    for k in range(len(log)):
        root, directory = _fresh(tmp_path / f"k{k}", with_old)
        fake = FaultyOS(k, _raise_eio)
        with monkeypatch.context() as m:
            _install(m, fake, fallback)
            try:
                pio.write_tree(directory, NEW)
                raised = False
            except OSError as exc:
                assert "injected" in str(exc)
                raised = True
        got = _which_set(directory)
        assert got in ("old", "new") if with_old else got in (None, "new"), (k, log[k])
        if raised:  # an error reported means nothing was published
            assert got == ("old" if with_old else None), (k, log[k])
        outcomes.append(got)
        pio.write_tree(directory, NEW)
        assert _which_set(directory) == "new" and _clean_listing(root), (k, log[k])
    # both outcomes occur: faults before the swap keep the old set, after it the new
    assert outcomes[0] == ("old" if with_old else None) and outcomes[-1] == "new"


def _publish_killed_at(k, directory, fallback):
    """Fork; the child publishes NEW and SIGKILLs itself at mutating call ``k``."""
    pid = os.fork()
    if pid == 0:  # pragma: no cover - runs in the child
        code = 3
        try:
            fake = FaultyOS(k, _kill_self)
            real_exchange = pio._rename_exchange

            def exchange(a, b):
                fake.tick("exchange")
                if fallback:
                    raise OSError(errno.EINVAL, "simulated")
                return real_exchange(a, b)
            pio.os, pio._rename_exchange = fake, exchange
            pio.write_tree(directory, NEW)
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL


@pytest.mark.parametrize("fallback", [False, True], ids=["exchange", "two-renames"])
def test_sigkill_at_every_call(tmp_path, monkeypatch, fallback):
    """Killed at any call: with the exchange the directory is at once the complete old or new
    set; with the fallback it may be missing until the next publish restores the old set."""
    if not fallback:
        _needs_exchange(tmp_path)
    log = _call_log(tmp_path, monkeypatch, fallback)
    seen = set()
    for k in range(len(log)):
        root, directory = _fresh(tmp_path / f"k{k}")
        assert _publish_killed_at(k, directory, fallback), f"call {k} ({log[k]}) was not reached"
        got = _which_set(directory)
        if fallback and got is None:
            assert log[k - 1] == "rename", "missing only between the two renames"
            with pio.publish_lock(root):
                pio.clean_leftovers(root)
            got = _which_set(directory)
            assert got == "old"
        assert got in ("old", "new"), (k, log[k])
        seen.add(got)
        pio.write_tree(directory, NEW)  # the next publish removes what the killed one left
        assert _which_set(directory) == "new" and _clean_listing(root), (k, log[k])
    assert seen == {"old", "new"}


def test_a_failing_final_swap_keeps_the_old_outputs(tmp_path, monkeypatch):
    """The step that puts the new set in place fails (exchange, or the fallback's second
    rename): the error is raised, the old outputs survive, nothing is left behind."""
    root, directory = _fresh(tmp_path)

    def broken(a, b):
        raise OSError(errno.EIO, "injected exchange failure")
    monkeypatch.setattr(pio, "_rename_exchange", broken)
    with pytest.raises(OSError, match="injected"):
        pio.write_tree(directory, NEW)
    assert _which_set(directory) == "old" and _clean_listing(root)

    def unsupported(a, b):
        raise OSError(errno.EINVAL, "simulated")
    monkeypatch.setattr(pio, "_rename_exchange", unsupported)
    real_rename = os.rename
    calls = []
    fake = FaultyOS(None, None)

    def rename(a, b):
        calls.append((a, b))
        if len(calls) == 2:  # tmp -> directory
            raise OSError(errno.EIO, "injected rename failure")
        return real_rename(a, b)
    monkeypatch.setattr(pio, "os", fake)
    monkeypatch.setattr(fake, "rename", rename, raising=False)
    with pytest.raises(OSError, match="injected"):
        pio.write_tree(directory, NEW)
    assert len(calls) == 3  # out -> .old, the failed one, .old -> out
    assert _which_set(directory) == "old" and _clean_listing(root)


def test_the_exchange_is_used_on_this_system(tmp_path):
    """Where the C library and the file system can swap two directories in one step
    (renameat2 RENAME_EXCHANGE on Linux), pendulab.io's exchange does it (else the fallback
    would run)."""
    _needs_exchange(tmp_path)
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    (a / "x").write_text("a")
    pio._rename_exchange(a, b)
    assert (b / "x").read_text() == "a" and not (a / "x").exists()


def test_a_reader_polling_always_sees_the_outputs(tmp_path):
    """A process polling out/manifest.json while another publishes 100 times never misses it
    (the two renames of the fallback leave a moment without it: the exchange is needed)."""
    _needs_exchange(tmp_path)
    root, directory = _fresh(tmp_path)
    stop = tmp_path / "stop"
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the reader
        os.close(r)
        misses = polls = 0
        try:
            while not stop.exists():
                polls += 1
                if not os.path.exists(directory / "manifest.json"):
                    misses += 1
        finally:
            os.write(w, f"{misses} {polls}".encode())
            os._exit(0)
    os.close(w)
    try:
        for i in range(100):
            pio.write_tree(directory, NEW if i % 2 == 0 else OLD)
    finally:
        stop.write_text("")
        os.waitpid(pid, 0)
        misses, polls = map(int, os.read(r, 100).split())
        os.close(r)
    assert polls > 100 and misses == 0
    assert _which_set(directory) == "old" and _clean_listing(root)


def test_concurrent_publishers_take_turns(tmp_path):
    """Two processes publishing into one root 20 times each, at once: all succeed."""
    root, directory = _fresh(tmp_path)
    pids = []
    for files in (OLD, NEW):
        pid = os.fork()
        if pid == 0:  # pragma: no cover - a publisher
            code = 1
            try:
                for _ in range(20):
                    pio.write_tree(directory, files)
                code = 0
            finally:
                os._exit(code)
        pids.append(pid)
    codes = [os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]) for pid in pids]
    assert codes == [0, 0]
    assert _which_set(directory) in ("old", "new") and _clean_listing(root)


def test_the_lock_serialises(tmp_path):
    """While one process holds the lock, another's publish waits for it."""
    root, directory = _fresh(tmp_path)
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the lock holder
        try:
            with pio.publish_lock(root):
                os.write(w, b"locked")
                time.sleep(0.5)
        finally:
            os._exit(0)
    os.read(r, 10)
    start = time.monotonic()
    pio.write_tree(directory, NEW)
    waited = time.monotonic() - start
    os.waitpid(pid, 0)
    assert waited > 0.3 and _which_set(directory) == "new"


def test_names_that_leave_the_directory_are_refused_before_anything_is_written(tmp_path):
    root, directory = _fresh(tmp_path)
    for bad in ("../x.txt", "/abs.txt", "a/../../x", ""):
        with pytest.raises(ValueError, match="leaves the output directory"):
            pio.write_tree(directory, {**NEW, bad: "x"})
        assert _which_set(directory) == "old" and _clean_listing(root)


def test_a_file_or_symlink_in_place_of_the_directory_is_refused(tmp_path):
    root = tmp_path / "root"
    root.mkdir()
    (root / "out").write_text("mine\n")
    with pytest.raises(NotADirectoryError):
        pio.write_tree(root / "out", NEW)
    assert (root / "out").read_text() == "mine\n"
    (root / "elsewhere").mkdir()
    (root / "link").symlink_to(root / "elsewhere")
    with pytest.raises(NotADirectoryError):
        pio.write_tree(root / "link", NEW)
    assert list((root / "elsewhere").iterdir()) == []


# -- the build command ----------------------------------------------------------

SCENE = 'system = "kapitza"\n[parameters]\nbody = "point"\n[products.equations]\n'


def test_build_cleans_and_restores_leftovers_of_older_and_killed_builds(tmp_path):
    """Leftovers named as pendulab 0.2.0 named them (mkdtemp's .X.tmp-xxxxxxxx, .X.old-<pid>),
    and a fallback killed between its renames (X missing, .X.old-* complete): the next build
    of any scene into the root removes the former and puts the latter back."""
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE)
    out = tmp_path / "out"
    build(scene, out, log=lambda m: None)
    manifest = (out / "scene" / "manifest.json").read_text()
    for stray in (".scene.tmp-k2j_x9qa", ".scene.old-4242"):  # 0.2.0's names: with a manifest
        (out / stray / "sub").mkdir(parents=True)
        (out / stray / "sub" / "f.txt").write_text("stranded\n")
        (out / stray / "manifest.json").write_text(manifest)
    (out / ".other.tmp-0123456789abcdef" / "sub").mkdir(parents=True)  # ours: killed mid-write
    (out / "gone").mkdir()
    (out / "gone" / "keep.txt").write_text("the old set\n")
    os.rename(out / "gone", out / ".gone.old-00ff00ff00ff00ff")
    (out / ".not-ours").mkdir()  # hidden directories of other patterns are left alone,
    (out / ".vim.old-1").mkdir()  # and so is one with 0.2.0's pattern but no manifest
    messages = []
    assert build(scene, out, log=messages.append) == {"scene": "up to date"}
    assert any("removed 4 leftover" in m for m in messages)
    assert sorted(os.listdir(out)) == [".not-ours", pio.LOCK_NAME, ".vim.old-1", "gone", "scene"]
    assert (out / "gone" / "keep.txt").read_text() == "the old set\n"


KILLER = textwrap.dedent("""
    # pendulab build with a product "fixture" whose files say which run made them
    # (argv[2]), SIGKILLed at mutating call argv[1] of pendulab.io (-1: never)
    import os, signal, sys, types
    from pendulab import io as pio, pipeline
    from pendulab.cli import main
    at, label = int(sys.argv[1]), sys.argv[2]
    product = types.ModuleType("fixture_product")
    product.OPTIONS, product.SYSTEMS = {{}}, ("kapitza",)
    product.produce = lambda ctx, options: {{
        f"{{k}}.txt": f"{{label}} {{k}}\\n" * (50 if label == "old" else 80) for k in "abcd"}}
    sys.modules["fixture_product"] = product
    pipeline.PRODUCTS["fixture"] = "fixture_product"
    real_exchange = pio._rename_exchange
    class Faulty:
        n = 0
        def __getattr__(self, name):
            real = getattr(os, name)
            if name not in {mutating!r}:
                return real
            def call(*a, **k):
                self.tick(name)
                return real(*a, **k)
            return call
        def tick(self, name):
            if Faulty.n == at:
                os.kill(os.getpid(), signal.SIGKILL)
            Faulty.n += 1
            print(name, file=sys.stderr)
    fake = Faulty()
    def exchange(a, b):
        fake.tick("exchange")
        return real_exchange(a, b)
    pio.os, pio._rename_exchange = fake, exchange
    sys.exit(main(sys.argv[3:]))
""").format(mutating=set(MUTATING))


def _cli_build(at, label, scene, out):
    return subprocess.run([sys.executable, "-c", KILLER, str(at), label, "build", str(scene),
                           "--force", "--out", str(out)], capture_output=True, text=True)


def _labels(directory):
    """The run ("old" | "new") that made every file in ``directory``; fails on a mixture."""
    got = _contents(directory)
    manifest = json.loads(got.pop("manifest.json"))
    assert manifest["files"] == {n: hashlib.sha256(t.encode()).hexdigest() for n, t in got.items()}
    assert sorted(got) == ["a.txt", "b.txt", "c.txt", "d.txt"]
    (label,) = {t.split()[0] for t in got.values()}
    return label


@pytest.mark.slow
def test_a_real_build_killed_while_publishing(tmp_path):
    """`pendulab build` (a process of its own) SIGKILLed at every third file-system call of
    its publish and at the calls around the exchange (the forked test above takes every
    call): the scene's directory holds the complete old or new set with matching manifest
    hashes; the leftovers are removed under the lock, and a last build leaves none."""
    _needs_exchange(tmp_path)
    scene = tmp_path / "scene.toml"
    scene.write_text('system = "kapitza"\n[products.fixture]\n')
    out = tmp_path / "out"
    assert _cli_build(-1, "old", scene, out).returncode == 0
    res = _cli_build(-1, "new", scene, out)
    assert res.returncode == 0 and _labels(out / "scene") == "new"
    calls = res.stderr.split()
    swap = calls.index("exchange")
    seen = set()
    for k in sorted(set(range(0, len(calls), 3)) | {swap - 1, swap, swap + 1}):
        before = _labels(out / "scene")
        label = "old" if before == "new" else "new"
        res = _cli_build(k, label, scene, out)
        assert res.returncode == -signal.SIGKILL, (k, calls[k], res.stderr)
        got = _labels(out / "scene")
        seen.add("before" if got == before else "after")
        if calls.index("mkdir") < k:
            assert pio.leftovers(out), (k, calls[k])
        with pio.publish_lock(out):
            pio.clean_leftovers(out)
        assert sorted(os.listdir(out)) == [pio.LOCK_NAME, "scene"]
    assert seen == {"before", "after"}
    assert _cli_build(-1, "old", scene, out).returncode == 0
    assert _labels(out / "scene") == "old" and sorted(os.listdir(out)) == [pio.LOCK_NAME, "scene"]


def test_without_syncfs_every_file_and_the_directory_are_fsynced(tmp_path, monkeypatch):
    """Where syncfs is missing (not Linux), each new file and the new directory get an
    fsync before the swap; a failing fsync of a file keeps the old set (one of the
    directory is ignored: some file systems cannot fsync a directory)."""
    monkeypatch.setattr(pio, "_has_syncfs", lambda: False)
    log = _call_log(tmp_path, monkeypatch)
    before_swap = log[:log.index("exchange")]
    assert before_swap.count("fsync") == len(NEW) + 1
    outcomes = []
    for k, name in enumerate(before_swap):
        if name != "fsync":
            continue
        root, directory = _fresh(tmp_path / f"k{k}")
        with monkeypatch.context() as m:
            _install(m, FaultyOS(k, _raise_eio))
            try:
                pio.write_tree(directory, NEW)
                outcomes.append("published")
            except OSError as exc:
                assert "injected" in str(exc)
                outcomes.append("refused")
        assert _which_set(directory) == ("old" if outcomes[-1] == "refused" else "new")
        assert _clean_listing(root)
    assert outcomes == ["refused"] * len(NEW) + ["published"]
