"""One road from derivation to number: the products follow the scene's drive.

Three scenes differ only in the drive y0(t):

* "a*cos(omega*t)" - the source's drive (000 eq. 1): Mathieu's equation;
* "a*cos(omega*t)**2" = a/2 + (a/2) cos(2 omega t): the pivot moves with
  amplitude a/2 at frequency 2 omega (the constant a/2 does not accelerate
  it), so at (a/l, omega0/omega) it is the source's pendulum at
  (a/(2l), omega0/(2 omega)): its limits of a/l at omega0/omega = rho are
  twice the plain ones at rho/2.  This rescaling is physics, worked out here
  by hand, not read from the code;
* "a*cos(omega*t) + a*cos(2*omega*t)" - Hill's equation with two harmonics.

References: the Floquet verdict of the monodromy matrix integrated from each
scene's own linear equation (DOP853) on both sides of every limit (the
products use the characteristic values a_0, b_1 for Mathieu drives: a
different algorithm), and for the Hill drive Hill's determinant
(pendulab.analyses.hill_general) solved for |tr M| = 2 along a/l, against the
product's bisection on the monodromy verdict.
"""

import json
import math
from fractions import Fraction

import pytest
import sympy as sp

from pendulab import symbols as S
from pendulab.errors import SceneError
from pendulab.numerics.model import pivot_system
from pendulab.numerics.monodromy import floquet_verdict
from pendulab.pipeline import run_products
from pendulab.scene import parse_scene

PLAIN, SQUARED, HILL = "a*cos(omega*t)", "a*cos(omega*t)**2", "a*cos(omega*t) + a*cos(2*omega*t)"


def _scene(drive, products, values=None, name="road"):
    data = {"name": name, "system": "kapitza",
            "parameters": {"body": "rod", "drive": drive}, "products": products}
    if values is not None:
        data["values"] = values
    return parse_scene(data, f"{name}.toml")


def _build(drive, products, values=None):
    files, ctx = run_products(_scene(drive, products, values))
    return {k: (json.loads(v) if k.endswith(".json") else v) for k, v in files.items()}, ctx


METHODS = ["exact", "eq12", "integer-series:4"]
POINT = [["-0.002", "0.2"]]
# one build per drive (a derivation costs seconds): floquet and stability together
PRODUCTS = {
    PLAIN: {"floquet": {"ratios": ["0.025", "0.05", "0.1"], "dps": 20, "points": POINT},
            "stability": {"points": 3, "max_ratio": "1/5", "methods": METHODS, "figure": False}},
    SQUARED: {"floquet": {"ratios": ["0.05", "0.1"], "dps": 20, "points": POINT},
              "stability": {"points": 5, "max_ratio": "2/5", "methods": METHODS, "figure": False}},
}


@pytest.fixture(scope="module")
def built():
    return {d: _build(d, p) for d, p in PRODUCTS.items()}


@pytest.fixture(scope="module")
def hill_built():
    return _build(HILL, {"floquet": {"ratios": ["0.1"], "dps": 20, "points": POINT},
                         "stability": {"points": 3, "max_ratio": "1/5", "methods": ["exact"],
                                       "figure": False}})


def _limits(doc):
    return {e["ratio"]: (float(e["lower"]), float(e["upper"])) for e in doc["limits"]}


def test_the_canonical_stage_sees_three_drives(built, hill_built):
    kinds = {d: ctx.get("canonical") for d, (_, ctx) in built.items()}
    assert kinds[PLAIN].kind == kinds[SQUARED].kind == "mathieu"
    assert hill_built[1].get("canonical").kind == "hill"
    assert kinds[PLAIN].frequency == S.omega and kinds[SQUARED].frequency == 2 * S.omega


def _check_edges_by_monodromy(ctx, ratio, lower, upper, rel=1e-6):
    fos = pivot_system(ctx.get("equations"), ctx.get("canonical"))
    verdict = {}
    for name, x in (("below lower", lower * (1 - rel)), ("above lower", lower * (1 + rel)),
                    ("below upper", upper * (1 - rel)), ("above upper", upper * (1 + rel))):
        verdict[name] = floquet_verdict(fos, {"a_over_l": x, "w0_over_w": ratio}).stable
    assert verdict == {"below lower": False, "above lower": True,
                       "below upper": True, "above upper": False}


