"""The resolver front end from Python (docs/theory.md §13): the demodulator, the scenario
generator's windings and the drive outputs through the binding, and ``angletrack track
--carrier-hz`` end to end on the issue's reference front end."""

import math

import numpy as np
import pytest

import angletrack
from angletrack import capture, cli

CARRIER_HZ = 10_000.0
SPEED_RAD_S = 50.0 * 2 * math.pi  # 50 rev/s
DELAY_RAD = math.radians(305.0)


def windings(duration_s=0.05, delay_rad=DELAY_RAD, seed=1):
    """A 10 kHz carrier sampled at 160 kHz by a 12-bit ADC, amplitude 1800 counts, noise
    1 LSB, at a constant 50 rev/s."""
    profile = angletrack.MotionProfile(0.3, SPEED_RAD_S).constant_speed(SPEED_RAD_S, duration_s)
    model = angletrack.ResolverModel(carrier_delay_rad=delay_rad)
    return angletrack.resolver_windings(profile, model, seed=seed), model


def write_raw(path, scenario):
    capture.write_capture(path, {"time": scenario.time_s, "y_c": scenario.y_c, "y_s": scenario.y_s,
                                 "reference": scenario.angle_rad})


def design_gains(path, sample_rate_hz):
    status = cli.main(["design", "kalman", "--sample-rate", str(sample_rate_hz), "--jerk-std", "1e6",
                       "--noise-std", "2e-4", "--format", "json", "--output", str(path)])
    assert status == 0


def test_resolver_windings_are_the_reference_front_end():
    scenario, model = windings(duration_s=0.01)
    assert model.amplitude_counts == 1800.0 and model.adc_sample_period_s == pytest.approx(1 / 160e3)
    assert len(scenario) == 1601 and scenario.sample_period_s == pytest.approx(1 / 160e3)
    assert np.all((scenario.y_c >= 0) & (scenario.y_c <= 4095)) and np.all(scenario.y_c == np.round(scenario.y_c))


def test_demodulator_estimates_the_delay_and_stamps_the_window_centres():
    scenario, model = windings(duration_s=0.01)
    pairs, demodulator = angletrack.demodulate(
        scenario.y_c, scenario.y_s, carrier_hz=CARRIER_HZ, samples_per_period=16,
        carrier_amplitude_counts=model.amplitude_counts, expected_delay_rad=DELAY_RAD,
    )
    # The delay modulo 360 degrees, within 3 degrees in 10 ms (docs/theory.md §13).
    error = math.remainder(demodulator.carrier_delay_rad - DELAY_RAD, 2 * math.pi)
    assert abs(error) < math.radians(3.0)
    assert demodulator.pair_period_s == pytest.approx(1e-4)
    # The loop's frequency, noisy at its bandwidth of about 0.2 f_c: within 0.1 %.
    assert demodulator.tracked_carrier_hz == pytest.approx(1e4, rel=1e-3)
    # The first pair after the 23 start-up windows; at 16 samples a period each holds at the
    # centroid of its trapezoid window (a period and the quarters around it: 20 samples, the
    # centroid 9.5 after the first) to within the loop's phase noise (measured: 0.002
    # samples), the windows cut at the tracked carrier's phase, one period apart; the 77th
    # window, cut there with the carrier 305 degrees behind phase 0, ends past the 1601
    # samples.
    assert pairs.window[0] == 23 and len(pairs) == 100 - 24
    offset = pairs.time_s * 160e3 - 9.5
    np.testing.assert_allclose(offset, np.round(offset), atol=0.01)
    np.testing.assert_allclose(np.diff(pairs.time_s), 1e-4, rtol=1e-3)
    truth = np.interp(pairs.time_s, scenario.time_s, scenario.angle_rad)
    angle = np.arctan2(pairs.y_s, pairs.y_c)
    # Measured 4.9e-4 rad at most.
    assert np.max(np.abs(np.remainder(angle - truth + math.pi, 2 * math.pi) - math.pi)) < 1e-3
    assert np.all(pairs.faults == 0)


def test_demodulator_refuses_an_unsupported_period_naming_it():
    with pytest.raises(ValueError, match="samples_per_period"):
        angletrack.Demodulator(carrier_hz=1e4, samples_per_period=3.5, carrier_amplitude_counts=1800)
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.Demodulator(carrier_hz=1e4, adc_rate_hz=3e4, carrier_amplitude_counts=1800)
    assert e.value.parameter == "adc_rate_hz"
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.Demodulator(carrier_hz=-1.0, samples_per_period=16, carrier_amplitude_counts=1800)
    assert e.value.parameter == "carrier_hz"


