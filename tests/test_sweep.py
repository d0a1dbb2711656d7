"""Sweeps: criteria, chunks, executors, pruning, progress, CLI.

References: trajectories whose statistics are known in closed form (no gravity
and no drive: theta'' = 0, on which RK4 is exact), the physics of the
undriven inverted pendulum (it falls), the source's Fig. 5 point (a stable
inverted motion, 000_8cba66c4fdf94ac6.txt sec. 4), the eq. 28 region (000 eq.
28, which the source says lies inside the numerically stable one) and the
exact Floquet limits of pendulab.analyses.stability (characteristic values
found by root finding, an independent route from is_stable's eigenvalue count).
"""

import io
import json
import math
import sys

import numpy as np
import pytest

from pendulab.cli import main
from pendulab.numerics import sweep as S

ROD = S.SystemSpec("rod")
POINT = S.SystemSpec("point")


def _bytes(result):
    return b"".join(np.ascontiguousarray(result.stats[k]).tobytes() for k in S.STATS)


# -- criteria on trajectories with known behaviour --------------------------------------------

P, STEPS = 20, 40
T = P * math.pi  # the run in tau: P drive periods of length pi


@pytest.mark.parametrize("th, om, mean, mean_abs, bounded", [
    (0.06, 0.0, True, True, True),             # rests at 0.06: every mean is 0.06
    (-0.05, 0.0, True, True, True),            # signed mean -0.05: |mean| < 0.1
    (0.05, 0.002, False, False, True),         # mean 0.05 + 0.001 T = 0.113
    (0.0, -0.01, False, False, True),          # mean -0.005 T = -0.314: the criterion takes |mean|
    (-0.3, 0.6 / T, True, False, True),        # runs from -0.3 to 0.3: mean 0, mean |theta| 0.15
    (1.0, 0.5 / T, False, False, True),        # ends at 1.5 < pi/2
    (1.0, 1.0 / T, False, False, False),       # ends at 2.0 > pi/2
])
def test_criteria_on_uniform_rotation(th, om, mean, mean_abs, bounded):
    # a/l = 0 and omega0/omega = 0: theta'' = 0, theta = theta(0) + theta'(0) tau, which RK4
    # integrates exactly; the statistics over the steps + 1 states are those of an arithmetic
    # sequence: mean = theta(0) + theta'(0) T/2, max |theta| = max(|theta(0)|, |theta(T)|)
    spec = S.make_spec(ROD, a_over_l=[0.0], w0_over_w=[0.0], theta_init=th, omega_init=om,
                       periods=P, steps_per_period=STEPS)
    r = S.sweep(spec, executor="serial", backend="numpy")
    end = th + om * T
    assert r.stats["mean_theta"][0, 0, 0] == pytest.approx(th + om * T / 2, abs=1e-12)
    assert r.stats["max_abs_theta"][0, 0, 0] == pytest.approx(max(abs(th), abs(end)), abs=1e-12)
    got = {c: bool(S.verdict(c, r.stats)[0, 0, 0]) for c in ("mean", "mean-abs", "bounded")}
    assert got == {"mean": mean, "mean-abs": mean_abs, "bounded": bounded}


def test_mean_abs_of_a_sign_changing_run():
    # theta from -0.3 to 0.3 in n equal steps: mean |theta| = 0.3 (n/2 + 1)/(n + 1) ... exactly
    # sum_i |(-0.3 + 0.6 i/n)| / (n + 1); computed here independently of the integrator
    n = P * STEPS
    spec = S.make_spec(ROD, a_over_l=[0.0], w0_over_w=[0.0], theta_init=-0.3, omega_init=0.6 / T,
                       periods=P, steps_per_period=STEPS)
    r = S.sweep(spec, executor="serial", backend="numpy")
    expected = sum(abs(-0.3 + 0.6 * i / n) for i in range(n + 1)) / (n + 1)
    assert r.stats["mean_abs_theta"][0, 0, 0] == pytest.approx(expected, rel=1e-9)


def test_undriven_inverted_pendulum_falls_and_fig5_point_stands():
    # a/l = 0, omega0/omega = 0.3: theta'' = 4 (0.3)^2 sin theta pushes it away from the top;
    # a/l = 1/5, omega0/omega = 1/20 is the source's Fig. 5 stable inverted motion (000 sec. 4)
    spec = S.make_spec(ROD, a_over_l=[0.0, 0.2], w0_over_w=[0.05, 0.3], theta_init=0.06,
                       omega_init=0.01, periods=100, steps_per_period=50)
    r = S.sweep(spec, executor="serial")
    for c in ("mean", "mean-abs", "bounded"):
        v = S.verdict(c, r.stats)[0]
        assert not v[1, 0], c          # (a/l, w) = (0, 0.3): falls
        assert v[0, 1], c              # (0.2, 0.05): Fig. 5, stable
    f = S.floquet_verdict(S.replace(spec, criterion="floquet")).reshape(2, 2)
    assert not f[1, 0] and f[0, 1]