@pytest.mark.parametrize("drive", [PLAIN, SQUARED])
def test_mathieu_limits_are_where_the_monodromy_verdict_changes(built, drive):
    doc, ctx = built[drive][0]["floquet.json"], built[drive][1]
    for ratio, (lo, up) in _limits(doc).items():
        _check_edges_by_monodromy(ctx, float(ratio), lo, up)


def test_squared_cosine_limits_follow_from_the_physical_rescaling(built):
    plain = built[PLAIN][0]["floquet.json"]
    squared = built[SQUARED][0]["floquet.json"]
    half = {str(Fraction(r) * 2): v for r, v in
            ((e["ratio"], (e["lower"], e["upper"])) for e in plain["limits"])}
    for e in squared["limits"]:
        ratio = str(Fraction(e["ratio"]))
        lo, up = half[ratio]
        assert abs(float(e["lower"]) - 2 * float(lo)) < 1e-15
        assert abs(float(e["upper"]) - 2 * float(up)) < 1e-15
    # and the products really differ: not the plain limits again
    same = _limits(built[PLAIN][0]["floquet.json"])
    assert all(abs(_limits(squared)[r][1] - same[r][1]) > 0.5 for r in _limits(squared))
    assert squared["theta0"] == "-w0_over_w**2" and squared["theta1"] == "3*a_over_l/4"
    assert "theta0" not in built[PLAIN][0]["floquet.json"]  # the source's drive: unchanged file


def _hill_coefficients(ctx, al, w):
    from pendulab.analyses.hill_general import numeric_fourier
    eqs, form = ctx.get("equations"), ctx.get("canonical")
    sub = {S.a: S.a_over_l * S.l, S.omega0: S.w0_over_w * S.omega, S.I: eqs.system.inertia}
    fourier = {k: tuple(sp.sympify(c).subs(sub) for c in pair) for k, pair in form.fourier.items()}
    return numeric_fourier(fourier, {S.a_over_l: al, S.w0_over_w: w}), float(form.period)


def test_hill_limits_agree_with_hills_determinant(hill_built, built):
    from scipy.optimize import brentq

    from pendulab.analyses.hill_general import hill_trace

    files, ctx = hill_built
    doc = files["floquet.json"]
    assert doc["kind"] == "hill"
    (lo, up), = _limits(doc).values()

    def g(x):
        return abs(hill_trace(*_hill_coefficients(ctx, x, 0.1)).trace) - 2

    # brackets a tenth of the interval wide around each limit
    width = (up - lo) / 10
    lo_ref = brentq(g, lo - width, lo + width, xtol=1e-13)
    up_ref = brentq(g, up - width, up + width, xtol=1e-13)
    assert abs(lo - lo_ref) < 1e-8 and abs(up - up_ref) < 1e-8
    _check_edges_by_monodromy(ctx, 0.1, lo, up)
    plain = _limits(built[PLAIN][0]["floquet.json"])["0.1"]
    assert abs(plain[0] - lo) > 0.05 and abs(plain[1] - up) > 0.1
    stab = files["stability.json"]
    assert stab["kind"] == "hill"
    assert abs(stab["limits"]["exact"][1]["lower"] - lo) < 1e-9


def test_stability_product_follows_the_drive(built):
    plain = built[PLAIN][0]["stability.json"]
    squared = built[SQUARED][0]["stability.json"]
    # squared at rho = 0, 0.1, 0.2, 0.3, 0.4; plain at rho/2 = 0, 0.05, 0.1
    for m in METHODS:
        for i, k in ((0, 0), (1, 2), (2, 4)):
            for side in ("lower", "upper"):
                p, s = plain["limits"][m][i][side], squared["limits"][m][k][side]
                assert (p is None) == (s is None)
                if p is not None:
                    assert abs(s - 2 * p) <= 2e-9 * max(1, abs(s))
    assert squared["formulas"] == {} and squared["drive"] == SQUARED


