"""Issue 21: ``angletrack calibrate`` on captures in any unit (int16 counts of amplitude
1800, volts of amplitude 0.455), and ``angletrack track --dtype fixed --calibration`` on
int16 counts: the stored calibration applied in integers by the fixed-point chain
(``FixedCalibration``, ``FixedAngleCorrectionTable``); ``FixedObserver`` with its stages."""

import math

import numpy as np
import pytest

import angletrack
from angletrack import calibration, capture, cli, harmonics

SAMPLE_RATE_HZ = 20_000.0
SPEED_RAD_S = 2 * math.pi * 200.0  # 200 electrical turns per second


def sensor_capture(path, *, amplitude, duration_s=0.25, ripple=0.0, integers=True, seed=1):
    """The issue's sensor at ``amplitude``: offsets 2 %, imbalance 3 %, quadrature 0.01 rad, a
    3rd and a 4th harmonic of 4 and 3 mrad, noise 0.1 % of the amplitude, at 200 turns/s
    (with a speed ripple of ``ripple``); int16 counts when ``integers``. Written with the
    reference angle; returns the truth."""
    t = np.arange(int(duration_s * SAMPLE_RATE_HZ)) / SAMPLE_RATE_HZ
    theta = 0.3 + SPEED_RAD_S * t - ripple * SPEED_RAD_S / (2 * math.pi * 5.0) * np.cos(2 * math.pi * 5.0 * t)
    read = theta + 4e-3 * np.sin(3 * theta + 0.3) + 3e-3 * np.sin(4 * theta + 1.1)
    rng = np.random.default_rng(seed)
    y_c = amplitude * (0.02 + np.cos(read) + 1e-3 * rng.normal(size=len(t)))
    y_s = amplitude * (-0.02 + 1.03 * np.sin(read + 0.01) + 1e-3 * rng.normal(size=len(t)))
    if integers:
        y_c, y_s = np.round(y_c).astype(np.int16), np.round(y_s).astype(np.int16)
    reference = np.remainder(theta + math.pi, 2 * math.pi) - math.pi
    if integers:
        # Counts as a recorder writes them: whole numbers in the text.
        np.savetxt(path, np.column_stack([t, y_c, y_s, reference]), fmt=["%.17g", "%d", "%d", "%.17g"],
                   delimiter=",", header="time,y_c,y_s,reference", comments="")
    else:
        capture.write_capture(path, {"time": t, "y_c": y_c, "y_s": y_s, "reference": reference})
    return theta


@pytest.fixture(scope="module")
def gains_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("fixed_calibration") / "g.json"
    assert cli.main(["design", "third-order", "--sample-rate", str(SAMPLE_RATE_HZ), "--butterworth-time-constant",
                     "2e-3", "--format", "json", "--output", str(path)]) == 0
    return path


def rms_of(printed):
    return float(printed.split("RMS ")[1].split()[0])


@pytest.mark.parametrize("amplitude, integers", [(1800.0, True), (0.455, False), (1.0, False)])
def test_calibrate_learns_the_same_harmonics_in_any_unit(tmp_path, gains_file, capsys, amplitude, integers):
    cap, out = tmp_path / "cap.csv", tmp_path / "cal.json"
    sensor_capture(cap, amplitude=amplitude, integers=integers)
    status = cli.main(["calibrate", str(cap), "--gains-file", str(gains_file), "--output", str(out)])
    printed = capsys.readouterr()
    assert status == 0, printed.err
    cal = harmonics.Calibration.from_json(out.read_text())
    print(f"amplitude {amplitude}: 3rd {cal.harmonic_amplitude(3):.4e}, 4th {cal.harmonic_amplitude(4):.4e}, "
          f"offset_c {cal.sensor[0] / amplitude:.4f}")
    # Measured: 4.032e-3 and 2.977e-3 rad at 1800 counts, 4.029e-3 and 2.970e-3 in volts and
    # normalised (the counts' rounding the only difference).
    assert cal.harmonic_amplitude(3) == pytest.approx(4e-3, abs=2e-4)
    assert cal.harmonic_amplitude(4) == pytest.approx(3e-3, abs=2e-4)
    # The offsets in the capture's units.
    assert cal.sensor[0] / amplitude == pytest.approx(0.02, abs=2e-3)


