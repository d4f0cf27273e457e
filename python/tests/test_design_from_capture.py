"""`angletrack design --from-capture` and `angletrack.design_from_capture`: the doors of the
Rust crate's design from a capture (its estimates and choice are checked against the
generator in crates/angletrack/tests/design_from_capture.rs). Here: the tracker file written
with its prediction, the counts and no-reference paths, the plot, and the refusals."""

import json
import math

import numpy as np
import pytest

import angletrack
from angletrack import capture, cli

RATE_HZ = 10_000.0


def write_capture(path, n=20_000, reference=True, counts=False, noise=0.01):
    """A shaft at 300 rad/s with a slow speed ripple, white noise per channel."""
    rng = np.random.default_rng(5)
    t = np.arange(n) / RATE_HZ
    theta = 0.3 + 300.0 * t + 0.2 * np.sin(20.0 * t)
    y_c = np.cos(theta) + noise * rng.standard_normal(n)
    y_s = np.sin(theta) + noise * rng.standard_normal(n)
    if counts:
        y_c, y_s = np.round(2048 + 1800 * y_c).astype(np.int64), np.round(2048 + 1800 * y_s).astype(np.int64)
    columns = {"time": t, "y_c": y_c, "y_s": y_s}
    if reference:
        columns["reference"] = theta
    capture.write_capture(path, columns)


