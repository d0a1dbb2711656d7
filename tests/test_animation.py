"""The animations: what they draw is the computed motion, and the files are what they say.

References: the pivot height y0 = a cos(omega t) (000 eq. 1) in tau = omega t/2,
so y0/l = (a/l) cos(2 tau); a rod's centre of mass at distance l from the pivot
(000 sec. 2.1); the string's length L(t) = L0 + v0 t or L0 - v0 t (002 sec. 2).
Stable and unstable pairs: Kapitza's condition for the inverted point mass,
a^2 omega^2 > 2 g l (Landau & Lifshitz, Mechanics, sec. 30, problem 1), that is
(a/l) / (omega0/omega) > sqrt(2); (0.1, 0.02) has the ratio 5 and (0.1, 0.2)
the ratio 0.5, far on either side (for the rod, I/(m l^2) = 4/3 moves the
threshold by a factor sqrt(4/3) only, 000 eq. 12).
"""

import math
import os
import shutil
import stat
import subprocess

import numpy as np
import pytest

from pendulab import animation as A
from pendulab.cli import main
from pendulab.numerics import sweep as S
from pendulab.numerics.sweep import SystemSpec

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def stable():
    return A.pivot_frames(SystemSpec("rod"), 0.1, 0.02, theta_init=0.3, omega_init=0.0,
                          periods=16, frames_per_period=8)


@pytest.mark.parametrize("body", ["rod", "point"])
def test_the_pendulum_stands_for_a_stable_pair_and_falls_for_an_unstable_one(body):
    up = A.pivot_frames(SystemSpec(body), 0.1, 0.02, theta_init=0.3, periods=16,
                        frames_per_period=8)
    down = A.pivot_frames(SystemSpec(body), 0.1, 0.2, theta_init=0.3, periods=16,
                          frames_per_period=8)
    # upright: the body never leaves the upper half-plane above the pivot
    assert np.max(np.abs(up.theta)) < 0.5
    assert np.all(up.mass[:, 1] > up.pivot[:, 1])
    # falling: the body goes past the horizontal, below the pivot
    assert np.max(np.abs(down.theta)) > math.pi / 2
    assert np.any(down.mass[:, 1] < down.pivot[:, 1])


def test_the_pivot_moves_as_the_drive_and_the_rod_keeps_its_length(stable):
    tau = stable.time
    assert np.allclose(stable.pivot[:, 1], 0.1 * np.cos(2 * tau), rtol=0, atol=1e-15)
    assert np.all(stable.pivot[:, 0] == 0)
    arm = stable.mass - stable.pivot
    assert np.allclose(np.hypot(arm[:, 0], arm[:, 1]), 1.0, rtol=0, atol=1e-14)
    # theta is measured from the upward vertical (000 sec. 2.1)
    assert np.allclose(np.arctan2(arm[:, 0], arm[:, 1]), stable.theta, rtol=0, atol=1e-13)


def test_another_drive_moves_the_pivot_as_that_drive():
    spec = SystemSpec("rod", drive="a*cos(omega*t) + a*cos(2*omega*t)")
    frames = A.pivot_frames(spec, 0.05, 0.01, periods=2, frames_per_period=8)
    tau = frames.time
    assert np.allclose(frames.pivot[:, 1], 0.05 * (np.cos(2 * tau) + np.cos(4 * tau)),
                       rtol=0, atol=1e-15)


def test_the_frames_are_steps_of_the_simulated_trajectory(stable):
    # 8 frames per period, 13 RK4 steps between frames: 104 steps per period
    spec = S.make_spec(SystemSpec("rod"), a_over_l=[0.1], w0_over_w=[0.02], theta_init=0.3,
                       omega_init=0.0, periods=16, steps_per_period=104)
    run = S.trajectory(spec)
    assert len(stable.time) == 16 * 8 + 1
    assert np.array_equal(stable.theta, run["states"][::13, 0])
    assert np.allclose(np.diff(stable.time), math.pi / 8, rtol=1e-12)


