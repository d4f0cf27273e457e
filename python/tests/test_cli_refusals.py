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
    """Asserts argparse refuses ``angletrack ARGS`` (status 2) in one line naming ``flag``;
    returns that line."""
    with pytest.raises(SystemExit) as exit_:
        cli.main([str(a) for a in args])
    err = capsys.readouterr().err.strip()
    assert exit_.value.code == 2 and err.count("\n") == 0 and f"argument {flag}:" in err, err
    return err


@pytest.mark.parametrize("args, flag", [
    (["track", "c.csv", "--gains", "0.1,0.01", "--carrier-hz", "1e4", "--latency", "-1"], "--latency"),
    (["track", "c.csv", "--gains", "0.1,0.01", "--carrier-hz", "1e4", "--expected-delay-deg", "nan"],
     "--expected-delay-deg"),
    (["track", "c.csv", "--gains", "0.1,0.01", "--carrier-hz", "1e4", "--carrier-amplitude", "0"],
     "--carrier-amplitude"),
    (["design", "kalman", "--sample-rate", "1e4", "--q"], "--q"),
])
def test_argument_errors_are_one_line_naming_the_option(capsys, args, flag):
    assert "--help" in argparse_refused(capsys, *args, flag=flag)


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


# ----------------------------------------------------------------- a failed run leaves no output


def raw_windings(path, duration_s=0.01):
    """Raw resolver windings (10 kHz carrier at 160 kHz, 12-bit counts) with a reference."""
    profile = angletrack.MotionProfile(0.3, 300.0).constant_speed(300.0, duration_s)
    scenario = angletrack.resolver_windings(profile, angletrack.ResolverModel(), seed=1)
    capture.write_capture(path, {"time": scenario.time_s, "y_c": scenario.y_c, "y_s": scenario.y_s,
                                 "reference": scenario.angle_rad})
    return path


def test_a_capture_of_bad_samples_leaves_no_estimates(tmp_path, capsys, gains):
    t, _ = angle(200)
    cap = tmp_path / "all_nan.csv"
    capture.write_capture(cap, {"time": t, "y_c": np.full(200, np.nan), "y_s": np.full(200, np.nan)})
    out = tmp_path / "a.csv"
    err = refused(capsys, "track", cap, "--gains-file", gains, "-o", out, flag="mean nothing")
    assert not out.exists(), err


@pytest.mark.parametrize("path", ["float", "fixed", "resolver"])
def test_a_skip_beyond_the_capture_leaves_no_estimates(tmp_path, capsys, gains, clean, path):
    out = tmp_path / "b.csv"
    if path == "resolver":
        args = [raw_windings(tmp_path / "raw.csv"), "--carrier-hz", 10000]
    elif path == "fixed":
        args = [counts(tmp_path / "counts.npy", angle(300)[1], 0.0), "--sample-rate", RATE_HZ, "--dtype", "fixed"]
    else:
        args = [clean]
    refused(capsys, "track", *args, "--gains-file", gains, "-o", out, "--skip", 5, flag="--skip 5")
    assert not out.exists()


def test_a_calibration_that_learned_nothing_leaves_no_estimates(tmp_path, capsys, gains):
    # A rotor standing still: no turn to learn from.
    t, _ = angle(500)
    noise = np.random.default_rng(0).normal(0.0, 0.01, (2, 500))
    cap = tmp_path / "still.csv"
    capture.write_capture(cap, {"time": t, "y_c": 0.8 + noise[0], "y_s": 0.6 + noise[1]})
    out = tmp_path / "c.csv"
    refused(capsys, "track", cap, "--gains-file", gains, "--calibrate", "-o", out, flag="learned 0 turns")
    assert not out.exists() and not (tmp_path / "still_calibration.json").exists()


def test_a_calibration_out_through_a_new_directory_is_written(tmp_path, capsys, gains, clean):
    out, cal = tmp_path / "e1.csv", tmp_path / "nosuch" / ".." / "g.json"
    status, err = run(capsys, "track", clean, "--gains-file", gains, "--calibrate", "--calibration-out", cal,
                      "-o", out)
    assert status == 0 and out.exists() and (tmp_path / "g.json").exists(), err