def test_drive_outputs_extrapolate_the_electrical_angle():
    gains = angletrack.Gains([0.3, 0.04, 0.002], 1e-4)
    theta = 0.1 + 100.0 * np.arange(2000) * 1e-4
    est = angletrack.track(gains, np.cos(theta), np.sin(theta))
    angles = angletrack.drive_outputs(est, sample_period_s=1e-4, pole_pairs=4, latency_s=60e-6)
    expected = 4 * (theta + 100.0 * 60e-6)
    error = np.remainder(angles.electrical_angle_rad - expected + math.pi, 2 * math.pi) - math.pi
    # Exact to rounding: measured 1.07e-14 rad, under one ulp (1.4e-14) of the unwrapped
    # electrical angle (up to 80 rad).
    assert np.max(np.abs(error[1000:])) < 2.2e-14
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.DriveOutputs(sample_period_s=1e-4, pole_pairs=0)
    assert e.value.parameter == "pole_pairs"
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.DriveOutputs(sample_period_s=1e-4, speed_cutoff_hz=6e3)
    assert e.value.parameter == "speed_cutoff_hz"


def test_track_carrier_follows_the_reference_within_0_2_mrad(tmp_path, capsys):
    scenario, _ = windings()
    raw, gains_file, out = tmp_path / "raw.csv", tmp_path / "g.json", tmp_path / "est.csv"
    write_raw(raw, scenario)
    design_gains(gains_file, 10_000)
    capsys.readouterr()
    status = cli.main(["track", str(raw), "--carrier-hz", "10000", "--gains-file", str(gains_file),
                       "--expected-delay-deg", "305", "--output", str(out), "--skip", "0.02"])
    printed = capsys.readouterr().out
    assert status == 0, printed
    rms = float(printed.split("RMS ")[1].split()[0])
    # Measured: 9.877e-05 rad RMS after 20 ms (the target: below 2 mrad; the design's
    # predicted noise figure at sensor noise 2e-4 is 9.98e-05 rad).
    assert rms < 2e-4, printed
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data.dtype.names[:2] == ("time_s", "angle_rad") and "front_end_faults" in data.dtype.names
    # One estimate per carrier period, stamped at the window centres.
    assert np.allclose(np.diff(data["time_s"]), 1e-4)
    truth = np.interp(data["time_s"], scenario.time_s, scenario.angle_rad)
    error = np.remainder(data["angle_rad"] - truth + math.pi, 2 * math.pi) - math.pi
    # The statistics' --skip counts from the first estimate.
    kept = data["time_s"] - data["time_s"][0] >= 0.02
    assert np.sqrt(np.mean(error[kept] ** 2)) == pytest.approx(rms, rel=1e-3)


@pytest.mark.parametrize(
    "gains_hz, carrier_hz, expected",
    [
        # Gains at the ADC rate, not the carrier's: refused naming both rates.
        (160_000, "10000", ["sample_rate", "160000 Hz", "10000 Hz"]),
        # A carrier of fewer than 4 ADC samples per period.
        (50_000, "50000", ["samples_per_period", "160000 Hz", "50000 Hz"]),
    ],
)
def test_track_carrier_refuses_in_one_line(tmp_path, capsys, gains_hz, carrier_hz, expected):
    scenario, _ = windings(duration_s=0.005)
    raw, gains_file = tmp_path / "raw.csv", tmp_path / "g.json"
    write_raw(raw, scenario)
    design_gains(gains_file, gains_hz)
    capsys.readouterr()
    assert cli.main(["track", str(raw), "--carrier-hz", carrier_hz, "--gains-file", str(gains_file)]) == 2
    err = capsys.readouterr().err
    assert all(e in err for e in expected) and len(err.strip().splitlines()) == 1, err


def test_track_carrier_electrical_angle_at_the_latency(tmp_path, capsys):
    scenario, _ = windings()
    raw, gains_file, out = tmp_path / "raw.csv", tmp_path / "g.json", tmp_path / "est.csv"
    write_raw(raw, scenario)
    design_gains(gains_file, 10_000)
    status = cli.main(["track", str(raw), "--carrier-hz", "10000", "--gains-file", str(gains_file),
                       "--expected-delay-deg", "305", "--pole-pairs", "4", "--latency", "60e-6",
                       "--output", str(out)])
    assert status == 0
    data = np.genfromtxt(out, delimiter=",", names=True)
    kept = data["time_s"] > 0.02
    # The electrical angle at time_s + latency: 4 times the reference there.
    expected = 4 * np.interp(data["time_s"] + 60e-6, scenario.time_s, scenario.angle_rad)
    error = np.remainder(data["electrical_angle_rad"] - expected + math.pi, 2 * math.pi) - math.pi
    # Measured: 4.25e-04 rad RMS (4 times the mechanical angle's error, and the latency's
    # extrapolation), the speed within 0.15 %.
    assert np.sqrt(np.mean(error[kept] ** 2)) < 8.5e-4
    assert np.allclose(data["electrical_speed_rad_s"][kept], 4 * SPEED_RAD_S, rtol=3e-3, atol=0.0)



