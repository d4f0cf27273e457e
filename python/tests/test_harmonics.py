"""Angle-dependent error calibration (issue's "Done when"): `angletrack calibrate` on a
50-turn capture of the harmonic sensor, then `angletrack track --calibration` on another
capture of it with a +-5 % speed ripple, below 0.5 mrad RMS against the reference."""

import json
import math
import shutil
import subprocess

import numpy as np
import pytest

import angletrack
from angletrack import capture, cli, export, harmonics

SAMPLE_PERIOD_S = 5e-5
SPEED_RAD_S = 2 * math.pi * 200.0


def harmonic_sensor():
    return angletrack.SensorModel(
        offset_cos=0.05, offset_sin=-0.05, amplitude_imbalance=0.05, quadrature_error_rad=0.02,
        angle_error_harmonics=[(3, 5e-3, 0.3), (4, 5e-3, 1.1)], noise_std=1e-3,
    )


def gains():
    return angletrack.third_order_butterworth(2e-3, SAMPLE_PERIOD_S).gains


def scenario(profile, seed):
    return angletrack.Scenario.generate(profile, harmonic_sensor(), sample_period_s=SAMPLE_PERIOD_S, seed=seed)


def learning_capture(seed=1):
    return scenario(angletrack.MotionProfile(0.0, SPEED_RAD_S).constant_speed(SPEED_RAD_S, 50 / 200), seed)


def rippling_capture(seed=2):
    profile = angletrack.MotionProfile(0.0, SPEED_RAD_S).speed_ripple(0.05 * SPEED_RAD_S, 2.0, 1.0)
    return scenario(profile, seed)


def write(path, s):
    capture.write_capture(path, {"time": s.time_s, "y_c": s.y_c, "y_s": s.y_s, "reference": s.angle_rad})


def wrapped_rms_after_mean(angle, reference, skip):
    e = np.angle(np.exp(1j * (angle[skip:] - reference[skip:])))
    return float(np.sqrt(np.mean((e - e.mean()) ** 2)))


def test_sensor_model_names_and_checks_its_angle_error_harmonics():
    sensor = harmonic_sensor()
    assert sensor.angle_error_harmonics[:2] == [(3, 5e-3, 0.3), (4, 5e-3, 1.1)]
    with pytest.raises(ValueError, match="angle_error_harmonics"):
        angletrack.SensorModel(angle_error_harmonics=[(k, 1e-3, 0.0) for k in range(1, 10)])
    bad = angletrack.SensorModel(angle_error_harmonics=[(3, float("nan"), 0.0)])
    with pytest.raises(ValueError, match="angle_error_harmonics"):
        angletrack.Scenario.generate(angletrack.MotionProfile(0.0, 1.0).constant_speed(1.0, 0.01), bad,
                                     sample_period_s=1e-4)


def test_calibrate_learns_the_harmonics_and_the_json_round_trips():
    s = learning_capture()
    cal = angletrack.calibrate(s.y_c, s.y_s, gains())
    assert cal.harmonic_amplitude(3) == pytest.approx(5e-3, abs=2e-4)
    assert cal.harmonic_amplitude(4) == pytest.approx(5e-3, abs=2e-4)
    assert cal.sensor[0] == pytest.approx(0.05, abs=2e-3)
    assert angletrack.Calibration.from_json(cal.to_json()) == cal
    with pytest.raises(ValueError, match="calibration file"):
        angletrack.Calibration.from_json(json.dumps({"format": "angletrack-calibration", "version": 1}))


def test_a_capture_too_slow_for_the_gains_is_learned_with_the_calibrations_own_loop():
    # 15 turns/s: the gains' loop follows orders 1 to 3; asked for order 3 with them, the
    # error names the option and the lowest learnable order; the own loop learns it.
    profile = angletrack.MotionProfile(0.0, 2 * math.pi * 15).constant_speed(2 * math.pi * 15, 1.0)
    s = scenario(profile, 3)
    with pytest.raises(angletrack.ConfigError, match="lowest learnable order is") as refused:
        angletrack.calibrate(s.y_c, s.y_s, gains(), own_loop=False, lowest_order=3)
    assert refused.value.parameter == "lowest_order"
    chosen = angletrack.calibrate(s.y_c, s.y_s, gains(), own_loop=False)
    assert chosen.method == "self, the gains' loop" and chosen.orders[2]["status"] == "within the loop's bandwidth"
    own = angletrack.calibrate(s.y_c, s.y_s, gains())
    assert own.method == "self, own loop" and own.orders[2]["status"] == "learned"
    assert own.harmonic_amplitude(3) == pytest.approx(5e-3, abs=3e-4)