def test_verdict_treats_nan_as_unstable():
    stats = {k: np.array([np.nan, 0.0]) for k in S.STATS}
    for c in ("mean", "mean-abs", "bounded"):
        assert S.verdict(c, stats).tolist() == [False, True]


# -- chunks and executors -------------------------------------------------------------------

def _small(criterion="mean", **kw):
    return S.make_spec(ROD, grid=8, initial=[(0.06, 0.01), (0.1, 0.1)], periods=30,
                       steps_per_period=40, criterion=criterion, **kw)


def test_chunking_does_not_change_a_bit():
    base = S.sweep(_small(chunk_size=1000), executor="serial")
    assert base.simulated == 128
    for size in (7, 1, 64):
        other = S.sweep(_small(chunk_size=size), executor="serial")
        assert _bytes(other) == _bytes(base)
        assert json.dumps(other.record(1)) == json.dumps(base.record(1))


def test_local_processes_give_the_same_bytes():
    spec = _small(chunk_size=20)
    serial = S.sweep(spec, executor="serial", backend="numpy")
    procs = S.sweep(spec, executor="processes", workers=2, backend="numpy")
    assert procs.executor == "processes"
    assert _bytes(procs) == _bytes(serial)
    assert json.dumps(procs.record(0)) == json.dumps(serial.record(0))


def test_assembly_checks_every_index_exactly_once():
    def chunk(idx):
        idx = np.asarray(idx)
        z = np.zeros(len(idx))
        return {"index": idx, "y": np.zeros((len(idx), 2)), "mean_theta": z, "mean_abs_theta": z,
                "max_abs_theta": z, "backend": "numpy"}
    ok = S.assemble(5, [chunk([3, 4]), chunk([0, 1, 2])])
    assert ok["mean_theta"].shape == (5,)
    with pytest.raises(S.PendulabError, match="1 cell.s. missing"):
        S.assemble(5, [chunk([0, 1, 2]), chunk([4])])
    with pytest.raises(S.PendulabError, match="1 duplicated"):
        S.assemble(5, [chunk([0, 1, 2]), chunk([2, 3, 4])])


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    import logging
    logging.getLogger("distributed").setLevel(logging.ERROR)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None, silence_logs=logging.ERROR) as lc:
        with distributed.Client(lc) as client:
            yield lc, client


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_bytes(cluster):
    _, client = cluster
    spec = _small(chunk_size=16)
    local = S.sweep(spec, executor="serial", backend="numpy")
    remote = S.sweep(spec, dask=client, backend="numpy")
    assert remote.executor == "dask"
    assert _bytes(remote) == _bytes(local)
    by_address = S.sweep(spec, dask=cluster[0].scheduler_address, backend="numpy", quiet=True)
    assert _bytes(by_address) == _bytes(local)


@pytest.mark.slow
def test_killing_a_dask_worker_mid_sweep_loses_and_duplicates_nothing(cluster):
    import os
    import signal
    _, client = cluster
    client.wait_for_workers(2, timeout=60)
    spec = S.make_spec(ROD, grid=10, initial=[(0.06, 0.01)], periods=40, steps_per_period=50,
                       chunk_size=5)
    local = S.sweep(spec, executor="serial", backend="numpy")
    killed = {}

    def kill_one(done, total, result):
        if killed:
            return
        busy = {w: keys for w, keys in client.processing().items() if keys}
        if not busy:
            return
        worker = sorted(busy)[0]
        pid = client.run(os.getpid, workers=[worker])[worker]
        killed.update(worker=worker, tasks=len(busy[worker]), done=done, total=total)
        os.kill(pid, signal.SIGKILL)

    remote = S.sweep(spec, dask=client, backend="numpy", callback=kill_one)
    assert killed and killed["tasks"] >= 1 and killed["done"] < killed["total"]
    assert remote.simulated == spec.cells
    assert _bytes(remote) == _bytes(local)


def test_unreachable_scheduler_is_one_line(capsys):
    code = main(["sweep", "--grid", "2", "--periods", "1", "--dask", "tcp://127.0.0.1:9"])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pendulab: error: cannot reach the Dask scheduler")


# -- the Floquet map ----------------------------------------------------------------------------