def test_plot_with_the_fixed_point_chain_draws_the_capture(tmp_path, capsys, gains):
    pytest.importorskip("matplotlib")
    out = tmp_path / "f.csv"
    cap = counts(tmp_path / "counts.npy", angle(300)[1], 2048.0)
    status, err = run(capsys, "track", cap, "--sample-rate", RATE_HZ, "--gains-file", gains, "--dtype", "fixed",
                      "-o", out, "--plot")
    assert status == 0 and out.exists() and (tmp_path / "f.png").stat().st_size > 10_000, err


def test_plot_on_the_resolver_path_is_refused_before_tracking(tmp_path, capsys, gains):
    out = tmp_path / "r.csv"
    err = refused(capsys, "track", raw_windings(tmp_path / "raw.csv"), "--carrier-hz", 10000, "--gains-file", gains,
                  "-o", out, "--plot", flag="--plot with --carrier-hz")
    assert not out.exists() and not (tmp_path / "r.png").exists(), err


# ----------------------------------------------------------------- counts: the mid-scale


@pytest.mark.parametrize("dtype", ["float64", "fixed"])
@pytest.mark.parametrize("stated", [["--adc-bits", 12, "--adc-signed"], ["--adc-range", "-2048,2047"]])
@pytest.mark.parametrize("centre", [0.8, 0.8 - math.pi])
def test_a_stated_signed_range_rules_out_the_unsigned_mid_scale(tmp_path, capsys, gains, dtype, stated, centre):
    # Signed 12-bit counts that are all positive (all negative): the rotor swinging within
    # the first (third) quadrant.
    t, _ = angle(1000)
    theta = centre + 0.6 * np.sin(2 * math.pi * 10.0 * t)
    cap = counts(tmp_path / "signed_q1.npy", theta, 0.0)
    out = tmp_path / "s.csv"
    status, err = run(capsys, "track", cap, "--sample-rate", RATE_HZ, "--gains-file", gains, "--dtype", dtype,
                      *stated, "-o", out)
    assert status == 0, err
    estimates = np.genfromtxt(out, delimiter=",", names=True)
    # After the loop's start-up (20 ms): measured 1.5e-3 rad at most (the loop's lag on the
    # swing, the counts' rounding); the mid-scale 1024 removed instead gave errors of radians.
    assert np.max(np.abs(estimates["angle_rad"][200:] - theta[200:])) < 3e-3


@pytest.mark.parametrize("dtype", ["float64", "fixed"])
def test_signed_counts_at_rest_in_the_first_quadrant_are_read_from_the_whole_capture(tmp_path, capsys, gains,
                                                                                     dtype):
    # Signed counts at rest at 0.5 rad for longer than the first chunk (65,536 rows), then
    # turning: the negative samples later in the capture make them signed (read from the
    # first samples they were taken as unsigned: 1.13 rad RMS, advice --calibrate).
    theta = np.concatenate([np.full(70_000, 0.5), 0.5 + 2 * math.pi * 50.0 * np.arange(1, 5001) / RATE_HZ])
    cap = counts(tmp_path / "signed.npy", theta, 0.0)
    out = tmp_path / "s.csv"
    status, err = run(capsys, "track", cap, "--sample-rate", RATE_HZ, "--gains-file", gains, "--dtype", dtype,
                      "-o", out)
    assert status == 0, err
    angle_rad = np.genfromtxt(out, delimiter=",", names=True)["angle_rad"]
    # Measured 0 at rest, 0.05 rad at the step to 50 rev/s, within 3 mrad of it after 20 ms.
    assert np.max(np.abs(angle_rad[:70_000] - 0.5)) < 1e-3
    assert np.max(np.abs(angle_rad[70_200:] - np.remainder(theta[70_200:] + math.pi, 2 * math.pi) + math.pi)) < 3e-3
    # The same counts cut before they turn show no signedness: refused, not guessed.
    short = counts(tmp_path / "still.npy", theta[:1000], 0.0)
    refused(capsys, "track", short, "--sample-rate", RATE_HZ, "--gains-file", gains, "--dtype", dtype, "-o", out,
            flag="--adc-signed or --adc-unsigned")