def test_track_calibrated_in_python_is_below_half_a_milliradian():
    learn, test = learning_capture(), rippling_capture()
    cal = angletrack.calibrate(learn.y_c, learn.y_s, gains())
    est = angletrack.track_calibrated(gains(), test.y_c, test.y_s, cal)
    plain = angletrack.track(gains(), test.y_c, test.y_s)
    skip = len(test) // 2
    corrected = wrapped_rms_after_mean(est.angle, test.angle_rad, skip)
    assert corrected < 5e-4
    assert wrapped_rms_after_mean(plain.angle, test.angle_rad, skip) > 2 * corrected


def test_cli_calibrate_then_track_with_calibration_below_half_a_milliradian(tmp_path, capsys):
    cap1, cap2 = tmp_path / "cap1.csv", tmp_path / "cap2.csv"
    write(cap1, learning_capture())
    test = rippling_capture()
    write(cap2, test)
    gains_file, cal_file, out = tmp_path / "g.json", tmp_path / "cal.json", tmp_path / "est.csv"
    gains_file.write_text(export.to_json(gains()))
    assert cli.main([str(a) for a in ("calibrate", cap1, "--gains-file", gains_file, "--output", cal_file)]) == 0
    assert capsys.readouterr().out.startswith("calibrated against the reference: 50 turns")
    assert cli.main([str(a) for a in ("track", cap2, "--gains-file", gains_file, "--calibration", cal_file,
                                       "--output", out, "--skip", 0.5)]) == 0
    printed = capsys.readouterr().out
    # The printed RMS includes the mean (a constant angle offset, which no reference-free
    # calibration can see): the target is the RMS after removing it.
    rms = float(printed.split("RMS ")[1].split()[0])
    mean = float(printed.split("mean ")[1].split()[0])
    assert math.sqrt(rms**2 - mean**2) < 5e-4, printed
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert wrapped_rms_after_mean(data["angle_rad"], test.angle_rad, len(test) // 2) < 5e-4
    # --calibrate beside an angle calibration is refused in one line, before anything is written.
    refused_out = tmp_path / "refused.csv"
    assert cli.main([str(a) for a in ("track", cap2, "--gains-file", gains_file, "--calibration", cal_file,
                                       "--calibrate", "--output", refused_out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("angletrack: error: calibration:") and "--calibrate" in err and err.count("\n") == 1
    assert not refused_out.exists()


def test_cli_calibrate_names_a_reference_that_runs_opposite_at_other_pole_pairs_and_takes_it_stated(tmp_path, capsys):
    # A mechanical encoder counting the other way on a 2-pole-pair sensor, its zero 0.7 rad
    # from the sensor's: refused naming --reference-ratio; stated, the harmonics are learned
    # as against the sensor's own reference (the offset taken as the reference's zero).
    s = learning_capture()
    cap, cal_file, gains_file = tmp_path / "mech.csv", tmp_path / "cal.json", tmp_path / "g.json"
    gains_file.write_text(export.to_json(gains()))
    mechanical = np.remainder(0.7 - s.angle_rad / 2, 2 * math.pi)
    capture.write_capture(cap, {"time": s.time_s, "y_c": s.y_c, "y_s": s.y_s, "reference": mechanical})
    base = ["calibrate", str(cap), "--gains-file", str(gains_file), "--output", str(cal_file)]
    capsys.readouterr()
    assert cli.main(base) == 2
    err = capsys.readouterr().err
    assert err.startswith("angletrack: error: reference:") and "--reference-ratio" in err and err.count("\n") == 1, err
    assert cli.main(base + ["--reference-ratio", "-2"]) == 0
    assert capsys.readouterr().out.startswith("calibrated against the reference")
    stated = json.loads(cal_file.read_text())
    write(cap, s)
    assert cli.main(base) == 0
    own = json.loads(cal_file.read_text())
    for key in ("cos", "sin"):
        np.testing.assert_allclose(stated[key], own[key], rtol=0, atol=2e-5)
    with pytest.raises(SystemExit) as exit_:
        cli.main(base + ["--reference-ratio", "0"])
    assert exit_.value.code == 2 and "--reference-ratio" in capsys.readouterr().err


def test_cli_calibrate_errors_name_the_flags_in_one_line(tmp_path, capsys):
    cap = tmp_path / "slow.csv"
    write(cap, scenario(angletrack.MotionProfile(0.0, 2 * math.pi * 15).constant_speed(2 * math.pi * 15, 1.0), 4))
    gains_file = tmp_path / "g.json"
    gains_file.write_text(export.to_json(gains()))
    base = ["calibrate", str(cap), "--gains-file", str(gains_file)]
    for extra, flag in ((["--self", "--loop", "gains", "--lowest-order", "2"], "--lowest-order"),
                        (["--lowest-order", "9"], "--lowest-order"),
                        (["--self", "--settle-fraction", "0.9"], "--settle-fraction")):
        assert cli.main(base + extra) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"angletrack: error: {flag}:") and err.count("\n") == 1, err
    short = tmp_path / "short.csv"
    write(short, scenario(angletrack.MotionProfile(0.0, SPEED_RAD_S).constant_speed(SPEED_RAD_S, 3 / 200), 3))
    assert cli.main(["calibrate", str(short), "--gains-file", str(gains_file)]) == 2
    err = capsys.readouterr().err
    assert "at least 5" in err and err.count("\n") == 1, err


def test_cli_self_calibration_reports_each_order_with_its_uncertainty(tmp_path, capsys):
    cap, cal_file = tmp_path / "cap.csv", tmp_path / "cal.json"
    write(cap, learning_capture())
    gains_file = tmp_path / "g.json"
    gains_file.write_text(export.to_json(gains()))
    assert cli.main([str(a) for a in ("calibrate", cap, "--gains-file", gains_file, "--self", "-o", cal_file)]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("calibrated by self, own loop: 39 turns"), printed
    document = json.loads(cal_file.read_text())
    assert document["method"] == "self, own loop"
    orders = {o["order"]: o for o in document["orders"]}
    assert [orders[k]["status"] for k in (1, 2, 3, 4)] == ["not requested", "not requested", "learned", "learned"]
    # 40 turns of 100 samples after the settling, 1e-3 of angle noise: about
    # 1e-3 sqrt(2 / 4000) = 2.2e-5 rad per coefficient.
    for k in range(1, 9):
        assert 1e-5 < orders[k]["uncertainty_rad"] < 5e-5, orders[k]
    assert all(orders[k]["status"] != "learned" for k in range(5, 13))
    cal = harmonics.Calibration.from_json(cal_file.read_text())
    assert cal.orders[2]["status"] == "learned" and cal.warnings == ()
    assert "    3" in printed and "not significant" in printed


def test_calibration_c_header_compiles_and_rust_block_has_the_constants(tmp_path):
    s = learning_capture()
    cal = angletrack.calibrate(s.y_c, s.y_s, gains())
    header = tmp_path / "rdc_calibration.h"
    header.write_text(cal.to_c_header(name="rdc"))
    source = tmp_path / "use.c"
    source.write_text('#include "rdc_calibration.h"\n'
                      "float third(void) { return rdc_angle_cos[2] + rdc_angle_sin[2] + rdc_sensor[0]; }\n")
    cc = shutil.which("cc")
    assert cc is not None, "a C compiler (cc) is needed for this test"
    subprocess.run([cc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-c", str(source), "-o", str(tmp_path / "u.o")],
                   check=True, cwd=tmp_path)
    rust = cal.to_rust(name="rdc")
    assert "pub const RDC_ANGLE_COS: [f32; 8]" in rust and "pub const RDC_SENSOR: (f32, f32, f32, f32, f32)" in rust


def test_track_reads_the_calibration_file_once_and_tells_its_kind(tmp_path, capsys, file_reads):
    from angletrack import calibration

    cap = tmp_path / "cap.csv"
    write(cap, rippling_capture())
    gains_file, cal_file = tmp_path / "g.json", tmp_path / "cal.json"
    gains_file.write_text(export.to_json(gains()))
    cal_file.write_text(angletrack.calibrate(learning_capture().y_c, learning_capture().y_s, gains()).to_json())
    assert cli.main([str(a) for a in ("track", cap, "--gains-file", gains_file, "--calibration", cal_file,
                                       "-o", tmp_path / "est.npy")]) == 0
    assert file_reads.count("cal.json") == 1
    assert "stored calibration (SensorCalibration) and angle correction (AngleCorrection, harmonics)" in (
        capsys.readouterr().out.splitlines()[0])
    # The two kinds of calibration file, and the arguments each gives the observer.
    stored = calibration.read_stored(cal_file)
    assert isinstance(stored, angletrack.Calibration) and calibration.angle_calibration(stored) is stored
    assert calibration.observer_arguments(False, stored) == {}
    sensor_file = tmp_path / "sensor.json"
    calibration.write(sensor_file, harmonic_sensor().calibration())
    sensor = calibration.read_stored(sensor_file)
    assert isinstance(sensor, angletrack.SensorCalibration) and calibration.angle_calibration(sensor) is None
    assert calibration.observer_arguments(False, sensor) == {"calibration": "frozen", "initial_calibration": sensor}
    assert calibration.observer_arguments(True, None) == {"calibration": "learn", "initial_calibration": None}
    # A missing file is one line naming it.
    assert cli.main([str(a) for a in ("track", cap, "--gains-file", gains_file, "--calibration",
                                       tmp_path / "missing.json")]) == 2
    err = capsys.readouterr().err
    assert "missing.json" in err and err.count("\n") == 1


def test_an_angle_calibration_applies_to_the_pairs_of_carrier_modulated_windings(tmp_path):
    from angletrack import harmonics, resolver, tracking

    cal = angletrack.calibrate(learning_capture().y_c, learning_capture().y_s, gains())
    settings = tracking.TrackSettings(capture=tmp_path / "windings.csv", output=tmp_path / "est.csv",
                                      gains=gains().gains, carrier_hz=1e3, calibration=cal)
    # The demodulated pairs go through the same stages as y_c, y_s samples (issue 21).
    observer = resolver.pairs_observer(settings, gains(), None)
    assert isinstance(observer, harmonics.CalibratedObserver) and observer.calibration is cal


def int16_capture(path, duration_s, seed):
    """The harmonic sensor in int16 counts of amplitude 1800 on the 20 kHz clock, with its
    reference angle; returns the truth."""
    s = scenario(angletrack.MotionProfile(0.0, SPEED_RAD_S).constant_speed(SPEED_RAD_S, duration_s), seed)
    y_c, y_s = np.round(1800 * s.y_c).astype(np.int16), np.round(1800 * s.y_s).astype(np.int16)
    reference = np.remainder(s.angle_rad + math.pi, 2 * math.pi) - math.pi
    np.savetxt(path, np.column_stack([s.time_s, y_c, y_s, reference]), fmt=["%.17g", "%d", "%d", "%.17g"],
               delimiter=",", header="time,y_c,y_s,reference", comments="")
    return s


@pytest.mark.parametrize("dtype", ["float64", "fixed"])
def test_calibrate_int16_counts_then_track_below_half_a_milliradian(tmp_path, capsys, dtype):
    # Issue 23: calibrated against the reference on one capture of counts, tracked on a
    # second, the RMS after the mean below 0.5 mrad in float64 and in integers.
    learning, test, cal = tmp_path / "learn.csv", tmp_path / "test.csv", tmp_path / "cal.json"
    int16_capture(learning, 0.25, 1)
    truth = int16_capture(test, 0.5, 2)
    gains_file = tmp_path / "g.json"
    gains_file.write_text(export.to_json(gains()))
    assert cli.main(["calibrate", str(learning), "--gains-file", str(gains_file), "-o", str(cal)]) == 0
    assert capsys.readouterr().out.startswith("calibrated against the reference")
    out = tmp_path / "est.csv"
    assert cli.main(["track", str(test), "--gains-file", str(gains_file), "--calibration", str(cal), "--dtype", dtype,
                     "--output", str(out)]) == 0
    data = np.genfromtxt(out, delimiter=",", names=True)
    rms = wrapped_rms_after_mean(data["angle_rad"], truth.angle_rad, len(truth) // 2)
    plain = tmp_path / "plain.csv"
    assert cli.main(["track", str(test), "--gains-file", str(gains_file), "--dtype", dtype, "--output",
                     str(plain)]) == 0
    uncorrected = wrapped_rms_after_mean(np.genfromtxt(plain, delimiter=",", names=True)["angle_rad"],
                                         truth.angle_rad, len(truth) // 2)
    print(f"{dtype}: {rms:.3e} rad RMS calibrated, {uncorrected:.3e} without")
    assert rms < 5e-4 and uncorrected > 1e-2


def test_calibrate_chunks_equals_calibrate_in_memory_and_old_files_read_as_unknown():
    s = learning_capture()
    whole = angletrack.calibrate(s.y_c, s.y_s, gains(), reference=s.angle_rad)
    chunked = harmonics.calibrate_chunks(
        lambda: ((s.y_c[k:k + 777], s.y_s[k:k + 777], s.angle_rad[k:k + 777]) for k in range(0, len(s), 777)), gains())
    assert chunked.method == whole.method == "reference"
    assert np.allclose(chunked.cos, whole.cos, rtol=0, atol=1e-12)
    assert chunked.orders[2]["uncertainty_rad"] == pytest.approx(whole.orders[2]["uncertainty_rad"], rel=1e-9)
    old = json.loads(whole.to_json())
    for key in ("method", "orders", "warnings"):
        del old[key]
    read = harmonics.Calibration.from_json(json.dumps(old))
    assert read.method == "unknown" and all(o["status"] == "unknown" for o in read.orders)
    assert read.cos == whole.cos