def test_track_fixed_applies_the_stored_calibration_in_integers(tmp_path, gains_file, capsys):
    learning, test, cal = tmp_path / "learn.csv", tmp_path / "test.csv", tmp_path / "cal.json"
    sensor_capture(learning, amplitude=1800.0)
    sensor_capture(test, amplitude=1800.0, duration_s=0.5, ripple=0.05, seed=2)
    assert cli.main(["calibrate", str(learning), "--gains-file", str(gains_file), "--output", str(cal)]) == 0
    base = ["track", str(test), "--gains-file", str(gains_file), "--skip", "0.1", "--dtype", "fixed"]
    capsys.readouterr()
    assert cli.main(base + ["--output", str(tmp_path / "plain.csv")]) == 0
    plain = capsys.readouterr().out
    assert cli.main(base + ["--calibration", str(cal), "--output", str(tmp_path / "fixed.csv")]) == 0
    fixed = capsys.readouterr().out
    assert "FixedAngleCorrectionTable" in fixed and "shifted left by 3 bits" in fixed, fixed
    assert cli.main(["track", str(test), "--gains-file", str(gains_file), "--skip", "0.1", "--calibration", str(cal),
                     "--output", str(tmp_path / "float.csv")]) == 0
    floating = capsys.readouterr().out
    assert cli.main(["track", str(test), "--gains-file", str(gains_file), "--skip", "0.1", "--calibration", str(cal),
                     "--dtype", "float32", "--output", str(tmp_path / "float32.csv")]) == 0
    single = capsys.readouterr().out
    assert "(f32, " in single and rms_of(single) < rms_of(floating) + 1e-4, single
    print(f"RMS: plain fixed {rms_of(plain):.3e}, fixed calibrated {rms_of(fixed):.3e}, float64 calibrated "
          f"{rms_of(floating):.3e}, float32 calibrated {rms_of(single):.3e}")
    # Measured: 1.68e-02 rad RMS without the calibration, 4.30e-04 with it in fixed point,
    # 4.27e-04 in float64 (the noise and the speed ripple's lag).
    assert rms_of(plain) > 5e-3, plain
    assert rms_of(fixed) < 1e-3, fixed
    assert rms_of(fixed) < rms_of(floating) + 2e-4, (fixed, floating)
    data = np.genfromtxt(tmp_path / "fixed.csv", delimiter=",", names=True)
    assert data.dtype.names[:2] == ("time_s", "angle_rad") and np.all(data["faults"][len(data) // 2:] == 0)
    # The same run as .npz and .npy: the firmware's binary angle as int32, the faults as uint8, the
    # values those of the CSV (whose floats read back exactly).
    for suffix in (".npz", ".npy"):
        assert cli.main(base + ["--calibration", str(cal), "--output", str(tmp_path / f"fixed{suffix}")]) == 0
    capsys.readouterr()
    archive, records = np.load(tmp_path / "fixed.npz"), np.load(tmp_path / "fixed.npy")
    assert archive["angle_binary"].dtype == np.int32 and archive["faults"].dtype == np.uint8
    assert records.dtype.names == data.dtype.names
    for name in data.dtype.names:
        np.testing.assert_array_equal(archive[name], data[name])
        np.testing.assert_array_equal(records[name], data[name])


def test_fixed_observer_takes_the_stages(tmp_path):
    theta = 0.3 + 0.05 * np.arange(4000)
    sensor = angletrack.SensorCalibration(offset_c=36.0, offset_s=-36.0, amplitude_c=1800.0, amplitude_s=1854.0)
    y_c = np.round(36.0 + 1800.0 * np.cos(theta)).astype(np.int16)
    y_s = np.round(-36.0 + 1854.0 * np.sin(theta)).astype(np.int16)
    design = angletrack.third_order_butterworth(2e-3, 5e-5)
    errors = {}
    for name, kwargs in {"plain": {}, "calibrated": {"calibration": sensor, "input_shift": 3}}.items():
        est = angletrack.FixedObserver(design, **kwargs).update(y_c, y_s)
        error = np.remainder(est.position_rad - theta + math.pi, 2 * math.pi) - math.pi
        errors[name] = float(np.sqrt(np.mean(error[2000:] ** 2)))
    print(errors)
    # Measured: 1.03e-2 rad RMS without the stage, 3.3e-5 with it.
    assert errors["plain"] > 1e-2 and errors["calibrated"] < 1e-3, errors
    with pytest.raises(ValueError, match="calibration"):
        angletrack.FixedObserver(design, calibration=3)
    with pytest.raises(angletrack.ConfigError):
        angletrack.FixedObserver(design, input_shift=16)


@pytest.mark.parametrize(
    "extra, expected",
    [
        (["--calibrate"], ["--dtype fixed", "--calibrate"]),
        (["--sin-cos", "fast"], ["--dtype fixed", "--sin-cos"]),
        (["--carrier-hz", "1000"], ["--dtype fixed", "--carrier-hz"]),
    ],
)
def test_track_fixed_refuses_in_one_line_naming_both_flags(tmp_path, gains_file, capsys, extra, expected):
    cap = tmp_path / "cap.csv"
    sensor_capture(cap, amplitude=1800.0, duration_s=0.01)
    capsys.readouterr()
    assert cli.main(["track", str(cap), "--gains-file", str(gains_file), "--dtype", "fixed"] + extra) == 2
    err = capsys.readouterr().err
    assert all(e in err for e in expected) and len(err.strip().splitlines()) == 1, err


def test_track_fixed_refuses_samples_that_are_not_counts(tmp_path, gains_file, capsys):
    cap = tmp_path / "volts.csv"
    sensor_capture(cap, amplitude=0.455, duration_s=0.01, integers=False)
    assert cli.main(["track", str(cap), "--gains-file", str(gains_file), "--dtype", "fixed"]) == 2
    err = capsys.readouterr().err
    assert "--dtype fixed" in err and "integer" in err and len(err.strip().splitlines()) == 1, err
    assert calibration.FORMAT