def test_demodulator_any_ratio_an_off_carrier_and_the_excitation_resolving_200_degrees():
    # Windings synthesised here from the resolver's equations: 48 kHz over a 5 kHz carrier
    # declared (9.6 samples per period), the true carrier 0.5 % off, 200 degrees of delay,
    # offsets, 30 rev/s; the excitation recorded in its own column.
    adc_hz, true_hz, delay = 48e3, 5025.0, math.radians(200.0)
    t = np.arange(int(0.05 * adc_hz)) / adc_hz
    theta = 0.3 + 2 * math.pi * 30.0 * t
    psi = 2 * math.pi * true_hz * t + delay
    carrier = 1500.0 * np.sin(psi)
    raw_c = np.round(2048.0 + 20.0 + np.cos(theta) * carrier)
    raw_s = np.round(2048.0 - 30.0 + np.sin(theta) * carrier)
    excitation = 2048.0 + 1000.0 * np.sin(psi)
    pairs, demodulator = angletrack.demodulate(
        raw_c, raw_s, carrier_hz=5e3, adc_rate_hz=adc_hz, carrier_amplitude_counts=1500.0, excitation=excitation)
    truth = 0.3 + 2 * math.pi * 30.0 * pairs.time_s
    error = np.remainder(np.arctan2(pairs.y_s, pairs.y_c) - truth + math.pi, 2 * math.pi) - math.pi
    # No half-turn error, and within 3 mrad RMS (measured: see the report of this change).
    assert len(pairs) > 200 and np.sqrt(np.mean(error[5:] ** 2)) < 3e-3
    assert demodulator.has_excitation and abs(demodulator.carrier_delay_rad) < 0.05
    assert demodulator.tracked_carrier_hz == pytest.approx(true_hz, abs=1.0)
    assert np.all(pairs.faults == 0)


def test_track_carrier_half_turn_from_the_stated_delay_after_an_inverted_excitation_probe(tmp_path, capsys):
    # 150 kHz over a 10 kHz carrier (15 per period), the carrier 200 degrees off phase 0 at
    # the first sample, recorded in an excitation column by an inverted probe (the windings
    # 180 degrees after it), synthesised here with numpy.
    adc_hz, delay = 150e3, math.radians(200.0)
    t = np.arange(int(0.05 * adc_hz)) / adc_hz
    theta = 0.4 + 2 * math.pi * 50.0 * t
    psi = 2 * math.pi * 10e3 * t + delay
    rng = np.random.default_rng(3)
    columns = {"time": t, "y_c": np.round(2048 + 1800 * np.cos(theta) * np.sin(psi) + rng.normal(0, 1, t.size)),
               "y_s": np.round(2048 + 1800 * np.sin(theta) * np.sin(psi) + rng.normal(0, 1, t.size)),
               "exc": np.round(2048 - 1000 * np.sin(psi)), "reference": theta}
    raw, gains_file, out = tmp_path / "raw.csv", tmp_path / "g.json", tmp_path / "est.csv"
    capture.write_capture(raw, columns)
    design_gains(gains_file, 10_000)
    track = ["track", str(raw), "--carrier-hz", "10000", "--gains-file", str(gains_file),
             "--columns", "excitation=exc", "--output", str(out), "--skip", "0.02"]
    capsys.readouterr()
    # Without --expected-delay-deg the half turn is taken around 0, half a turn off here, and
    # every row says so (not a fault).
    assert cli.main(track) == 0
    printed = capsys.readouterr().out
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert np.all(data["half_turn_unresolved"] == 1) and np.all(data["front_end_faults"] == 0), printed
    assert "half_turn_unresolved" in printed and "--expected-delay-deg" in printed, printed
    # Stated, 180 degrees after the excitation: the right angle, every row resolved.
    assert cli.main(track + ["--expected-delay-deg", "180"]) == 0
    printed = capsys.readouterr().out
    rms = float(printed.split("RMS ")[1].split()[0])
    assert rms < 2e-3, printed
    assert np.all(np.genfromtxt(out, delimiter=",", names=True)["half_turn_unresolved"] == 0)