def test_the_gif_has_every_frame_and_the_same_bytes_each_time(stable):
    from PIL import Image
    short = A.Frames(stable.time[:20], stable.theta[:20], stable.pivot[:20], stable.mass[:20],
                     stable.body, stable.frames_per_period, stable.period, stable.title)
    one, two = (A.gif_bytes(A.rendered(short)) for _ in range(2))
    assert one == two and one[:6] == b"GIF89a"
    import io
    im = Image.open(io.BytesIO(one))
    assert im.n_frames == 20 and im.size == (A.PIXELS, A.PIXELS)
    assert im.info["duration"] == 1000 / A.FPS and im.info["loop"] == 0
    # the frames differ (the pendulum moves): not one picture repeated
    im.seek(0)
    first = np.asarray(im.convert("RGB"))
    im.seek(19)
    assert np.any(np.asarray(im.convert("RGB")) != first)


def test_describe_says_what_a_second_shows(stable):
    text = A.describe(stable)
    assert "8 per drive period" in text and f"{A.FPS} frames per second" in text
    assert f"{8 / A.FPS:g} s of the file" in text


def test_the_string_is_as_long_as_its_length_says():
    from pendulab.equations import derive
    from pendulab.systems import VariableLength
    from pendulab.exprs import parse
    for text, sign in (("L0 + v0*t", 1), ("L0 - v0*t", -1)):
        eqs = derive(VariableLength(length=parse(text)))
        frames = A.string_frames(eqs, {"L0": 1.0, "v0": 0.02, "g": 9.81}, 0.3, 10.0,
                                 frames_per_period=8)
        r = np.hypot(frames.mass[:, 0], frames.mass[:, 1])
        assert np.allclose(r, 1.0 + sign * 0.02 * frames.time, rtol=1e-14)
        assert np.all(frames.mass[:, 1] < 0)  # it hangs below the suspension
        # one frame every eighth of the small-swing period 2 pi sqrt(L0/g)
        assert np.allclose(np.diff(frames.time), 2 * math.pi * math.sqrt(1 / 9.81) / 8)


# --- the command -------------------------------------------------------------