@pytest.mark.parametrize("system, ratio", [(ROD, 4 / 3), (POINT, 1.0)])
def test_floquet_map_against_eq28_and_exact_limits(system, ratio):
    from pendulab.analyses.stability import limits
    spec = S.make_spec(system, grid=13, criterion="floquet")
    r = S.sweep(spec)
    assert r.simulated == 0
    f = r.stable[0]
    a = np.asarray(spec.a_over_l)
    inside_eq28 = below_exact = 0
    for i, w in enumerate(spec.w0_over_w):
        lo28, up28 = limits(w, ratio, "eq28")
        lo, up = limits(w, ratio, "exact")
        mex = (a > lo + 1e-9) & (a < up - 1e-9)
        # the inside of the exact first band is stable; below its lower limit nothing is
        assert f[i][mex].all(), w
        assert not f[i][a < lo - 1e-9].any(), w
        inside_eq28 += int(((a > lo28 + 1e-9) & (a < up28 - 1e-9)).sum())
        below_exact += int((a < lo - 1e-9).sum())
    # 000 sec. 4: eq. 28 underestimates the stable region (its upper limit is too low)
    assert 0 < inside_eq28 < int(f.sum()) and below_exact > 0


HILL = "a*cos(omega*t) + a*cos(2*omega*t)"


def test_floquet_of_a_hill_drive_is_the_pointwise_monodromy_verdict():
    """The sweep's Hill map (traces_along, DOP853, one integration per row) against
    floquet_verdict cell by cell by the independent route: mpmath Taylor series, 12 digits."""
    from pendulab.numerics.monodromy import floquet_verdict
    system = S.SystemSpec("point", drive=HILL)
    values = (0.0, 0.1, 0.3, 0.5)
    spec = S.make_spec(system, a_over_l=values, w0_over_w=(0.05, 0.25, 0.5), criterion="floquet")
    res = S.sweep(spec)
    fos = S.first_order_system(system)
    want = np.zeros((3, 4), dtype=bool)
    for i, w in enumerate(spec.w0_over_w):
        for j, a in enumerate(values):
            v = floquet_verdict(fos, {"a_over_l": a, "w0_over_w": w}, method="mp", dps=12)
            assert abs(abs(v.trace) - 2) > 1e-6, (a, w)   # no cell on a band edge
            want[i, j] = v.stable
    assert (res.stable[0] == want).all()
    assert want.any() and not want.all()           # both verdicts occur
    # a different drive from the source's: the Mathieu map of the same grid differs
    mathieu = S.sweep(S.replace(spec, system=S.SystemSpec("point"))).stable[0]
    assert (mathieu != want).any()


def test_pruning_a_hill_drive_is_refused_in_one_line():
    spec = S.make_spec(S.SystemSpec("rod", drive=HILL), grid=3, criterion="mean", periods=2)
    with pytest.raises(S.InputError, match="hill equation, not Mathieu's") as info:
        S.pruned_sweep(spec)
    assert "\n" not in str(info.value)


