"""Fixed-step RK4 (C kernel and NumPy), its statistics, its order, and the DOP853 reference.

The order test measures RK4's error against SciPy's DOP853 at rtol 1e-13 (an independent
method of order 8) and expects the ratio 2^4 = 16 on halving the step (classical RK4 is of
order 4; Hairer, Norsett & Wanner, Solving ODEs I, sec. II.1).
"""

import math
import multiprocessing

import numpy as np
import pytest

from pendulab.errors import InputError
from pendulab.numerics import codegen, integrate
from pendulab.numerics.integrate import ensemble_rk4, reference_trajectory, rk4_error, rk4_trajectory

from test_codegen import system  # noqa: E402  (the same systems, built once)


@pytest.fixture(autouse=True)
def _kernel_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("PENDULAB_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "kcache"))
    monkeypatch.delenv("PENDULAB_CC", raising=False)
    yield


# point, parameters and time step of each system (pivot: tau; string: t in s with g = 9.81)
CASES = {
    "rod": ([0.06, 0.01], [0.2, 0.05], 0.2),
    "point-hill": ([0.3, -0.2], [0.1, 0.1], 0.1),
    "string-linear": ([0.5, 0.0], [1.0, 9.81, 0.1], 0.05),
    "string-periodic": ([0.8, 0.3], [1.0, 0.2, 9.81, 1.7], 0.05),
}


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("linear", [False, True])
def test_rk4_is_of_order_four(name, linear):
    fos = system(name)
    y0, p, dt = CASES[name]
    span = 40 * dt
    errors = [rk4_error(fos, y0, p, 0.0, dt / 2 ** j, 40 * 2 ** j, linear=linear)
              for j in range(3)]
    ratios = [errors[j] / errors[j + 1] for j in range(2)]
    assert all(13.0 < r < 19.0 for r in ratios), (errors, ratios)
    assert errors[-1] < 1e-5 * max(1.0, span)


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.needs_cc
def test_c_and_numpy_integrators_give_the_same_bits(name, rng):
    fos = system(name)
    _, p, dt = CASES[name]
    n = 70                                          # two full blocks and a partial one
    y0 = np.column_stack([rng.uniform(-1, 1, n), rng.uniform(-0.5, 0.5, n)])
    params = np.array(p) * rng.uniform(0.8, 1.2, (n, len(p)))
    for linear in (False, True):
        c = ensemble_rk4(fos, y0, params, 0.3, dt, 200, linear=linear, backend="c")
        py = ensemble_rk4(fos, y0, params, 0.3, dt, 200, linear=linear, backend="numpy")
        assert (c.backend, py.backend) == ("c", "numpy")
        for field in ("y", "mean_theta", "mean_abs_theta", "max_abs_theta"):
            # the same IEEE operations in the same order: the same bits
            assert np.array_equal(getattr(c, field), getattr(py, field)), field


@pytest.mark.needs_cc
def test_statistics_are_over_the_states_including_the_initial_one():
    fos = system("rod")
    y0, p = [0.06, 0.01], [0.2, 0.05]
    steps, dt = 500, math.pi / 100
    for backend in ("c", "numpy"):
        _, states = rk4_trajectory(fos, y0, p, 0.0, dt, steps, backend="numpy")
        r = ensemble_rk4(fos, [y0], p, 0.0, dt, steps, backend=backend)
        th = states[:, 0]
        assert th.shape == (steps + 1,)
        np.testing.assert_allclose(r.y[0], states[-1], rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(r.mean_theta[0], th.sum() / (steps + 1), rtol=1e-11)
        np.testing.assert_allclose(r.mean_abs_theta[0], np.abs(th).sum() / (steps + 1), rtol=1e-11)
        assert r.max_abs_theta[0] == pytest.approx(np.abs(th).max(), rel=1e-12)
        assert (r.steps, r.dt) == (steps, dt)
    # the initial state counts: a start at the largest |theta| is the maximum
    r = ensemble_rk4(fos, [[0.5, 0.0]], [0.0, 0.0], 0.0, 0.1, 3)
    assert r.max_abs_theta[0] == 0.5


@pytest.mark.needs_cc
def test_trajectories_c_and_numpy_give_the_same_bits():
    fos = system("string-periodic")
    y0, p, dt = CASES["string-periodic"]
    tc, sc = rk4_trajectory(fos, y0, p, 0.0, dt, 300, backend="c")
    tn, sn = rk4_trajectory(fos, y0, p, 0.0, dt, 300, backend="numpy")
    assert np.array_equal(tc, tn) and sc.shape == (301, 2)
    assert np.array_equal(sc, sn)


@pytest.mark.needs_cc
def test_beyond_the_fast_sine_range_the_library_sine_is_used():
    fos = system("rod")
    limit = codegen.SIN_LIMIT
    # a fast rotation that passes SIN_LIMIT within the run, and a calm one in the same block
    y0 = [[limit - 50.0, 40.0], [0.06, 0.01]]
    p = [[0.2, 0.05], [0.2, 0.05]]
    c = ensemble_rk4(fos, y0, p, 0.0, 0.01, 400, backend="c")
    py = ensemble_rk4(fos, y0, p, 0.0, 0.01, 400, backend="numpy")
    assert c.max_abs_theta[0] > limit and c.exact_trajectories == py.exact_trajectories == 1
    assert np.array_equal(c.y[1], py.y[1])               # the calm one: the fast sine, same bits
    np.testing.assert_allclose(c.y, py.y, rtol=1e-12)
    np.testing.assert_allclose(c.mean_theta, py.mean_theta, rtol=1e-12)
    _, sc = rk4_trajectory(fos, y0[0], p[0], 0.0, 0.01, 400, backend="c")
    _, sn = rk4_trajectory(fos, y0[0], p[0], 0.0, 0.01, 400, backend="numpy")
    np.testing.assert_allclose(sc, sn, rtol=1e-12)


@pytest.mark.needs_cc
def test_threads_do_not_change_a_bit(rng):
    fos = system("rod")
    n = 333
    y0 = np.column_stack([rng.uniform(-0.1, 0.1, n), rng.uniform(-0.1, 0.1, n)])
    params = rng.uniform(0, 1, (n, 2))
    one = ensemble_rk4(fos, y0, params, 0.0, 0.05, 300, threads=1, backend="c")
    two = ensemble_rk4(fos, y0, params, 0.0, 0.05, 300, threads=2, backend="c")
    for field in ("y", "mean_theta", "mean_abs_theta", "max_abs_theta"):
        assert np.array_equal(getattr(one, field), getattr(two, field))


def _child(queue):
    fos = system("rod")
    r = ensemble_rk4(fos, [[0.06, 0.01]] * 40, [0.2, 0.05], 0.0, 0.05, 200, threads=2)
    queue.put((r.backend, float(r.y[0, 0])))


@pytest.mark.needs_cc
def test_the_kernel_runs_in_a_forked_process_after_use_in_the_parent():
    fos = system("rod")
    here = ensemble_rk4(fos, [[0.06, 0.01]] * 40, [0.2, 0.05], 0.0, 0.05, 200, threads=2)
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()
    proc = ctx.Process(target=_child, args=(queue,))
    proc.start()
    got = queue.get(timeout=60)
    proc.join(timeout=60)
    assert got == ("c", float(here.y[0, 0]))


@pytest.mark.needs_cc
def test_a_blow_up_shows_in_the_statistics():
    # the string shortening through zero length: L0 + v0 t = 0 at t = 1
    fos = system("string-linear")
    for backend in ("c", "numpy"):
        with np.errstate(all="ignore"):
            r = ensemble_rk4(fos, [[0.1, 0.0]], [1.0, 9.81, -1.0], 0.0, 0.01, 300, backend=backend)
        assert not np.isfinite(r.max_abs_theta[0]) and not np.isfinite(r.mean_theta[0])


def test_empty_ensemble_and_broadcast_parameters():
    fos = system("rod")
    r = ensemble_rk4(fos, np.empty((0, 2)), [0.2, 0.05], 0.0, 0.1, 5)
    assert r.y.shape == (0, 2) and r.mean_theta.shape == (0,)
    a = ensemble_rk4(fos, [[0.06, 0.01], [0.06, 0.01]], [0.2, 0.05], 0.0, 0.1, 5)
    b = ensemble_rk4(fos, [[0.06, 0.01], [0.06, 0.01]], [[0.2, 0.05]] * 2, 0.0, 0.1, 5)
    assert np.array_equal(a.y, b.y)
    off = ensemble_rk4(fos, [[0.06, 0.01]], [0.2, 0.05], 0.0, 0.1, 5, stats=False)
    assert np.isnan(off.mean_theta[0]) and np.isfinite(off.y).all()


def test_reference_is_tight():
    # DOP853 against itself at a tolerance 100 times looser: the reference moves less than that
    fos = system("rod")
    t = np.linspace(0.0, 20.0, 41)
    a = reference_trajectory(fos, [0.06, 0.01], [0.2, 0.05], t)
    b = reference_trajectory(fos, [0.06, 0.01], [0.2, 0.05], t, rtol=1e-11, atol=1e-13)
    assert np.max(np.abs(a - b)) < 1e-9
    assert np.array_equal(a[0], [0.06, 0.01])


@pytest.mark.parametrize("name, linear", [("rod", True), ("rod", False), ("string-linear", True)])
def test_reference_agrees_with_an_mpmath_taylor_solution(name, linear):
    """DOP853 on the generated scalar right-hand side against mpmath's Taylor-series ODE
    solver (mpmath.odefun, 25 digits) on the lambdified derivation: an independent method
    and an independent evaluation of the equation."""
    import mpmath
    import sympy as sp
    fos = system(name)
    y0, p, _ = CASES[name]
    exprs = fos.linear_rhs if linear else fos.rhs
    f = sp.lambdify((fos.time, fos.states, fos.params), list(exprs), "mpmath")
    t = np.linspace(0.0, 3.0, 7)
    ref = reference_trajectory(fos, y0, p, t, linear=linear)
    with mpmath.workdps(25):
        pm = [mpmath.mpf(v) for v in p]
        sol = mpmath.odefun(lambda x, y: f(x, y, pm), 0, [mpmath.mpf(v) for v in y0])
        exact = np.array([[float(v) for v in sol(mpmath.mpf(x))] for x in t])
    assert np.max(np.abs(ref - exact)) < 1e-11


def test_reference_turns_a_math_overflow_into_one_line(monkeypatch):
    """The scalar right-hand side uses math's functions, which raise where NumPy's give inf:
    the reference says it overflowed, in one line."""
    def huge(fos, linear=False):
        def rhs(t, y, p=()):
            return [y[1], math.exp(1e6 * y[0])]
        return rhs
    monkeypatch.setattr(codegen, "scalar_function", huge)
    with pytest.raises(InputError, match="overflowed"):
        reference_trajectory(system("rod"), [0.06, 0.01], [0.2, 0.05], np.linspace(0, 1, 5))


ROD_Y, ROD_P = [[0.06, 0.01]], [0.2, 0.05]


@pytest.mark.parametrize("kwargs, fragment", [
    ({"y0": [0.06, 0.01]}, "y0 must have shape (n, 2)"),
    ({"y0": [[0.06, 0.01, 0.0]]}, "y0 must have shape (n, 2)"),
    ({"y0": [[float("nan"), 0.0]]}, "y0 has a value that is not finite"),
    ({"y0": [["a", 0.0]]}, "y0 must be an array of numbers"),
    ({"params": [0.2]}, "params must have 2 values (a_over_l, w0_over_w), got 1"),
    ({"params": [[0.2, 0.05]] * 2}, "params must have shape (1, 2)"),
    ({"params": [[[0.2, 0.05]]]}, "params must have shape (n, 2) or (2,)"),
    ({"steps": 0}, "steps must be a positive integer"),
    ({"steps": -3}, "steps must be a positive integer"),
    ({"steps": 2.5}, "steps must be a positive integer"),
    ({"steps": True}, "steps must be a positive integer"),
    ({"dt": float("nan")}, "dt must be a finite number"),
    ({"dt": float("inf")}, "dt must be a finite number"),
    ({"dt": 0.0}, "dt must be a finite nonzero number"),
    ({"dt": "0.1"}, None),
    ({"t0": None}, "t0 must be a finite number"),
    ({"backend": "gpu"}, "backend must be one of auto, c, numpy"),
    ({"threads": 0}, "threads must be a positive integer"),
])
def test_bad_input_is_one_line(kwargs, fragment):
    args = {"y0": ROD_Y, "params": ROD_P, "t0": 0.0, "dt": 0.1, "steps": 5}
    args.update(kwargs)
    extra = {k: args.pop(k) for k in ("backend", "threads") if k in args}
    fos = system("rod")
    if fragment is None:                    # a numeric string is a number
        assert ensemble_rk4(fos, args["y0"], args["params"], args["t0"], args["dt"],
                            args["steps"], **extra).y.shape == (1, 2)
        return
    with pytest.raises(InputError) as info:
        ensemble_rk4(fos, args["y0"], args["params"], args["t0"], args["dt"], args["steps"],
                     **extra)
    assert fragment in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("call, fragment", [
    (lambda f: rk4_trajectory(f, [[0.06, 0.01]], ROD_P, 0.0, 0.1, 5), "y0 must have shape (2,)"),
    (lambda f: rk4_trajectory(f, [0.06, 0.01], [0.2], 0.0, 0.1, 5), "params must have shape (2,)"),
    (lambda f: rk4_trajectory(f, [0.06, 0.01], ROD_P, 0.0, 0.1, 0), "steps must be"),
    (lambda f: reference_trajectory(f, [0.06, 0.01], ROD_P, [0.0]), "at least two times"),
    (lambda f: reference_trajectory(f, [0.06, 0.01], ROD_P, [0.0, 1.0, 0.5]), "monotonic"),
    (lambda f: rk4_error(f, [0.06, 0.01], ROD_P, 0.0, float("nan"), 5), "dt must be"),
])
def test_bad_input_of_the_single_trajectory_calls(call, fragment):
    with pytest.raises(InputError) as info:
        call(system("rod"))
    assert fragment in str(info.value) and "\n" not in str(info.value)


def test_default_threads_is_positive():
    assert integrate.default_threads() >= 1


@pytest.mark.needs_cc
def test_a_large_time_argument_also_takes_the_library_sine():
    # L(t) = L0 (1 + e cos(w t)) far out in time: sin(w t) beyond SIN_LIMIT, theta small
    fos = system("string-periodic")
    t0 = 3.0 * codegen.SIN_LIMIT
    p = [1.0, 0.2, 9.81, 1.7]
    c = ensemble_rk4(fos, [[0.1, 0.0]], p, t0, 0.01, 300, backend="c")
    py = ensemble_rk4(fos, [[0.1, 0.0]], p, t0, 0.01, 300, backend="numpy")
    assert c.max_abs_theta[0] < 1.0 and c.exact_trajectories == py.exact_trajectories == 1
    calm = ensemble_rk4(fos, [[0.1, 0.0]], p, 0.0, 0.01, 300, backend="c")
    assert calm.exact_trajectories == 0
    np.testing.assert_allclose(c.y, py.y, rtol=1e-9, atol=1e-12)