def test_the_tracker_file_holds_the_printed_prediction_and_tracks(tmp_path, capsys):
    cap, out = tmp_path / "capture.csv", tmp_path / "t.json"
    write_capture(cap)
    assert cli.main(["design", "--from-capture", str(cap), "--grid-points", "8", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    document = json.loads(out.read_text())
    predicted = document["predicted_error_rms_rad"]
    assert f"predicted_error_rms_rad {predicted:.4g}" in printed
    assert "motion from the reference column" in printed and "runner-up" in printed
    assert document["number_type"] == "f32" and document["design"]["method"] == "design from a capture"
    # The noise read back within 5 % of the 1 % written.
    assert abs(document["design"]["noise_std"] / 0.01 - 1) < 0.05
    estimates = tmp_path / "e.csv"
    assert cli.main(["track", str(cap), "--tracker", str(out), "-o", str(estimates)]) == 0


def test_counts_without_a_reference_are_quantised_and_read_from_the_signals(tmp_path, capsys):
    cap, out = tmp_path / "counts.csv", tmp_path / "t.json"
    write_capture(cap, reference=False, counts=True, noise=0.002)
    assert cli.main(["design", "--from-capture", str(cap), "--grid-points", "8", "--dtype", "fixed",
                     "--quantisation-step", "1", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "motion from the signals' own angle" in printed and "quantisation" in printed
    document = json.loads(out.read_text())
    assert document["number_type"] == "fixed" and document["input"]["kind"] == "counts"
    assert document["design"]["motion_from_reference"] is False


def test_the_plot_is_drawn(tmp_path, capsys):
    cap, png = tmp_path / "capture.csv", tmp_path / "d.png"
    write_capture(cap)
    assert cli.main(["design", "--from-capture", str(cap), "--grid-points", "6", "--plot", str(png)]) == 0
    assert png.stat().st_size > 10_000


def test_python_returns_the_design_the_estimates_and_the_candidates():
    t = np.arange(20_000) / RATE_HZ
    theta = 300.0 * t
    rng = np.random.default_rng(2)
    y_c = np.cos(theta) + 0.01 * rng.standard_normal(t.size)
    y_s = np.sin(theta) + 0.01 * rng.standard_normal(t.size)
    result = angletrack.design_from_capture(y_c, y_s, 1 / RATE_HZ, reference_angle_rad=theta, grid_points=6,
                                            number_type="f64")
    assert isinstance(result["design"], angletrack.Design)
    assert result["design"].gains.gains == result["chosen"]["gains"]
    assert len(result["candidates"]) == 18 and len(result["runners_up"]) == 2
    parts = result["chosen"]
    assert math.isclose(parts["predicted_error_rms_rad"] ** 2,
                        parts["noise_rad"] ** 2 + parts["lag_rad"] ** 2 + parts["number_type_rad"] ** 2, rel_tol=1e-9)
    assert len(result["spectra"]["frequency_hz"]) == len(result["spectra"]["noise_rad2_per_hz"])
    # Without a reference and with white noise of 0.01: the autocovariance least-squares
    # estimate is there, its noise the phase detector's (0.01 of the amplitude).
    unreferenced = angletrack.design_from_capture(y_c, y_s, 1 / RATE_HZ, grid_points=6, number_type="f64")
    als = unreferenced["als"]
    assert als is not None and als["lags"] > 0 and als["first_pass_bandwidth_hz"] > 0
    assert abs(als["noise_std"]["value"] - 0.01) < 5e-4, als
    assert unreferenced["motion"]["jerk_by_differences_rad_s3"]["value"] > 0


@pytest.mark.parametrize("kwargs, parameter", [
    ({"number_type": "f16"}, "number_type"),
    ({"max_overshoot": -0.1}, "max_overshoot"),
    ({"grid_points": 1}, "grid_points"),
    ({"grid_points": -3}, "grid_points"),
])
def test_python_refusals_name_the_argument(kwargs, parameter):
    theta = np.arange(5000) * 0.01
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.design_from_capture(np.cos(theta), np.sin(theta), 1e-4, **kwargs)
    assert e.value.parameter == parameter and str(e.value).startswith(parameter)


@pytest.mark.parametrize("n, speed, reference, message", [
    (500, 300.0, False, "capture too short: 500 samples, at least 2000 needed"),
    (5000, 0.0, True, "capture at standstill"),
    (5000, 0.0, False, "cos and sin do not trace the Lissajous ellipse"),
    (5000, 10.0, False, "capture with too few turns"),
])
def test_a_capture_that_cannot_support_the_estimates_is_refused_in_one_line(tmp_path, capsys, n, speed, reference,
                                                                            message):
    cap = tmp_path / "capture.csv"
    t = np.arange(n) / RATE_HZ
    noise = 0.01 * np.random.default_rng(1).standard_normal((2, n))
    columns = {"time": t, "y_c": np.cos(speed * t) + noise[0], "y_s": np.sin(speed * t) + noise[1]}
    if reference:
        columns["reference"] = speed * t
    capture.write_capture(cap, columns)
    status = cli.main(["design", "--from-capture", str(cap), "-o", str(tmp_path / "t.json")])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "t.json").exists()


def test_an_observer_with_from_capture_is_refused(tmp_path, capsys):
    cap = tmp_path / "capture.csv"
    write_capture(cap, n=3000)
    assert cli.main(["design", "kalman", "--from-capture", str(cap)]) == 2
    assert "observer: kalman given with --from-capture" in capsys.readouterr().err


def test_the_guide_capture_measures_what_was_predicted(tmp_path, capsys):
    """docs/guide/design-from-capture.md's commands: the calibrated tracker measures within
    10 % of the prediction, both near the 0.22 mrad the page quotes."""
    from test_guide import write_capture as write_guide_capture

    cap, tracker, calibrated = tmp_path / "capture.csv", tmp_path / "t.json", tmp_path / "c.json"
    write_guide_capture(cap)
    assert cli.main(["design", "--from-capture", str(cap), "-o", str(tracker)]) == 0
    predicted = json.loads(tracker.read_text())["predicted_error_rms_rad"]
    assert cli.main(["calibrate", str(cap), "--tracker", str(tracker), "-o", str(calibrated)]) == 0
    capsys.readouterr()
    assert cli.main(["track", str(cap), "--tracker", str(calibrated), "--skip", "0.05",
                     "-o", str(tmp_path / "e.csv")]) == 0
    line = next(li for li in capsys.readouterr().out.splitlines() if li.strip().startswith("RMS "))
    measured = float(line.split()[1])
    assert abs(measured / predicted - 1) < 0.10, (measured, predicted)
    assert 0.11e-3 < predicted < 0.44e-3


def test_a_specification_with_from_capture_is_refused(tmp_path, capsys):
    cap = tmp_path / "capture.csv"
    write_capture(cap, n=3000)
    assert cli.main(["design", "--from-capture", str(cap), "--bandwidth", "100"]) == 2
    assert "--bandwidth: not used with --from-capture" in capsys.readouterr().err