def test_cli_sweep_with_a_hill_drive(capsys):
    assert main(["sweep", "--body", "point", "--drive", HILL, "--grid", "5", "--criterion",
                 "floquet", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    spec = S.make_spec(S.SystemSpec("point", drive=HILL), grid=5, criterion="floquet")
    assert record["count"] == int(S.floquet_verdict(spec).sum())
    assert main(["sweep", "--drive", "import os", "--criterion", "floquet"]) == 2
    assert capsys.readouterr().err.startswith("pendulab: error: --drive:")


# -- pruning: model only what the question needs -------------------------------------------

@pytest.mark.parametrize("criterion", ["bounded", "mean-abs", "mean"])
def test_pruned_map_equals_the_full_map(criterion):
    spec = S.make_spec(ROD, grid=14, initial=[(0.06, 0.01), (0.1, 0.1)], periods=100,
                       steps_per_period=50, criterion=criterion)
    full = S.sweep(spec)
    pruned = S.pruned_sweep(spec)
    assert np.array_equal(pruned.stable, full.stable)
    assert full.simulated == spec.cells
    if criterion != "mean":  # for the signed mean every Floquet-unstable cell is integrated
        assert pruned.simulated < spec.cells // 2
    _, simulate = S.prune_plan(spec)
    assert pruned.simulated == int(simulate.sum())


def test_prune_plan_integrates_the_boundary():
    spec = S.make_spec(ROD, grid=20, criterion="bounded")
    predicted, simulate = S.prune_plan(spec, margin=1)
    f = predicted[0]
    # every cell with a neighbour of the other verdict is integrated
    for i in range(20):
        for j in range(20):
            nb = f[max(i - 1, 0):i + 2, max(j - 1, 0):j + 2]
            if nb.any() and not nb.all():
                assert simulate[0, i, j]


# -- progress -------------------------------------------------------------------------------

class _TTY(io.StringIO):
    def isatty(self):
        return True


def test_progress_only_on_a_terminal_and_not_with_quiet(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert S._progress(10, False, "x") is None
    monkeypatch.setattr(sys, "stderr", _TTY())
    assert S._progress(10, True, "x") is None
    bar = S._progress(10, False, "x")
    assert bar is not None and bar.delay == S.PROGRESS_DELAY
    bar.close()


def test_cli_sweep_is_silent_on_a_pipe(capsys):
    assert main(["sweep", "--grid", "3", "--periods", "2", "--json"]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    json.loads(out)


# -- command line -----------------------------------------------------------------------------

def test_cli_sweep_json(capsys):
    code = main(["sweep", "--body", "point", "--theta-init", "-0.05", "--omega-init", "-1e-3",
                 "--grid", "5", "--periods", "20", "--steps-per-period", "40", "--criterion",
                 "bounded", "--json", "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    rec = json.loads(out)
    assert rec["count"] == len(rec["stable"]) > 0
    assert rec["theta_init"] == -0.05 and rec["omega_init"] == -1e-3
    grid = [k / 4 for k in range(5)]
    assert all(a in grid and w in grid for a, w in rec["stable"])


def test_cli_floquet_and_inertia_ratio(capsys):
    assert main(["sweep", "--inertia-ratio", "4/3", "--grid", "11", "--criterion", "floquet", "--json"]) == 0
    explicit = json.loads(capsys.readouterr().out)
    assert main(["sweep", "--body", "rod", "--grid", "11", "--criterion", "floquet", "--json"]) == 0
    rod = json.loads(capsys.readouterr().out)
    assert explicit["stable"] == rod["stable"] and rod["count"] > 0


@pytest.mark.parametrize("argv, fragment", [
    (["--grid", "0"], "--grid must be an integer from 1 to 400, got 0"),
    (["--grid", "-3"], "--grid must be an integer from 1 to 400, got -3"),
    (["--grid", "2.5"], "--grid must be an integer from 1 to 400, got '2.5'"),
    (["--periods", "-1"], "--periods must be an integer from 1 to 100000"),
    (["--steps-per-period", "0"], "--steps-per-period must be an integer from 1 to 10000"),
    (["--criterion", "median"], "--criterion must be one of"),
    (["--theta-init", "nan"], "--theta-init must be a number from -10000 to 10000, got 'nan'"),
    (["--omega-init", "inf"], "--omega-init must be a number from -10000 to 10000, got 'inf'"),
    (["--theta-init", "abc"], "--theta-init must be a number"),
    (["--inertia-ratio", "0.5"], "--inertia-ratio must be a number from 1 to 1000, got '0.5'"),
    (["--prune", "--criterion", "floquet"], "--prune applies to"),
])
def test_cli_sweep_bad_input(argv, fragment, capsys):
    code = main(["sweep", "--periods", "1"] + argv)
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and out == ""
    assert len(lines) == 1 and lines[0].startswith("pendulab: error:") and fragment in lines[0]


def test_cli_collects_every_problem_in_one_line(capsys):
    assert main(["sweep", "--grid", "0", "--periods", "-2", "--criterion", "x"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--grid" in err[0] and "--periods" in err[0] and "--criterion" in err[0]


def test_cli_simulate_json_csv_and_reference(capsys):
    base = ["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--periods", "4", "--every", "20"]
    assert main(base + ["--json", "--reference"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert len(rec["tau"]) == len(rec["theta"]) == 4 * 100 // 20 + 1
    assert rec["theta"][0] == 0.06 and rec["dtheta"][0] == 0.01
    assert rec["max_error_theta"] < 1e-6  # RK4 at pi/100 against DOP853 (rtol 1e-13)
    assert main(base + ["--csv", "--theta-init", "-0.05"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "tau,theta,dtheta" and lines[1].split(",")[1] == "-0.05"


@pytest.mark.parametrize("argv, fragment", [
    (["--a-over-l", "-0.1"], "--a-over-l must be a number from 0 to 10000, got '-0.1'"),
    (["--w0-over-w", "nan"], "--w0-over-w must be a number from 0 to 1000, got 'nan'"),
    (["--periods", "0"], "--periods must be an integer from 1 to 100000, got 0"),
    (["--every", "-1"], "--every must be an integer from 1 to 10000000, got -1"),
])
def test_cli_simulate_bad_input(argv, fragment, capsys):
    code = main(["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05"] + argv)
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0]
