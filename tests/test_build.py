"""Scenes, the lazy pipeline, atomic and reproducible builds, and the CLI."""

import filecmp
import json
import os
import subprocess
import sys
import types
from pathlib import Path

import pytest

from pendulab import pipeline
from pendulab.build import build
from pendulab.cli import COMMANDS, main
from pendulab.errors import InputError, SceneError
from pendulab.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "derivations"


def _write(tmp_path, text, name="scene.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


GOOD = """
system = "kapitza"
[parameters]
body = "point"
[products.equations]
"""


# -- bad input ----------------------------------------------------------------

@pytest.mark.parametrize("text, key, fragment", [
    ('system = "kapitza"\ncolour = 1\n[products.equations]\n', "colour", "unknown key"),
    ('system = "sled"\n[products.equations]\n', "system", "must be one of"),
    ('[products.equations]\n', "system", "missing"),
    ('system = "kapitza"\n', "products", "missing"),
    ('system = "kapitza"\n[products.nonsense]\n', "products.nonsense", "unknown product"),
    ('system = "kapitza"\n[parameters]\nbody = 3\n[products.equations]\n', "parameters.body", "must be one of"),
    ('system = "kapitza"\n[parameters]\ndrive = "a*cos(omega*t"\n[products.equations]\n',
     "parameters.drive", "cannot parse"),
    ('system = "kapitza"\n[parameters]\ndrive = "__import__(\'os\').system(\'true\')"\n[products.equations]\n',
     "parameters.drive", "not allowed"),
    ('system = "kapitza"\n[parameters]\nbody = "explicit"\ninertia = "-2"\n[products.equations]\n',
     "parameters.inertia", "must be positive"),
    ('system = "variable-length"\n[parameters]\nlength = "-1"\n[products.equations]\n',
     "parameters.length", "must be positive"),
    ('system = "variable-length"\n[parameters]\nmass = "0"\n[products.equations]\n',
     "parameters.mass", "must be positive"),
    ('system = "variable-length"\n[parameters]\nmass = "m*cos(t)"\n[products.equations]\n',
     "parameters.mass", "must be a constant"),
    ('system = "kapitza"\n[parameters]\ndrive = "a*Abs(cos(omega*t))"\n[products.equations]\n',
     "parameters.drive", "twice differentiable"),
    ('system = "kapitza"\n[parameters]\ndrive = "a*cos(omega*t)*theta"\n[products.equations]\n',
     "parameters.drive", "write theta(t)"),
    ('system = "kapitza"\n[parameters]\ndrive = "t**(10**10)"\n[products.equations]\n',
     "parameters.drive", "too large"),
    ('system = "kapitza"\n[parameters]\ndrive = "((10**1000)**1000)**1000"\n[products.equations]\n',
     "parameters.drive", "too large"),
    ('system = "kapitza"\n[parameters]\ndrive = "Derivative(a*cos(omega*t), (t, 1000000))"\n'
     '[products.equations]\n', "parameters.drive", "too high"),
    ('system = "kapitza"\n[parameters]\nbody = "explicit"\ninertia = "sqrt(-1)"\n[products.equations]\n',
     "parameters.inertia", "imaginary unit"),
    ('system = "variable-length"\n[parameters]\nbody = "rod"\n[products.equations]\n',
     "parameters.body", "unknown parameter"),
    ('system = "kapitza"\n[products.equations]\nfoo = 1\n', "products.equations.foo", "unknown option"),
    ('system = "kapitza"\nname = "../escape"\n[products.equations]\n', "name", "must be"),
    ('system = [1, 2]\n[products.equations]\n', "system", "must be one of"),
    ('system = "kapitza"\n[parameters]\nangle = "left"\n[products.equations]\n', "parameters.angle", "must be one of"),
    ('system = "kapitza\n', None, "not valid TOML"),
])
def test_bad_scenes_name_file_and_key(tmp_path, text, key, fragment):
    path = _write(tmp_path, text)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    msg = str(info.value)
    assert str(path) in msg and fragment in msg
    if key:
        assert f": {key}:" in msg


def test_all_problems_are_reported_at_once(tmp_path):
    path = _write(tmp_path, 'system = "kapitza"\nfoo = 1\nbar = 2\n[parameters]\nangle = "x"\n'
                            '[products.equations]\n')
    with pytest.raises(SceneError) as info:
        load_scene(path)
    lines = str(info.value).splitlines()
    assert len(lines) == 3 and all(line.startswith(str(path)) for line in lines)


def test_missing_product_option_is_named(tmp_path, monkeypatch):
    """A product whose required option (default None) is absent is refused before any work."""
    fake = types.ModuleType("pendulab_fake_product")
    fake.OPTIONS = {"theta0": (float, None, "needed")}
    fake.produce = lambda ctx, options: {"x.txt": "x\n"}
    monkeypatch.setitem(sys.modules, "pendulab_fake_product", fake)
    monkeypatch.setitem(pipeline.PRODUCTS, "fake", "pendulab_fake_product")
    path = _write(tmp_path, 'system = "kapitza"\n[products.fake]\n')
    with pytest.raises(SceneError, match="products.fake.theta0: missing"):
        load_scene(path)
    path = _write(tmp_path, 'system = "kapitza"\n[products.fake]\ntheta0 = "x"\n')
    with pytest.raises(SceneError, match="products.fake.theta0: must be a number"):
        load_scene(path)


def test_cli_bad_scene_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys):
    path = _write(tmp_path, 'system = "kapitza"\n[parameters]\ndrive = "a.b"\n[products.equations]\n')
    out = tmp_path / "out"
    assert main(["build", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "parameters.drive" in err[0] and str(path) in err[0]
    assert not out.exists()


def test_cli_bad_derive_argument(capsys):
    assert main(["derive", "kapitza", "--drive", "os.system('x')"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("pendulab: error:") and "\n" not in err


def test_argparse_errors_exit_2():
    with pytest.raises(SystemExit) as info:
        main(["derive", "kapitza", "--body", "stone"])
    assert info.value.code == 2


# -- laziness -----------------------------------------------------------------

def test_unrequested_stages_never_run(tmp_path):
    """An equations-only scene runs system/equations/canonical and imports no analysis module."""
    path = _write(tmp_path, GOOD)
    code = (
        "import sys, json\n"
        "from pendulab.build import build\n"
        f"build({str(path)!r}, out_root={str(tmp_path / 'out')!r}, log=lambda m: None)\n"
        "mods = [m for m in sys.modules if m.startswith('pendulab.analyses')]\n"
        "print(json.dumps(mods))\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(res.stdout.strip().splitlines()[-1]) == []


def test_context_runs_only_what_is_asked(tmp_path):
    scene = load_scene(_write(tmp_path, GOOD))
    ctx = pipeline.Context(scene)
    ctx.get("equations")
    assert ctx.ran == ["system", "equations"]
    files, ctx = pipeline.run_products(scene)
    assert "closed_form" not in ctx.ran and set(files) == {"equations.json", "equations.tex"}


# -- atomicity, skipping, reproducibility --------------------------------------

def test_skip_when_unchanged_and_force(tmp_path):
    path = _write(tmp_path, GOOD)
    out = tmp_path / "out"
    assert build(path, out, log=lambda m: None) == {"scene": "built"}
    assert build(path, out, log=lambda m: None) == {"scene": "up to date"}
    assert build(path, out, force=True, log=lambda m: None) == {"scene": "built"}
    # a hand edit of an output is noticed (its hash no longer matches)
    (out / "scene" / "equations.json").write_text("{}\n")
    assert build(path, out, log=lambda m: None) == {"scene": "built"}
    # a changed scene is rebuilt
    path.write_text(GOOD.replace("point", "rod"))
    assert build(path, out, log=lambda m: None) == {"scene": "built"}


def test_failed_build_leaves_previous_outputs_intact(tmp_path, monkeypatch):
    path = _write(tmp_path, GOOD)
    out = tmp_path / "out"
    build(path, out, log=lambda m: None)
    before = {p.name: p.read_bytes() for p in (out / "scene").iterdir()}
    from pendulab.products import equations

    def broken(ctx, options):
        raise RuntimeError("disk on fire")
    monkeypatch.setattr(equations, "produce", broken)
    with pytest.raises(RuntimeError):
        build(path, out, force=True, log=lambda m: None)
    after = {p.name: p.read_bytes() for p in (out / "scene").iterdir()}
    assert before == after
    # no temporary directory left behind (the lock file stays: see pendulab.io.publish_lock)
    assert sorted(os.listdir(out)) == [".pendulab.lock", "scene"]


def test_error_in_a_product_names_file_and_product_and_writes_no_scene(tmp_path, monkeypatch, capsys):
    """Two scenes, the second fails inside its product: one line naming that file and
    product, exit 2, and the first scene's outputs are not written either."""
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    _write(scenes, GOOD, "a.toml")
    _write(scenes, 'system = "variable-length"\n[products.equations]\n', "b.toml")
    from pendulab.errors import InputError
    from pendulab.products import equations
    real = equations.produce

    def fails_for_b(ctx, options):
        if ctx.scene.name == "b":
            raise InputError("cannot do this one")
        return real(ctx, options)
    monkeypatch.setattr(equations, "produce", fails_for_b)
    out = tmp_path / "out"
    assert main(["build", str(scenes), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert str(scenes / "b.toml") in err[0] and "products.equations: cannot do this one" in err[0]
    assert not out.exists()


def test_unwritable_output_is_a_one_line_error(tmp_path, capsys):
    path = _write(tmp_path, GOOD)
    blocker = tmp_path / "blocker"
    blocker.write_text("a file where the output directory should go\n")
    assert main(["build", str(path), "--out", str(blocker)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0] == f"pendulab: error: --out {blocker} exists and is not a directory"
    assert blocker.read_text().startswith("a file")


def test_generated_is_reproducible_byte_for_byte(tmp_path):
    """`pendulab build derivations/` on the committed scenes gives the committed generated/."""
    out = tmp_path / "generated"
    build(SCENES, out, force=True, log=lambda m: None)
    committed = ROOT / "generated"
    names = sorted(p.name for p in committed.iterdir() if not p.name.startswith("."))
    assert names == sorted(p.name for p in out.iterdir() if not p.name.startswith("."))
    for name in names:
        cmp = filecmp.dircmp(committed / name, out / name)
        assert not cmp.left_only and not cmp.right_only, name
        for f in cmp.common_files:
            assert (committed / name / f).read_bytes() == (out / name / f).read_bytes(), f"{name}/{f}"


def test_every_committed_scene_is_built():
    scenes = {load_scene(p).name for p in SCENES.glob("*.toml")}
    built = {p.name for p in (ROOT / "generated").iterdir() if p.is_dir()}
    assert scenes == built


# -- CLI ------------------------------------------------------------------------

def test_every_command_is_installed():
    from pendulab.cli import available_commands
    assert available_commands() == list(COMMANDS)


@pytest.mark.parametrize("argv", [[], ["derive"], ["derive", "kapitza"], ["derive", "variable-length"],
                                  ["build"]])
def test_help_on_each_command(argv, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv + ["--help"])
    assert info.value.code == 0
    assert "usage: pendulab" in capsys.readouterr().out


def test_derive_json_keys(capsys):
    assert main(["derive", "kapitza", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"lagrangian", "eom", "linear", "canonical"} <= set(doc)
    assert {"theta0", "theta1"} <= set(doc["canonical"])
    assert main(["derive", "variable-length", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"lagrangian", "eom", "linear", "canonical", "solution"} <= set(doc)


def test_derive_latex_is_an_align_block(capsys):
    assert main(["derive", "kapitza", "--body", "point", "--latex"]) == 0
    out = capsys.readouterr().out
    assert "\\begin{align*}" in out and out.rstrip().endswith("\\end{align*}")


def test_console_script_runs():
    res = subprocess.run([sys.executable, "-m", "pendulab", "derive", "kapitza", "--json"],
                         capture_output=True, text=True)
    assert res.returncode == 0 and json.loads(res.stdout)["canonical"]["kind"] == "mathieu"


# -- right errors, early -----------------------------------------

def _no_work(monkeypatch):
    """Make reading or computing a scene fail the test: the check must come first."""
    import pendulab.build as pb

    def forbidden(*args, **kwargs):
        raise AssertionError("a scene was read or computed before --out was checked")
    monkeypatch.setattr(pb, "load_scene", forbidden)
    monkeypatch.setattr(pipeline, "run_products", forbidden)


@pytest.mark.parametrize("out, message", [
    ("README.md", "--out README.md exists and is not a directory"),
    ("README.md/sub", "--out README.md/sub: README.md is not a directory, so it cannot be created"),
    ("", "--out is empty: name a directory (the default is 'generated')"),
    ("   ", "--out is empty: name a directory (the default is 'generated')"),
])
def test_bad_out_is_refused_before_any_work(tmp_path, monkeypatch, capsys, out, message):
    (tmp_path / "README.md").write_text("# mine\n")
    monkeypatch.chdir(tmp_path)
    _no_work(monkeypatch)
    before = sorted(os.listdir(tmp_path))
    assert main(["build", str(SCENES), "--out", out]) == 2
    assert capsys.readouterr().err == f"pendulab: error: {message}\n"
    assert sorted(os.listdir(tmp_path)) == before  # nothing written, not even into the cwd
    assert (tmp_path / "README.md").read_text() == "# mine\n"


def test_bad_out_through_the_api_too(tmp_path, monkeypatch):
    from pendulab.errors import InputError
    _no_work(monkeypatch)
    with pytest.raises(InputError, match="output directory is empty"):
        build(SCENES, "")
    (tmp_path / "f").write_text("")
    with pytest.raises(InputError, match="exists and is not a directory"):
        build(SCENES, tmp_path / "f")


def test_a_new_nested_out_is_created(tmp_path):
    path = _write(tmp_path, GOOD)
    assert build(path, tmp_path / "a" / "b", log=lambda m: None) == {"scene": "built"}
    assert (tmp_path / "a" / "b" / "scene" / "manifest.json").exists()


def test_manifest_records_the_scene_file_without_machine_paths(tmp_path, monkeypatch):
    """As given relative, as given absolute, from another working directory: the same record."""
    scenes = tmp_path / "lessons"
    scenes.mkdir()
    _write(scenes, GOOD, "pivot.toml")
    records = set()
    for cwd, arg in ((tmp_path, "lessons/pivot.toml"), (scenes, "pivot.toml"),
                     (ROOT, str(scenes / "pivot.toml"))):
        monkeypatch.chdir(cwd)
        build(arg, tmp_path / "out", force=True, log=lambda m: None)
        text = (tmp_path / "out" / "pivot" / "manifest.json").read_text()
        records.add(json.loads(text)["source"])
        assert str(tmp_path) not in text
    assert records == {"lessons/pivot.toml"}
    for name in ("kapitza-point", "kapitza-rod", "variable-length"):
        manifest = json.loads((ROOT / "generated" / name / "manifest.json").read_text())
        assert manifest["source"] == f"derivations/{name}.toml"


def test_a_scene_of_the_same_name_from_another_file_is_refused_unless_replace(tmp_path, capsys):
    one, two = tmp_path / "one", tmp_path / "two"
    one.mkdir()
    two.mkdir()
    (one / "a.toml").write_text('name = "pivot"\n' + GOOD)
    (two / "b.toml").write_text('name = "pivot"\n' + GOOD.replace("point", "rod"))
    out = tmp_path / "out"
    assert main(["build", str(one / "a.toml"), "--out", str(out)]) == 0
    before = {p.name: p.read_bytes() for p in (out / "pivot").iterdir()}
    assert main(["build", str(two / "b.toml"), "--out", str(out), "--force"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [f"pendulab: error: {two / 'b.toml'}: name: {out / 'pivot'} holds the outputs of "
                   "another scene file, recorded as one/a.toml in its manifest.json; rename this "
                   "scene or give --replace to replace them"]
    assert {p.name: p.read_bytes() for p in (out / "pivot").iterdir()} == before
    assert main(["build", str(two / "b.toml"), "--out", str(out), "--replace"]) == 0
    manifest = json.loads((out / "pivot" / "manifest.json").read_text())
    assert manifest["source"] == "two/b.toml"
    assert {p.name: p.read_bytes() for p in (out / "pivot").iterdir()} != before
    # the same content from another file is not "up to date": the record must change
    (one / "a.toml").write_text((two / "b.toml").read_text())
    assert build(one / "a.toml", out, replace=True, log=lambda m: None) == {"pivot": "built"}
    assert json.loads((out / "pivot" / "manifest.json").read_text())["source"] == "one/a.toml"


def test_a_directory_not_written_by_build_is_refused(tmp_path):
    out = tmp_path / "out"
    (out / "scene").mkdir(parents=True)
    (out / "scene" / "notes.txt").write_text("my notes\n")
    path = _write(tmp_path, GOOD)
    with pytest.raises(SceneError, match="holds files that pendulab build did not write"):
        build(path, out, log=lambda m: None)
    assert (out / "scene" / "notes.txt").read_text() == "my notes\n"
    (out / "scene" / "notes.txt").unlink()  # an empty directory is taken
    assert build(path, out, log=lambda m: None) == {"scene": "built"}


def test_the_input_hash_covers_pendulabs_version(tmp_path, monkeypatch):
    """Outputs made by another version are rebuilt, not kept as up to date."""
    import pendulab
    import pendulab.build as pb
    path = _write(tmp_path, GOOD)
    out = tmp_path / "out"
    assert build(path, out, log=lambda m: None) == {"scene": "built"}
    scene = load_scene(path)
    digest = pb.input_hash(scene)
    monkeypatch.setattr(pb, "__version__", "99.0.0")
    monkeypatch.setattr(pendulab, "__version__", "99.0.0")
    assert pb.input_hash(scene) != digest
    assert build(path, out, log=lambda m: None) == {"scene": "built"}
    manifest = json.loads((out / "scene" / "manifest.json").read_text())
    assert manifest["generator"] == "pendulab 99.0.0" and manifest["input_sha256"] != digest
    assert build(path, out, log=lambda m: None) == {"scene": "up to date"}


def test_two_builds_at_once_both_succeed(tmp_path):
    """Two `pendulab build --force` processes into one root at the same time: exit 0 both,
    the outputs complete, no leftover."""
    path = _write(tmp_path, GOOD)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "pendulab", "build", str(path), "--force", "--out", str(out)]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for _ in range(2)]
    results = [p.communicate() + (p.returncode,) for p in procs]
    assert [r[2] for r in results] == [0, 0], results
    assert sorted(os.listdir(out)) == [".pendulab.lock", "scene"]
    assert build(path, out, log=lambda m: None) == {"scene": "up to date"}


# -- each derivation once per build --------------------------------

def test_the_body_does_not_enter_the_driven_pivots_equations():
    """Why one derivation serves every body (pendulab.equations.derive): derived afresh for
    the rod, the point mass and the generic body I, the records agree but for the system."""
    import dataclasses
    from pendulab import equations
    from pendulab.systems import DrivenPivot
    records = [equations._derive_driven_pivot(DrivenPivot(body=b)) for b in ("rod", "point", "explicit")]
    fields = [f.name for f in dataclasses.fields(records[0]) if f.name != "system"]
    for other in records[1:]:
        for name in fields:
            assert getattr(other, name) == getattr(records[0], name), name
    shared = [equations.derive(DrivenPivot(body=b)) for b in ("rod", "point")]
    assert [r.system.body for r in shared] == ["rod", "point"]


def test_a_build_derives_each_equation_once(tmp_path, monkeypatch):
    """Two kapitza scenes (point, rod) with equations and the stability comparison, which
    needs eqs. 12 and 19 (phelps_hunter, averaging): the driven pivot's Euler-Lagrange
    equations are derived once, its Mathieu form is formed once (the stage, phelps_hunter and
    stability.body_map share pipeline.canonical_form), and no closed form is derived again
    per row of the table."""
    from pendulab import canonical, equations
    from pendulab.analyses import averaging, phelps_hunter, stability
    for f in (phelps_hunter._mathieu_parameters, phelps_hunter._small_parameter_exponent,
              phelps_hunter.interval_eq12, averaging._lagrangian_torques, averaging._averaged,
              stability._formula, stability._series_theta1, stability.body_map):
        f.cache_clear()
    monkeypatch.setattr(equations, "_DERIVED", {})
    monkeypatch.setattr(pipeline, "_CANONICAL", {})
    counts = {"derive": 0, "periodic_form": 0, "series": 0}
    # eq. 11 per form (Mathieu plane, physical) and depth: calls of the cached function,
    # cache hits included, so that 1 per argument tuple proves one derivation of each
    eq11 = {}

    def counting(name, real):
        def wrapper(*args, **kwargs):
            counts[name] += 1
            return real(*args, **kwargs)
        return wrapper

    def counting_by_args(real):
        def wrapper(*args):
            eq11[args] = eq11.get(args, 0) + 1
            return real(*args)
        return wrapper
    monkeypatch.setattr(equations, "_derive_driven_pivot",
                        counting("derive", equations._derive_driven_pivot))
    monkeypatch.setattr(canonical, "periodic_form", counting("periodic_form", canonical.periodic_form))
    monkeypatch.setattr(phelps_hunter, "_small_parameter_exponent",
                        counting_by_args(phelps_hunter._small_parameter_exponent))
    import pendulab.analyses.series as series
    monkeypatch.setattr(series, "stability_interval_series",
                        counting("series", series.stability_interval_series))
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    table = ('[products.stability]\npoints = 5\nmax_ratio = "1/2"\n'
             'methods = ["eq12", "eq19", "eq19-corrected", "eq28"]\nfigure = false\n')
    _write(scenes, 'system = "kapitza"\n[parameters]\nbody = "point"\n[products.equations]\n' + table,
           "point.toml")
    _write(scenes, 'system = "kapitza"\n[parameters]\nbody = "rod"\n[products.equations]\n' + table,
           "rod.toml")
    # jobs=1: the counters live in this process (with jobs > 1 the scenes run in forked workers)
    assert build(scenes, tmp_path / "out", log=lambda m: None, jobs=1) == {"point": "built", "rod": "built"}
    # eq28 rows: the same 5 values of omega0/omega for both bodies, computed once each
    assert counts == {"derive": 1, "periodic_form": 1, "series": 5}
    # eq. 12 needs the physical eq. 11, which is formed from the Mathieu-plane one: each
    # derived once (mathieu, depth) -> calls
    assert eq11 == {(False, 1): 1, (True, 1): 1}


def test_shared_series_limits_are_bit_for_bit_the_direct_ones():
    """The comparison's series rows, shared across bodies, equal the direct
    stability_interval_series(order, ratio, inertia_ratio) exactly."""
    from pendulab.analyses import series, stability
    for order in (2, 6):
        for ratio in (0.0, 0.15, 0.35):
            for r in (1.0, 4 / 3, 1.7):
                assert stability.limits(ratio, r, f"series:{order}") == \
                    series.stability_interval_series(order, ratio, r)


# -- scenes side by side (pendulab.build.compute_scenes) -------------------------------

TWO = {"a.toml": GOOD, "b.toml": 'system = "variable-length"\n[products.equations]\n',
       "c.toml": GOOD.replace("point", "rod")}


def _scenes(tmp_path):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name, text in TWO.items():
        _write(scenes, text, name)
    return scenes


def test_scenes_in_worker_processes_give_the_serial_bytes(tmp_path):
    scenes = _scenes(tmp_path)
    trees = {}
    for jobs in (1, 2, 3):
        out = tmp_path / f"out{jobs}"
        assert build(scenes, out, log=lambda m: None, jobs=jobs) == {"a": "built", "b": "built", "c": "built"}
        trees[jobs] = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert trees[1] == trees[2] == trees[3]
    assert len(trees[1]) == 3 * 3 + 1  # equations.json, .tex, manifest.json per scene; the lock file


def _errors_serial_and_parallel(scenes, out):
    """The SceneError messages of building ``scenes`` into ``out`` with jobs 1 and 2."""
    messages = []
    for jobs in (1, 2):
        with pytest.raises(SceneError) as info:
            build(scenes, out, log=lambda m: None, jobs=jobs)
        messages.append(str(info.value))
    return messages


def test_an_error_in_a_worker_is_the_serial_one_line_error(tmp_path, monkeypatch):
    """The failing scene is computed again in the parent: the same SceneError as a serial build
    (file and product named), the first failing scene in order, nothing written."""
    scenes = _scenes(tmp_path)
    from pendulab.errors import InputError
    from pendulab.products import equations
    real = equations.produce

    def fails(ctx, options):
        if ctx.scene.name in ("b", "c"):
            raise InputError(f"cannot do {ctx.scene.name}")
        return real(ctx, options)
    monkeypatch.setattr(equations, "produce", fails)
    messages = _errors_serial_and_parallel(scenes, tmp_path / "out")
    assert messages[0] == messages[1]
    assert messages[0] == f"{scenes / 'b.toml'}: products.equations: cannot do b"
    assert not (tmp_path / "out").exists()


def test_a_worker_that_dies_is_replaced_by_the_parent(tmp_path, monkeypatch):
    """A worker killed in the middle of a scene (os._exit: as the out-of-memory killer does)
    does not fail the build: the parent computes that scene itself."""
    scenes = _scenes(tmp_path)
    from pendulab.products import equations
    real = equations.produce
    parent = os.getpid()

    def dies_in_a_worker(ctx, options):
        if ctx.scene.name == "b" and os.getpid() != parent:
            os._exit(9)
        return real(ctx, options)
    monkeypatch.setattr(equations, "produce", dies_in_a_worker)
    out = tmp_path / "out"
    assert build(scenes, out, log=lambda m: None, jobs=2) == {"a": "built", "b": "built", "c": "built"}
    assert (out / "b" / "equations.json").exists()


def test_a_parallel_build_leaves_the_callers_garbage_collector_as_it_was(tmp_path):
    """compute_scenes freezes the heap it shares with the workers it forks; an API caller's
    process gets it back unfrozen, with its own thresholds."""
    import gc
    before = gc.get_threshold()
    scenes = _scenes(tmp_path)
    assert build(scenes, tmp_path / "out", log=lambda m: None, jobs=2) == \
        {"a": "built", "b": "built", "c": "built"}
    assert gc.get_freeze_count() == 0
    assert gc.get_threshold() == before
    # a caller that froze objects of its own keeps them frozen
    gc.freeze()
    try:
        mine = gc.get_freeze_count()
        assert build(scenes, tmp_path / "out2", log=lambda m: None, jobs=2) == \
            {"a": "built", "b": "built", "c": "built"}
        assert 0 < gc.get_freeze_count() <= mine  # still frozen, and nothing more frozen
    finally:
        gc.unfreeze()


def test_the_heap_is_unfrozen_when_the_workers_cannot_start(tmp_path, monkeypatch):
    import gc

    from pendulab import build as build_module

    def no_shared_memory(*args):
        raise OSError("shared memory unavailable")
    monkeypatch.setattr(build_module, "_Shared", no_shared_memory)
    with pytest.raises(OSError):
        build(_scenes(tmp_path), tmp_path / "out", log=lambda m: None, jobs=2)
    assert gc.get_freeze_count() == 0


MANY = {"m.toml": 'system = "kapitza"\n[parameters]\nbody = "rod"\n[products.equations]\n'
                   '[products.kernels]\n[products.series]\norder = 4\n'
                   '[products.stability]\npoints = 3\nmax_ratio = "1/2"\nmethods = ["eq28"]\n'
                   'figure = false\n',
        "v.toml": 'system = "variable-length"\n[products.equations]\n[products.kernels]\n'}


def test_products_of_one_scene_in_several_processes_give_the_serial_bytes(tmp_path):
    """Products, not scenes, are shared out: one scene's products computed by two processes
    give the files and the stages of a serial build."""
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name, text in MANY.items():
        _write(scenes, text, name)
    trees, logs = {}, {}
    for jobs in (1, 2, 4):
        out = tmp_path / f"out{jobs}"
        lines = []
        assert build(scenes, out, log=lines.append, jobs=jobs) == {"m": "built", "v": "built"}
        trees[jobs] = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
        logs[jobs] = [line.replace(str(out), "OUT") for line in lines]
    assert trees[1] == trees[2] == trees[4]
    assert logs[1] == logs[2] == logs[4]
    assert any("stages: system, equations, canonical" in line for line in logs[1])


def test_two_products_writing_one_file_in_two_processes_is_the_serial_error(tmp_path, monkeypatch):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    _write(scenes, MANY["m.toml"], "m.toml")
    from pendulab.products import kernels
    monkeypatch.setattr(kernels, "produce", lambda ctx, options: {"series.json": "{}"})
    messages = _errors_serial_and_parallel(scenes, tmp_path / "out")
    assert messages[0] == messages[1]
    assert messages[0].endswith("product 'series' writes 'series.json', which another product writes")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("value", ["0", "-1", "two", "1.5", "65"])
def test_bad_jobs_is_a_one_line_error(tmp_path, monkeypatch, capsys, value):
    from pendulab.build import job_count
    monkeypatch.setenv("PENDULAB_JOBS", value)
    with pytest.raises(InputError) as info:
        job_count()
    assert str(info.value).startswith("PENDULAB_JOBS must be a whole number of processes")
    path = _write(tmp_path, GOOD)
    assert main(["build", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("pendulab: error: PENDULAB_JOBS must be")
    assert not (tmp_path / "out").exists()


def test_job_count_defaults_and_choices(monkeypatch):
    from pendulab.build import MAX_JOBS, job_count
    monkeypatch.delenv("PENDULAB_JOBS", raising=False)
    assert 1 <= job_count() <= MAX_JOBS
    assert job_count(3) == 3
    monkeypatch.setenv("PENDULAB_JOBS", "1")
    assert job_count() == 1
    assert job_count(2) == 2  # an explicit argument wins over the environment


@pytest.mark.parametrize("figure, preloaded", [("false", False), ("true", True)])
def test_heavy_imports_shared_by_scenes_are_made_before_the_workers_fork(tmp_path, figure, preloaded):
    """Two scenes whose stability product draws its figure: the parent imports matplotlib once
    (the workers inherit it); without figures it imports none."""
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    table = f'[products.stability]\npoints = 2\nmax_ratio = "1/2"\nmethods = ["eq28"]\nfigure = {figure}\n'
    for body in ("point", "rod"):
        _write(scenes, f'system = "kapitza"\n[parameters]\nbody = "{body}"\n' + table, f"{body}.toml")
    code = (
        "import sys\n"
        "from pendulab.build import build\n"
        f"build({str(scenes)!r}, out_root={str(tmp_path / 'out')!r}, log=lambda m: None, jobs=2)\n"
        "print('matplotlib.pyplot' in sys.modules)\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert res.stdout.strip().splitlines()[-1] == str(preloaded)
    assert (tmp_path / "out" / "rod" / "stability.json").exists()
    assert (tmp_path / "out" / "rod" / "stability.svg").exists() == preloaded


def test_tasks_are_each_taken_once_dearest_first_and_scenes_stay_in_one_process():
    """_Shared.take: every task is handed out exactly once; the dearest free task first, except
    that a process leaves a scene that only another process has worked on to that process
    while a task at least half as dear of another scene is free."""
    import multiprocessing as mp

    from pendulab.build import _Shared
    # (scene, product, part) in the build's order, dearest first
    tasks = [(0, "motion", None), (1, "experiments", "map:text"), (0, "bessel", None),
             (1, "experiments", "fig2"), (0, "equations", None), (2, "series", None)]
    weights = [10, 6, 4, 4, 0.5, 1]
    state = _Shared(mp.Array("b", len(tasks)), mp.Array("i", 3), mp.Value("b", 0), weights)
    assert state.take(tasks, 1) == 0          # process 1 takes motion (scene 0)
    assert state.take(tasks, 0) == 1          # process 0 the next: map:text (scene 1)
    assert state.take(tasks, 0) == 3          # bessel is scene 0's, process 1's: fig2 instead
    assert state.take(tasks, 1) == 2          # process 1 takes bessel itself
    assert state.take(tasks, 0) == 5          # equations is scene 0's; series (nobody's) is free
    # equations (lighter than SMALL) is left to process 1, which knows its scene: process 0 stops
    assert state.take(tasks, 0) is None
    assert state.take(tasks, 1) == 4
    assert state.take(tasks, 1) is None and state.take(tasks, 0) is None
    assert list(state.taken) == [1] * len(tasks)


def test_a_product_in_parts_in_two_processes_gives_the_serial_bytes(tmp_path):
    """The experiments product is computed in parts spread over the processes; the files and
    the log are those of a serial build."""
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    _write(scenes, 'system = "kapitza"\n[parameters]\nbody = "rod"\n[products.experiments]\n'
                   'grid = 4\nperiods = 10\nsteps_per_period = 20\nmaps = ["text", "caption"]\n'
                   'fig5_periods = 2\nfig2_periods = 2\nfigures = false\n', "x.toml")
    trees, logs = {}, {}
    for jobs in (1, 2):
        out = tmp_path / f"out{jobs}"
        lines = []
        assert build(scenes, out, log=lines.append, jobs=jobs) == {"x": "built"}
        trees[jobs] = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
        logs[jobs] = [line.replace(str(out), "OUT") for line in lines]
    assert trees[1] == trees[2] and logs[1] == logs[2]
    assert "x/experiments.json" in trees[1]
