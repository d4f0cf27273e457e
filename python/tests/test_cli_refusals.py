"""The command line's refusals: bad input gets one line naming the flag as written, exit
status 2, and leaves no output behind (no complete-looking file from a run that fails)."""

import math

import numpy as np
import pytest

import angletrack
from angletrack import capture, cli

RATE_HZ = 10_000.0


def run(capsys, *args):
    """(status, stderr) of ``angletrack ARGS``."""
    status = cli.main([str(a) for a in args])
    return status, capsys.readouterr().err


def refused(capsys, *args, flag):
    """Asserts ``angletrack ARGS`` is refused in one line naming ``flag``; returns it."""
    status, err = run(capsys, *args)
    assert status == 2 and err.count("\n") == 1 and err.startswith("angletrack: error: "), err
    assert flag in err, err
    return err


@pytest.fixture(scope="module")
def gains(tmp_path_factory):
    path = tmp_path_factory.mktemp("gains") / "g.json"
    assert cli.main(["design", "kalman", "--sample-rate", str(RATE_HZ), "--jerk-std", "1e6", "--noise-std", "0.01",
                     "-o", str(path)]) == 0
    return path


def angle(n):
    t = np.arange(n) / RATE_HZ
    return t, 0.3 + 2 * math.pi * 50.0 * t


@pytest.fixture
def clean(tmp_path):
    """0.15 s at 50 rev/s (7.5 turns) with a reference column."""
    t, theta = angle(1500)
    path = tmp_path / "clean.csv"
    capture.write_capture(path, {"time": t, "y_c": np.cos(theta), "y_s": np.sin(theta), "reference": theta})
    return path


def counts(path, theta, mid, amplitude=1800.0, reference=True):
    """Whole ADC counts around ``mid`` as an integer .npy structured array."""
    fields = [("y_c", np.int32), ("y_s", np.int32)] + ([("reference", np.float64)] if reference else [])
    data = np.zeros(len(theta), dtype=fields)
    data["y_c"] = np.round(mid + amplitude * np.cos(theta))
    data["y_s"] = np.round(mid + amplitude * np.sin(theta))
    if reference:
        data["reference"] = theta
    np.save(path, data)
    return path


def argparse_refused(capsys, *args, flag):
    """Asserts argparse refuses ``angletrack ARGS`` (status 2, after its usage lines) in a
    last line naming ``flag``; returns that line."""
    with pytest.raises(SystemExit) as exit_:
        cli.main([str(a) for a in args])
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert exit_.value.code == 2 and f"argument {flag}:" in last, last
    return last


@pytest.mark.parametrize("value", ["0", "-3", "4294967296", "65537", "2.5"])
def test_pole_pairs_out_of_range_are_refused_naming_the_flag(tmp_path, capsys, gains, clean, value):
    out = tmp_path / "x.csv"
    last = argparse_refused(capsys, "track", clean, "--gains-file", gains, "--carrier-hz", 10000,
                            "--pole-pairs", value, "-o", out, flag="--pole-pairs")
    assert "from 1 to 65536" in last and not out.exists()


def test_design_refuses_a_plot_onto_its_gains_file(tmp_path, capsys):
    same = tmp_path / "same.png"
    same.write_bytes(b"kept")
    refused(capsys, "design", "kalman", "--sample-rate", RATE_HZ, "--jerk-std", 1e6, "--noise-std", 0.01,
            "--format", "json", "-o", same, "--plot", same, flag="--plot")
    assert same.read_bytes() == b"kept"


def test_calibrate_writes_the_format_its_output_names(tmp_path, capsys, gains, clean):
    # The rule of design's gains (one function): the extension names the format, a --format
    # that contradicts it is refused before the capture is read.
    cal = tmp_path / "cal.json"
    err = refused(capsys, "calibrate", clean, "--gains-file", gains, "--format", "c", "-o", cal, flag="--format c")
    assert "does not match --output" in err and not cal.exists()
    header = tmp_path / "cal.h"
    assert cli.main(["calibrate", str(clean), "--gains-file", str(gains), "-o", str(header)]) == 0
    assert "#ifndef ANGLETRACK_CALIBRATION_H" in header.read_text()
    assert cli.main(["calibrate", str(clean), "--gains-file", str(gains), "-o", str(cal)]) == 0
    out = tmp_path / "e.csv"
    assert cli.main(["track", str(clean), "--gains-file", str(gains), "--calibration", str(cal), "-o", str(out)]) == 0


def test_calibrate_makes_its_output_directory(tmp_path, capsys, gains, clean):
    out = tmp_path / "new" / "dir" / "cal.json"
    assert cli.main(["calibrate", str(clean), "--gains-file", str(gains), "-o", str(out)]) == 0
    assert '"format"' in out.read_text()


@pytest.mark.parametrize("command", [
    ["calibrate", "{clean}", "--gains-file", "{gains}", "-o", "{dir}"],
    ["track", "{clean}", "--gains-file", "{gains}", "-o", "{dir}/x.csv", "--plot", "{dir}"],
    ["design", "kalman", "--sample-rate", "1e4", "--jerk-std", "1e6", "--noise-std", "0.01", "-o", "{dir}"],
])
def test_an_output_that_is_a_directory_is_refused_naming_the_flag(tmp_path, capsys, gains, clean, command):
    args = [a.format(clean=clean, gains=gains, dir=tmp_path) for a in command]
    flag = "--plot" if "--plot" in args else "--output"
    # The track's --plot names a .png, so that argparse takes it.
    if flag == "--plot":
        (tmp_path / "d.png").mkdir()
        args[-1] = str(tmp_path / "d.png")
    err = refused(capsys, *args, flag=flag)
    assert "is a directory" in err and not (tmp_path / "x.csv").exists()


def test_an_output_whose_directory_cannot_be_made_is_refused_before_tracking(tmp_path, capsys, gains, clean):
    out = tmp_path / "e.csv"
    err = refused(capsys, "track", clean, "--gains-file", gains, "-o", out, "--plot", "/proc/nope/x.png",
                  flag="--plot: /proc/nope/x.png: cannot make its directory")
    assert not out.exists(), err
