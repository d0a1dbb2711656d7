"""`pendulab simulate --drive`: one trajectory under any periodic pivot drive.

Independent reference: the rod's equation written here from Newton's law for a rigid body
on a vertically moving pivot (000 sec. 2: I theta'' = m l (g + y0''(t)) sin theta, theta
from the upward vertical, I = (4/3) m l^2 for the rod, omega0^2 = m g l / I), put in
tau = omega t/2 (000 sec. 4), so that with w = omega0/omega and A = a/l

    d^2 theta/dtau^2 = (4 w^2 + 3 y0''(t)/(l omega^2)) sin theta,

and integrated by SciPy's solve_ivp (DOP853, rtol 1e-12).  The first run checks this
convention on the source's own drive; the second is the two-harmonic drive.
"""

import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pendulab.cli import main

A, W = 0.2, 0.05


def _reference(tau, harmonics):
    # y0 = a sum_k cos(k omega t) = a sum_k cos(2 k tau): y0''/(l omega^2) = -A sum_k k^2 cos(2 k tau)
    def rhs(s, y):
        accel = -A * sum(k * k * np.cos(2 * k * s) for k in harmonics)
        return [y[1], (4 * W * W + 3 * accel) * np.sin(y[0])]
    sol = solve_ivp(rhs, (0, tau[-1]), [0.06, 0.01], method="DOP853", rtol=1e-12, atol=1e-14,
                    t_eval=tau)
    return sol.y[0]


def _simulate(capsys, *extra):
    argv = ["simulate", "--a-over-l", str(A), "--w0-over-w", str(W), "--periods", "4",
            "--steps-per-period", "400", "--every", "40", "--json", *extra]
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("drive, harmonics", [
    (None, (1,)),
    ("a*cos(omega*t) + a*cos(2*omega*t)", (1, 2)),
])
def test_the_trajectory_is_the_drives_motion(drive, harmonics, capsys):
    rec = _simulate(capsys, *(["--drive", drive] if drive else []))
    assert rec["drive"] == drive
    ref = _reference(np.array(rec["tau"]), harmonics)
    assert np.max(np.abs(np.array(rec["theta"]) - ref)) < 1e-7  # RK4 at pi/400


def test_the_drives_differ_and_the_text_names_the_drive(capsys):
    one = _simulate(capsys)
    two = _simulate(capsys, "--drive", "a*cos(omega*t) + a*cos(2*omega*t)")
    assert abs(one["theta"][-1] - two["theta"][-1]) > 1e-3
    assert main(["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--periods", "1",
                 "--drive", "a*cos(omega*t) + a*cos(2*omega*t)", "--reference"]) == 0
    out = capsys.readouterr().out
    assert "drive y0(t) = a*cos(omega*t) + a*cos(2*omega*t)" in out
    assert "largest |theta - theta_DOP853|" in out


@pytest.mark.parametrize("drive, fragment", [
    ("a*cos(", "--drive: cannot parse"),
    ("b*cos(omega*t)", "the drive b*cos(omega*t) uses b:"),
])
def test_a_bad_drive_is_one_line(drive, fragment, capsys):
    code = main(["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--drive", drive])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1 and fragment in err


def test_a_drive_of_another_fundamental_says_whose_periods_are_run(capsys):
    # a*cos(3 omega t) has the fundamental Omega = 3 omega: tau = Omega t/2, and at
    # omega0/omega = 0.3 it is the source's drive at omega0/Omega = 0.1 (000 eqs. 5-6 with
    # Omega for omega), the same trajectory in the same tau
    base = ["simulate", "--a-over-l", "0.2", "--theta-init", "0.06", "--omega-init", "0.01",
            "--periods", "3", "--json"]
    assert main(base + ["--w0-over-w", "0.3", "--drive", "a*cos(3*omega*t)"]) == 0
    tripled = json.loads(capsys.readouterr().out)
    assert tripled["drive_fundamental"] == "3*omega"
    assert main(base + ["--w0-over-w", "0.1"]) == 0
    source = json.loads(capsys.readouterr().out)
    assert "drive_fundamental" not in source
    assert tripled["theta"] == pytest.approx(source["theta"], rel=1e-12, abs=1e-15)
    assert main(base[:-1] + ["--w0-over-w", "0.3", "--drive", "a*cos(3*omega*t)"]) == 0
    text = capsys.readouterr().out
    assert "those of its fundamental Omega = 3*omega" in text
