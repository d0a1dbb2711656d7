"""Scene product "stability" and the `pendulab stability` command."""

import json
import sys

import pytest

from pendulab import load_expr
from pendulab.analyses import stability as st
from pendulab.cli import main
from pendulab.errors import InputError, SceneError
from pendulab.pipeline import Context
from pendulab.products import stability as product
from pendulab.scene import parse_scene

METHODS = ["exact", "eq12", "eq19", "eq19-corrected"]


def make_ctx(body="rod", **options):
    options.setdefault("methods", METHODS)
    options.setdefault("points", 6)
    params = {"body": body}
    if body == "explicit":
        params["inertia"] = options.pop("inertia")
    scene = parse_scene({"name": "stab", "system": "kapitza", "parameters": params,
                         "products": {"stability": options}}, path="scene.toml")
    return Context(scene), scene.products["stability"]


def test_json_and_tex_without_figure():
    ctx, options = make_ctx(figure=False)
    files = product.produce(ctx, options)
    assert sorted(files) == ["stability.json", "stability.tex"]
    doc = json.loads(files["stability.json"])
    assert doc["inertia_ratio"] == "4/3"
    assert doc["w0_over_w"] == [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]
    assert doc["methods"] == METHODS
    row = doc["limits"]["exact"][1]
    assert row["lower"] == pytest.approx(st.limits(0.2, 4 / 3, "exact")[0], rel=1e-9)
    assert doc["limits"]["eq19"][3]["upper"] is None
    # the closed forms round-trip and are the derived ones
    formulas = st.formulas()
    for method in ("eq12", "eq19", "eq19-corrected"):
        lower = load_expr(doc["formulas"][method]["lower"])
        names = {s.name for s in lower.free_symbols}
        assert names <= {"w0_over_w", "inertia_ratio"}
        derived = formulas[method][0]
        assert lower == derived  # same symbols, same assumptions (pendulab.symbols)
    tex = files["stability.tex"]
    assert tex.count("\\toprule") == tex.count("\\bottomrule") == 2  # lower and upper blocks
    assert tex.count("\\\\") == 2 * (2 + 6)  # per block: title, header and 6 rows
    assert "0.200 & " in tex and "---" in tex
    for k, method in enumerate(METHODS):  # every column letter is explained in the caption
        assert f"({chr(ord('a') + k)}) " in tex


def test_deterministic_text():
    ctx1, options = make_ctx(figure=False)
    ctx2, _ = make_ctx(figure=False)
    assert product.produce(ctx1, options) == product.produce(ctx2, options)


def test_figure_is_deterministic_svg():
    pytest.importorskip("matplotlib")
    ctx, options = make_ctx(points=5)
    svg1 = product.produce(ctx, options)["stability.svg"]
    ctx, options = make_ctx(points=5)
    svg2 = product.produce(ctx, options)["stability.svg"]
    assert svg1 == svg2
    assert svg1.lstrip().startswith("<?xml") and "<svg" in svg1
    assert "<dc:date>" not in svg1


def test_figure_without_matplotlib_is_a_clear_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    ctx, options = make_ctx(points=3)
    with pytest.raises(InputError, match="needs matplotlib"):
        product.produce(ctx, options)


def test_point_and_explicit_bodies():
    ctx, options = make_ctx(body="point", figure=False, points=3)
    doc = json.loads(product.produce(ctx, options)["stability.json"])
    assert doc["inertia_ratio"] == "1"
    ctx, options = make_ctx(body="explicit", inertia="m*l**2 + m*l**2/3", figure=False, points=3)
    doc = json.loads(product.produce(ctx, options)["stability.json"])
    assert doc["inertia_ratio"] == "4/3"


@pytest.mark.parametrize("overrides, fragment", [
    ({"methods": ["exact", "eq99"]}, "unknown method 'eq99'"),
    ({"points": 1}, "points.*must be an integer (between|from) 2"),
    ({"max_ratio": "abc"}, "max_ratio.*must be"),
    ({"body": "explicit", "inertia": "I"}, "needs a numeric I/\\(m l\\^2\\)"),
])
def test_bad_options_name_the_product(overrides, fragment):
    body = overrides.pop("body", "rod")
    # option values are refused when the scene is read (with its other problems), the
    # body when the product runs; either way the message names the scene and the product
    with pytest.raises(SceneError, match=fragment) as info:
        ctx, options = make_ctx(body=body, figure=False, **overrides)
        product.produce(ctx, options)
    assert "products.stability" in str(info.value)
    assert "scene.toml" in str(info.value)


# -- CLI ------------------------------------------------------------------------------

def test_cli_json(capsys):
    assert main(["stability", "--body", "point", "--ratio", "0.1", "--method", "eq12", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert set(record) == {"lower", "upper", "method", "ratio", "body", "inertia_ratio"}
    assert record["method"] == "eq12" and record["body"] == "point"
    assert record["lower"] == pytest.approx(2**0.5 * 0.1)


def test_cli_text_and_inertia_ratio(capsys):
    assert main(["stability", "--inertia-ratio", "1.5", "--ratio", "1/20", "--method", "eq19"]) == 0
    out = capsys.readouterr().out
    assert "upper: none" in out and "inertia_ratio: 1.5" in out and "ratio: 0.05" in out


def test_cli_default_is_exact_for_a_rod(capsys, scipy_limits):
    assert main(["stability", "--ratio", "0.1", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["method"] == "exact" and record["body"] == "rod"
    assert record["lower"] == pytest.approx(scipy_limits(0.1, 4 / 3)[0], rel=1e-10)


@pytest.mark.parametrize("argv, fragment", [
    (["--ratio", "-1"], "--ratio must be a number from 0 to 1000, got '-1'"),
    (["--ratio", "x"], "--ratio must be a number from 0 to 1000, got 'x'"),
    (["--inertia-ratio", "0.5", "--ratio", "0.1"],
     "--inertia-ratio must be a number from 1 to 1000, got '0.5'"),
    (["--ratio", "0.1", "--method", "eq13"], "--method: unknown method"),
])
def test_cli_bad_values_exit_2_one_line(argv, fragment, capsys):
    assert main(["stability", *argv]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0]


def test_cli_body_and_inertia_ratio_are_exclusive(capsys):
    with pytest.raises(SystemExit) as info:
        main(["stability", "--body", "rod", "--inertia-ratio", "2", "--ratio", "0.1"])
    assert info.value.code == 2
    assert "not allowed with" in capsys.readouterr().err