@pytest.mark.parametrize("dtype", ["float64", "fixed"])
def test_a_still_shaft_in_unsigned_counts_is_not_clipping(tmp_path, capsys, gains, dtype):
    # 12-bit offset-binary counts, noise-free, the rotor at rest at 60 degrees: its
    # constant channels held no rail (every row was flagged CLIPPING, the angle 0 rad).
    cap = counts(tmp_path / "still.npy", np.full(20_000, math.pi / 3), 2048.0, amplitude=1800.0)
    out = tmp_path / "s.csv"
    status, err = run(capsys, "track", cap, "--sample-rate", RATE_HZ, "--gains-file", gains, "--dtype", dtype,
                      "--adc-unsigned", "-o", out)
    assert status == 0, err
    estimates = np.genfromtxt(out, delimiter=",", names=True)
    assert not np.any(estimates["faults"])
    assert np.max(np.abs(estimates["angle_rad"] - math.pi / 3)) < 1e-3


def test_the_plot_centres_unsigned_counts_as_track_does(tmp_path, gains):
    # Unsigned 12-bit counts on mid-scale 2048: the figure's angle error (plot, track --plot)
    # is measured on the counts centred as the observer sees them.
    from angletrack import plots, tracking

    t, theta = angle(1000)
    cap = counts(tmp_path / "counts.npy", theta, 2048.0)
    settings = tracking.TrackSettings(capture=cap, output=cap, gains_file=gains, sample_rate_hz=RATE_HZ)
    a = plots.analyse_capture(settings)
    # Measured 0.16 mrad RMS (the counts' rounding); on the raw counts it was 1.4 rad.
    assert a.errors.rms_rad() < 1e-3 and "mid-scale 2048 removed" in a.description
    assert abs(a.fit.offset_cos) < 2 and abs(a.fit.offset_sin) < 2


# ----------------------------------------------------------------- options that would do nothing


def test_plot_refuses_a_skip_beyond_the_capture(tmp_path, capsys, clean):
    png = tmp_path / "p.png"
    refused(capsys, "plot", clean, "-o", png, "--skip", 100, flag="--skip 100")
    assert not png.exists()


def test_calibration_out_without_calibrate_is_refused(tmp_path, capsys, gains, clean):
    out = tmp_path / "x.csv"
    refused(capsys, "track", clean, "--gains-file", gains, "--calibration-out", tmp_path / "c.json", "-o", out,
            flag="--calibration-out")
    assert not out.exists()


@pytest.mark.parametrize("option", [["--samples-per-period", 16], ["--carrier-amplitude", 1800],
                                    ["--expected-delay-deg", 305], ["--pole-pairs", 4]])
def test_winding_options_without_carrier_hz_are_refused(tmp_path, capsys, gains, clean, option):
    out = tmp_path / "x.csv"
    err = refused(capsys, "track", clean, "--gains-file", gains, *option, "-o", out, flag=option[0])
    assert "--carrier-hz" in err and not out.exists()


def test_a_gains_file_with_a_byte_order_mark_is_read_and_one_not_utf8_is_named(tmp_path, capsys, gains, clean):
    text = gains.read_bytes()
    bom = tmp_path / "bom.json"
    bom.write_bytes(b"\xef\xbb\xbf" + text)
    assert cli.main(["track", str(clean), "--gains-file", str(bom), "-o", str(tmp_path / "a.csv")]) == 0
    latin = tmp_path / "latin.json"
    latin.write_bytes(text.replace(b'"format"', b'"f\xe4rmat"', 1))
    out = tmp_path / "b.csv"
    err = refused(capsys, "track", clean, "--gains-file", latin, "-o", out, flag="--gains-file")
    assert "latin.json: not UTF-8 text (byte 0xe4" in err and not out.exists()


def test_a_file_in_the_way_of_an_output_directory_is_named(tmp_path, capsys, gains, clean):
    in_the_way = tmp_path / "afile"
    in_the_way.write_text("keep")
    for args, flag in [
        (["track", clean, "--gains-file", gains, "-o", in_the_way / "deeper" / "x.csv"], "--output"),
        (["plot", clean, "--out", in_the_way], "--out"),
        (["report", "--out", in_the_way, "--no-plots"], "--out"),
    ]:
        err = refused(capsys, *args, flag=flag)
        assert f"{in_the_way} is a file, not a directory" in err, err
    assert in_the_way.read_text() == "keep"
