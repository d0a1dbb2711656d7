"""Inputs at the extremes: tiny theta0 / q keep their significant digits, huge exponents are
refused at once (an audit found wrong digits below ratio ~1e-16 and a hang on 1e99999999999)."""

import subprocess
import sys

import mpmath
import pytest

from pendulab.analyses.floquet import characteristic_exponent, first_band, mathieu_b, stability_limits
from pendulab.errors import InputError, PrecisionError


def _sqrt2_times(r):
    # point mass: theta0 = -4 r^2 and a_0(q) = -q^2/2 + 7 q^4/128 + ... (DLMF 28.6.1), so the
    # lower limit q = 2 a/l solves -q^2/2 = -4 r^2 to relative O(r^2): a/l = sqrt(2) r
    with mpmath.workdps(60):
        return mpmath.sqrt(2) * mpmath.mpf(r)


@pytest.mark.parametrize("ratio", ["1e-20", "1e-40", "1e-50"])
def test_lower_limit_at_tiny_ratio_keeps_its_digits(ratio):
    ref = _sqrt2_times(ratio)
    for method in (None, "mpmath"):
        lo, _ = stability_limits(ratio, dps=30, method=method)
        with mpmath.workdps(40):
            assert abs(lo / ref - 1) < mpmath.mpf(10) ** -28, (method, lo)
    lo, _ = stability_limits(ratio)                       # double precision
    assert lo > 0 and abs(lo / float(ref) - 1) < 1e-14


def test_first_band_at_tiny_theta0():
    lo, _ = first_band("-4e-60", dps=30, method="mpmath")
    with mpmath.workdps(40):
        assert abs(lo / (2 * _sqrt2_times("1e-30")) - 1) < mpmath.mpf(10) ** -28


def test_default_route_answers_tiny_q_where_the_balls_cannot():
    # b_2(q) = 4 - q^2/12 + O(q^4) (DLMF 28.6.19)
    q = mpmath.mpf("1e-10")
    with mpmath.workdps(40):
        v = mathieu_b(2, "1e-10", dps=30)
        assert abs(v - (4 - q * q / 12)) < mpmath.mpf(10) ** -29
    with pytest.raises(PrecisionError):                   # asked for proofs: said so
        mathieu_b(2, "1e-40", dps=30, method="arb")
    assert mathieu_b(2, "1e-40", dps=30) == 4


@pytest.mark.parametrize("text", ["1e99999999999", "-1e-99999999999", "1/1e99999999999"])
def test_huge_exponents_are_refused_not_expanded(text):
    with pytest.raises(InputError, match="exponent"):
        characteristic_exponent(text, "0.1", dps=30)


@pytest.mark.parametrize("argv", [
    ["floquet", "--theta0", "1e99999999999", "--theta1", "0", "--dps", "30"],
    ["floquet", "--theta0", "1", "--theta1", "1e-99999999999"],
    ["stability", "--ratio", "1e99999999999"],
    ["simulate", "--a-over-l", "1e99999999999", "--w0-over-w", "0.1"],
    ["floquet", "--theta0", "\u0663", "--theta1", "1"],      # an Arabic-Indic digit
])
def test_command_line_refuses_them_in_one_line(argv):
    p = subprocess.run([sys.executable, "-m", "pendulab", *argv], capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pendulab: error:"), p.stderr


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_ctrl_c_during_a_build_is_one_line(tmp_path, jobs):
    import os
    import signal
    import time
    # two scenes that each compute for about 10 s (a 25 x 25 map on the NumPy integrator), so
    # that the build is surely still running when the signal comes, however fast the machine
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in ("slow-a", "slow-b"):
        (scenes / f"{name}.toml").write_text(
            f'name = "{name}"\nsystem = "kapitza"\n[parameters]\nbody = "rod"\n'
            '[products.experiments]\nmaps = ["text"]\ngrid = 25\nperiods = 300\n'
            'criteria = ["mean"]\nfig5 = false\nfig2 = false\nfigures = false\n'
            'backend = "numpy"\n')
    env = dict(os.environ, PENDULAB_JOBS=jobs)
    p = subprocess.Popen([sys.executable, "-m", "pendulab", "build", str(scenes), "--force",
                          "--out", str(tmp_path / "out")], stderr=subprocess.PIPE, text=True,
                         env=env)
    time.sleep(2.5)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err          # the build takes ~10 s: still running at 2.5 s
    assert err.strip().splitlines() == [
        "pendulab: error: interrupted (outputs are published whole or not at all)"], err
    assert not (tmp_path / "out").exists() or not any(
        d.name.startswith(".") and d.is_dir() for d in (tmp_path / "out").iterdir())


def test_map_beyond_the_float_range_is_refused_without_warnings():
    import warnings

    import numpy as np

    from pendulab.analyses.floquet import stability_map
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError, match="not finite"):
            stability_map(np.array([0.1]), np.array([1e300]))