def test_methods_that_do_not_apply_are_refused_in_one_line(built, hill_built):
    from pendulab.analyses.stability import scene_comparison, scene_map
    from pendulab.errors import InputError

    with pytest.raises(InputError, match=r"method 'eq19' is derived by averaging the drive "
                                         r"a\*cos\(omega\*t\)"):
        scene_comparison(scene_map(built[SQUARED][1]), [0.1], ["exact", "eq19"])
    with pytest.raises(InputError, match=r"method 'eq28' is derived for Mathieu's equation"):
        scene_comparison(scene_map(hill_built[1]), [0.1], ["exact", "eq28"])


def test_a_non_periodic_drive_is_refused_in_one_line():
    from pendulab.pipeline import Context, product_module

    drive = "a*cos(omega*t) + a*cos(sqrt(2)*omega*t)"
    scene = _scene(drive, {"floquet": {}, "stability": {"figure": False}})
    ctx = Context(scene)  # one derivation for both products
    for product in ("floquet", "stability"):
        with pytest.raises(Exception) as info:
            product_module(product).produce(ctx, scene.products[product])
        text = str(info.value)
        assert "\n" not in text and product in text and "linear equation" in text
        assert "products.stability" in text if product == "stability" else True


# The source's Fig. 2 pendulum (000 sec. 4): a rod 10 cm long (so l = 5 cm to the
# centre of mass), pivot amplitude 6 mm at 86 Hz, g = 9.81 m/s^2; the source
# states theta0 = -2e-3 and theta1 = 0.2.
FIG2 = {"l": 0.05, "a": "6/1000", "omega": "2*pi*86", "g": 9.81}


def test_fig2_numbers_give_the_sources_parameters():
    files, _ = _build(PLAIN, {"floquet": {"ratios": [], "dps": 20}}, values=FIG2)
    point = files["floquet.json"]["scene_point"]
    # physics, by hand: a uniform rod of length 2l about its end has I = (4/3) m l^2, so
    # omega0^2 = m g l/I = 3 g/(4 l); theta0 = -4 omega0^2/omega^2, theta1 = 2 a l m/I = 3a/(2l)
    omega = 2 * math.pi * 86
    theta0 = -3 * 9.81 / (0.05 * omega**2)
    theta1 = 3 * 0.006 / (2 * 0.05)
    assert abs(float(point["theta0"]) - theta0) < 1e-15 and abs(float(point["theta1"]) - theta1) < 1e-15
    assert round(float(point["theta0"]), 4) == -0.0020 and round(float(point["theta1"]), 1) == 0.2
    assert point["stable"] is True


def test_scene_values_are_validated_with_their_keys():
    bad = {"l": "nan", "zz": 3, "a": -1, "g": True, "m": "2*"}
    with pytest.raises(SceneError) as info:
        _scene(PLAIN, {"equations": {}}, values=bad)
    text = str(info.value)
    for key in ("values.l", "values.zz", "values.a", "values.g", "values.m"):
        assert key in text
    assert "not a symbol of this scene's system" in text


def test_the_source_map_is_derived_not_typed():
    from pendulab.analyses.stability import body_map
    m = body_map()
    # 000 eqs. 5-6 in the groups: theta0 = -4 (omega0/omega)^2, theta1 = 2 (a/l)/(I/(m l^2))
    assert sp.simplify(m.theta0 + 4 * S.w0_over_w**2) == 0
    assert sp.simplify(m.theta1 - 2 * S.a_over_l / S.inertia_ratio) == 0


def test_variable_length_values_name_its_own_symbols():
    data = {"system": "variable-length", "products": {"equations": {}},
            "values": {"L0": 1, "v0": "1/10", "g": 9.81}}
    scene = parse_scene(data, "vl.toml")
    assert scene.values == {"L0": 1, "v0": sp.Rational(1, 10), "g": sp.Rational(981, 100)}
    data["values"] = {"a": 1, "omega0": 2}
    with pytest.raises(SceneError, match=r"values\.a: not a symbol"):
        parse_scene(data, "vl.toml")