def _run(capsys, *argv):
    code = main(["animate", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_the_command_writes_the_gif_and_says_what_it_shows(tmp_path, capsys):
    out = tmp_path / "k.gif"
    code, stdout, err = _run(capsys, "kapitza", "--periods", "2", "--frames-per-period", "4",
                             "--out", str(out), "--quiet")
    assert code == 0 and stdout == ""
    assert out.read_bytes()[:6] == b"GIF89a"
    assert "9 frames, 4 per drive period" in err
    assert sorted(os.listdir(tmp_path)) == ["k.gif"]


@pytest.mark.parametrize("argv, words", [
    (["kapitza", "--out", "x.png"], "not .png"),
    (["kapitza", "--out", "x"], "a name without one"),
    (["kapitza", "--periods", "400", "--frames-per-period", "64", "--out", "x.gif"],
     "at most 2000"),
    (["kapitza", "--drive", "a*cos(omega*t) + b", "--out", "x.gif"], "b"),
    (["kapitza", "--out", "."], "not a name without one"),
    (["variable-length", "--theta-0", "0", "--out", "x.gif"], "--theta-0 must not be 0"),
    (["variable-length", "--length", "L0 - v0*t", "--t-end", "60", "--out", "x.gif"], "L(t)"),
])
def test_bad_options_give_one_line_and_write_nothing(argv, words, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, stdout, err = _run(capsys, *argv, "--quiet")
    assert code == 2 and stdout == ""
    assert err.count("\n") == 1 and err.startswith("pendulab: error:"), err
    assert words in err
    assert os.listdir(tmp_path) == []


def test_an_out_under_a_file_is_refused(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    code, _, err = _run(capsys, "kapitza", "--out", str(tmp_path / "f" / "x.gif"))
    assert code == 2 and err.count("\n") == 1 and "--out's directory" in err
    assert os.listdir(tmp_path) == ["f"]


def test_mp4_without_ffmpeg_is_refused_in_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    code, _, err = _run(capsys, "kapitza", "--out", str(tmp_path / "k.mp4"))
    assert code == 2 and err.count("\n") == 1 and "ffmpeg" in err
    assert not (tmp_path / "k.mp4").exists()


def test_mp4_goes_through_ffmpeg(tmp_path, capsys, monkeypatch):
    # a stand-in ffmpeg that checks what it is given and writes the raw frames it read
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    fake = bin_dir / "ffmpeg"
    fake.write_text("#!/bin/sh\n"
                    'for last; do :; done\n'
                    'case "$*" in *"-s 320x320 -r 25 -i -"*"-c:v libx264"*) ;; *) exit 3;; esac\n'
                    'cat > "$last"\n')
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", str(bin_dir) + os.pathsep + os.environ.get("PATH", ""))
    out = tmp_path / "k.mp4"
    code, _, err = _run(capsys, "kapitza", "--periods", "1", "--frames-per-period", "4",
                        "--out", str(out), "--quiet")
    assert code == 0, err
    assert out.stat().st_size == 5 * A.PIXELS * A.PIXELS * 3  # five RGB frames


@pytest.mark.skipif(shutil.which("ffmpeg") is None,
                    reason="no ffmpeg on this machine: the stand-in above tests the pipe")
def test_a_real_ffmpeg_writes_an_mp4_with_every_frame(tmp_path, capsys):
    # the frame count and size are read back by ffprobe, not by pendulab
    out = tmp_path / "k.mp4"
    code, _, err = _run(capsys, "kapitza", "--periods", "2", "--frames-per-period", "6",
                        "--out", str(out), "--quiet")
    assert code == 0, err
    probe = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-count_frames",
                            "-show_entries", "stream=nb_read_frames,width,height,r_frame_rate",
                            "-of", "default=noprint_wrappers=1", str(out)],
                           capture_output=True, text=True, check=True).stdout.split()
    assert sorted(probe) == sorted([f"width={A.PIXELS}", f"height={A.PIXELS}",
                                    f"r_frame_rate={A.FPS}/1", "nb_read_frames=13"])


def test_without_matplotlib_the_command_says_so(tmp_path, capsys, monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    code, _, err = _run(capsys, "kapitza", "--periods", "1", "--out", str(tmp_path / "k.gif"))
    assert code == 2 and err.count("\n") == 1 and "matplotlib" in err
    assert not (tmp_path / "k.gif").exists()


# --- the product ---------------------------------------------------------------

def test_the_scene_product_writes_the_commands_file(tmp_path, capsys):
    scene = tmp_path / "anim.toml"
    scene.write_text('name = "anim"\nsystem = "kapitza"\n[parameters]\nbody = "rod"\n'
                     "[products.animation]\nperiods = 2\nframes_per_period = 4\n")
    assert main(["build", str(scene), "--out", str(tmp_path / "out")]) == 0
    built = (tmp_path / "out" / "anim" / "animation.gif").read_bytes()
    assert main(["animate", "kapitza", "--periods", "2", "--frames-per-period", "4",
                 "--out", str(tmp_path / "cmd.gif"), "--quiet"]) == 0
    assert built == (tmp_path / "cmd.gif").read_bytes()
    capsys.readouterr()


def test_the_product_refuses_too_many_frames_and_another_systems_options(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "bad"\nsystem = "kapitza"\n'
                   "[products.animation]\nperiods = 400\nframes_per_period = 64\n")
    assert main(["build", str(bad), "--out", str(tmp_path / "out")]) == 2
    assert "at most 2000" in capsys.readouterr().err
    # each system takes its own options: the string's t_end means nothing to the pivot
    mixed = tmp_path / "mixed.toml"
    mixed.write_text('name = "mixed"\nsystem = "kapitza"\n[products.animation]\nt_end = 5\n')
    assert main(["build", str(mixed), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "products.animation.t_end: unknown option for a kapitza scene" in err
    string = tmp_path / "string.toml"
    string.write_text('name = "string"\nsystem = "variable-length"\n[products.animation]\n'
                      "a_over_l = 0.2\ntheta_0 = 0\n")
    assert main(["build", str(string), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "a_over_l: unknown option for a variable-length scene" in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


STRING_SCENE = ('name = "vl"\nsystem = "variable-length"\n[parameters]\nlength = "{length}"\n'
                "[products.animation]\nL0 = 1.0\nv0 = 0.02\ntheta_0 = 0.3\nt_end = 6\n"
                "frames_per_period = 8\n{extra}")


def test_a_string_scene_gets_the_commands_film_of_its_own_length(tmp_path, capsys):
    from PIL import Image
    scene = tmp_path / "vl.toml"
    scene.write_text(STRING_SCENE.format(length="L0 - v0*t", extra=""))
    assert main(["build", str(scene), "--out", str(tmp_path / "out")]) == 0
    built = tmp_path / "out" / "vl" / "animation.gif"
    assert main(["animate", "variable-length", "--length", "L0 - v0*t", "--L0", "1", "--v0",
                 "0.02", "--theta-0", "0.3", "--t-end", "6", "--frames-per-period", "8",
                 "--out", str(tmp_path / "cmd.gif"), "--quiet"]) == 0
    assert built.read_bytes() == (tmp_path / "cmd.gif").read_bytes()
    # frames: one every (2 pi sqrt(L0/g))/8 s from 0 to t_end (g = 9.81 by default)
    period = 2 * math.pi * math.sqrt(1.0 / 9.81)
    assert Image.open(built).n_frames == math.floor(6 / period * 8) + 1
    # a growing string is another film
    scene.write_text(STRING_SCENE.format(length="L0 + v0*t", extra=""))
    assert main(["build", str(scene), "--out", str(tmp_path / "grow")]) == 0
    assert (tmp_path / "grow" / "vl" / "animation.gif").read_bytes() != built.read_bytes()
    capsys.readouterr()


def test_a_string_scene_names_the_numbers_its_length_lacks(tmp_path, capsys):
    scene = tmp_path / "vl.toml"
    scene.write_text(STRING_SCENE.format(length="L0*(1 + eps*cos(Omega*t))", extra=""))
    assert main(["build", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "products.animation: L(t) = " in err and "needs numbers for Omega, eps" in err
    assert not (tmp_path / "out").exists()
    # given in values, the periodic length is animated
    scene.write_text(STRING_SCENE.format(length="L0*(1 + eps*cos(Omega*t))",
                                         extra="values = {eps = 0.1, Omega = 6.0}\n"))
    assert main(["build", str(scene), "--out", str(tmp_path / "out")]) == 0
    assert (tmp_path / "out" / "vl" / "animation.gif").stat().st_size > 0
    capsys.readouterr()


@pytest.mark.parametrize("argv, words", [
    # L(t) = L0 e^(-t) falls to L0/10^6 at t = 6 ln 10 = 13.8155 s: refused before integrating
    (["--length", "L0*exp(-t)", "--t-end", "20"], "falls to 1e-06 L(0) at t = 13.8155"),
    # L0 e^(-t/2) stays above L0/10^6 up to 27 s, but its swing quickens as sqrt(g/L(t)):
    # the integral of sqrt(g/L)/(2 pi) is 4 sqrt(g/L0) (e^(27/4) - 1)/(2 pi) = 5430 swings at
    # g = 100, past the 2000 DOP853 integrates in about a minute (frames: 172, within theirs)
    (["--length", "L0*exp(-t/2)", "--g", "100", "--t-end", "27", "--frames-per-period", "4"],
     "is about 5.43e+03 oscillations of the string"),
])
def test_a_string_too_costly_to_integrate_is_refused_before_any_work(argv, words, tmp_path,
                                                                     capsys):
    import time
    start = time.monotonic()
    code = main(["animate", "variable-length", *argv, "--out", str(tmp_path / "s.gif"),
                 "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and words in err[0], err
    assert time.monotonic() - start < 20 and not (tmp_path / "s.gif").exists()
