"""Front-end faults through the observer (docs/theory.md §15): coasting through a loss of
excitation and a winding open or shorted on the resolver path (windings synthesised here,
not by the library's generator), and clipping against a stated or measured ADC range on
every capture, from Python and the CLI."""

import math

import numpy as np
import pytest

import angletrack
from angletrack import cli

CARRIER_HZ = 10_000.0
ADC_HZ = 160_000.0
OMEGA = 2 * math.pi * 50.0  # 50 rev/s
FRONT_END = int(angletrack.Faults.FRONT_END)
CLIPPING = int(angletrack.FrontEndFaults.CLIPPING)


def wrapped(a):
    return np.remainder(a + math.pi, 2 * math.pi) - math.pi


def windings(duration_s, fault=None, theta0=0.3, seed=2, carrier_hz=CARRIER_HZ, adc_hz=ADC_HZ,
             delay_deg=20.0, noise_counts=1.0):
    """Raw windings of a resolver at 50 rev/s: a 10 kHz sine carrier sampled at 160 kHz by
    a 12-bit ADC (mid-scale 2048, amplitude 1800 counts, carrier delay ``delay_deg`` behind
    phase 0, noise 1 count RMS, rounded); ``fault(t, c, s)`` rewrites the carrier-modulated
    windings."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(duration_s * adc_hz))) / adc_hz
    theta = theta0 + OMEGA * t
    carrier = np.sin(2 * math.pi * carrier_hz * t - math.radians(delay_deg))
    c, s = 1800.0 * np.cos(theta) * carrier, 1800.0 * np.sin(theta) * carrier
    if fault is not None:
        c, s = fault(t, c, s)
    noisy = [np.round(2048.0 + v + rng.normal(0.0, noise_counts, len(t))) for v in (c, s)]
    return t, theta, noisy[0], noisy[1]


def write_csv(path, **columns):
    names = list(columns)
    np.savetxt(path, np.column_stack([columns[n] for n in names]), delimiter=",", header=",".join(names),
               comments="", fmt="%.17g")


def read_csv(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


@pytest.fixture(scope="module")
def carrier_gains(tmp_path_factory):
    path = tmp_path_factory.mktemp("gains") / "gains_10k.json"
    assert cli.main(["design", "kalman", "--sample-rate", str(CARRIER_HZ), "--jerk-std", "1e6",
                     "--noise-std", "2e-4", "--format", "json", "--output", str(path)]) == 0
    return path


def track_windings(tmp_path, gains, t, theta, c, s, capsys, *options):
    capture, out = tmp_path / "windings.csv", tmp_path / "est.csv"
    write_csv(capture, time=t, y_c=c, y_s=s)
    assert cli.main(["track", str(capture), "--gains-file", str(gains), "--carrier-hz", str(CARRIER_HZ),
                     "-o", str(out), *options]) == 0
    summary = capsys.readouterr().out
    est = read_csv(out)
    truth = theta[0] + OMEGA * est["time_s"]
    return est, wrapped(est["angle_rad"] - truth), summary


def test_the_resolver_path_writes_npy_and_npz(tmp_path, carrier_gains, capsys):
    # The same run as CSV, .npy and .npz: the fault columns uint8, the same values in each.
    t, _, c, s = windings(0.02)
    capture = tmp_path / "windings.csv"
    write_csv(capture, time=t, y_c=c, y_s=s)
    outputs = [tmp_path / f"est{suffix}" for suffix in (".csv", ".npy", ".npz")]
    for out in outputs:
        assert cli.main(["track", str(capture), "--gains-file", str(carrier_gains), "--carrier-hz",
                         str(CARRIER_HZ), "--pole-pairs", "2", "-o", str(out)]) == 0
    capsys.readouterr()
    text, records, archive = read_csv(outputs[0]), np.load(outputs[1]), np.load(outputs[2])
    assert list(records.dtype.names) == list(text) == sorted(archive.files, key=list(text).index)
    assert "front_end_faults" in text and "electrical_angle_rad" in text
    assert records["front_end_faults"].dtype == np.uint8 and archive["faults"].dtype == np.uint8
    assert len(records) > 150
    for name in text:
        np.testing.assert_array_equal(records[name], text[name])
        np.testing.assert_array_equal(archive[name], text[name])


def test_a_10_ms_loss_of_excitation_is_coasted_through(tmp_path, carrier_gains, capsys):
    lost = (0.10, 0.11)

    def loss(t, c, s):
        off = (t >= lost[0]) & (t < lost[1])
        return np.where(off, 0.0, c), np.where(off, 0.0, s)

    est, error, summary = track_windings(tmp_path, carrier_gains, *windings(0.16, loss), capsys)
    through = est["time_s"] >= lost[0]
    # The targets: within 20 mrad of the truth and the speed within 2 % through the loss
    # and after it (measured 6.4 mrad and 0.24 %).
    assert np.max(np.abs(error[through])) < 0.02
    assert np.max(np.abs(est["speed_rad_s"][through] / OMEGA - 1.0)) < 0.02
    during = (est["time_s"] > lost[0] + 2e-4) & (est["time_s"] < lost[1] - 2e-4)
    assert np.all(est["front_end_faults"][during].astype(int) & int(angletrack.FrontEndFaults.LOSS_OF_EXCITATION))
    assert np.all(est["faults"][during].astype(int) & FRONT_END)
    after = est["time_s"] > lost[1] + 2e-4
    assert not np.any(est["faults"][after].astype(int) & (FRONT_END | int(angletrack.Faults.FALSE_LOCK)))
    assert "LOSS_OF_EXCITATION" in summary


def test_the_front_end_fault_flags_are_the_cores():
    # The bits of DemodulatedPairs.faults and the front_end_faults column, documented in
    # the C header and the guide: a renamed or moved flag is an incompatible change.
    flags = [(flag.name, int(flag)) for flag in angletrack.FrontEndFaults]
    assert flags == [("LOSS_OF_EXCITATION", 1), ("PHASE_DRIFT", 2), ("CLIPPING", 4), ("WEAK_EXCITATION", 8),
                     ("WINDING", 16), ("EXCITATION_REFERENCE", 32)]


def test_carrier_windings_clipped_after_the_first_chunk_are_flagged(tmp_path, carrier_gains, capsys):
    # Windings in volts (no ADC range stated): amplitude 0.7 for the first 0.5 s (80,000
    # samples, past the first chunk of 65,536 rows), then 1.5, clipped at +-0.9 (the carrier's
    # peaks held flat over 4 samples or more, what makes a rail). The first
    # chunk holds no rail, so the range is a guess (-2 to 1) that the clipping never reaches:
    # the rails must be measured on the later samples, and every pair whose window holds a
    # clipped sample flagged.
    t = np.arange(96_000) / ADC_HZ
    theta = 0.3 + OMEGA * t
    carrier = np.sin(2 * math.pi * CARRIER_HZ * t - math.radians(20.0))
    amplitude = np.where(t < 0.5, 0.7, 1.5)
    c = np.clip(amplitude * np.cos(theta) * carrier, -0.9, 0.9)
    s = np.clip(amplitude * np.sin(theta) * carrier, -0.9, 0.9)
    est, error, summary = track_windings(tmp_path, carrier_gains, t, theta, c, s, capsys)
    clipped = (np.abs(c) >= 0.9) | (np.abs(s) >= 0.9)
    assert not np.any(clipped[t < 0.5]) and np.mean(clipped[t >= 0.5]) > 0.2
    flagged = (est["front_end_faults"].astype(int) & CLIPPING) != 0
    # A window is 1.25 carrier periods (20 samples) about its centre stamp: each pair whose
    # window holds a clipped sample is flagged, and none of the clean part is.
    period = 1.0 / CARRIER_HZ
    holds = np.array([np.any(clipped[(t >= stamp - 0.625 * period) & (t < stamp + 0.625 * period)])
                      for stamp in est["time_s"]])
    assert not np.any(flagged[est["time_s"] < 0.5 - period])
    late = est["time_s"] > 0.5 + period
    assert np.mean(holds[late]) > 0.9 and np.all(flagged[late][holds[late]])
    assert "CLIPPING" in summary and "rails measured as the samples come" in summary, summary


@pytest.mark.parametrize("delay_deg", [90.0, 305.0])
@pytest.mark.parametrize("onset", [0.1, 0.10003])
def test_the_carrier_comes_back_on_its_half_turn_after_a_loss(tmp_path, carrier_gains, capsys, delay_deg,
                                                               onset):
    # The excitation gone for 10 ms from the start of a carrier period or 0.3 of one into it
    # (the window straddling the onset then has part of the carrier), 3.6 counts of noise.
    # The carrier loop must keep its frequency through the loss: the window at the onset
    # once set a frequency the loop kept for the whole loss, and it came back half a turn
    # off (the angle pi wrong from then on, nothing flagged).
    def loss(t, c, s):
        off = (t >= onset) & (t < onset + 0.01)
        return np.where(off, 0.0, c), np.where(off, 0.0, s)

    scenario = windings(0.16, loss, theta0=0.7, delay_deg=delay_deg, noise_counts=3.6)
    est, error, summary = track_windings(tmp_path, carrier_gains, *scenario, capsys,
                                         "--expected-delay-deg", str(delay_deg))
    through = est["time_s"] >= onset - 1e-3
    # The targets of a 10 ms loss: 20 mrad and 2 % (measured at most 5.0 mrad and 1.0 %
    # over 0 to 305 degrees and three onsets).
    assert np.max(np.abs(error[through])) < 0.02
    assert np.max(np.abs(est["speed_rad_s"][through] / OMEGA - 1.0)) < 0.02
    assert "LOSS_OF_EXCITATION" in summary


@pytest.mark.parametrize("winding, reading", [("y_c", "open"), ("y_s", "shorted")])
def test_a_winding_open_or_shorted_is_flagged_within_one_carrier_period(tmp_path, carrier_gains, capsys,
                                                                        winding, reading):
    # At the onset the shaft is at 0.3 + 2 pi 50 0.1 rad (= 0.3 mod pi): the cosine winding
    # carries 0.96 of the amplitude, the sine winding 0.3; the fault lasts 10 ms.
    onset, end = 0.1, 0.11
    if winding == "y_s":
        onset, end = 0.1025, 0.1125  # the shaft then at 1.085 rad: the sine winding at 0.88

    def fault(t, c, s):
        on = (t >= onset) & (t < end)
        # Open: the winding's input floats to mid-scale; shorted: no carrier either.
        if winding == "y_c":
            return np.where(on, 0.0, c), s
        return c, np.where(on, 0.0, s)

    est, error, summary = track_windings(tmp_path, carrier_gains, *windings(0.16, fault), capsys)
    flagged = est["time_s"][(est["faults"].astype(int) & FRONT_END) != 0]
    assert len(flagged) > 0
    # The first flagged pair holds within one carrier period of the onset.
    assert onset <= flagged[0] <= onset + 1.0 / CARRIER_HZ
    assert "WINDING" in summary
    # Coasted through: the angle within 0.4 rad (measured 0.18 and 0.28; the pair straddling
    # the onset, half faulted and not yet flagged, kicks the speed that the coast then
    # holds), and within 12 mrad from 0.2 ms after the winding is back (measured up to 5.7).
    through = est["time_s"] >= onset
    assert np.max(np.abs(error[through])) < 0.4
    assert np.max(np.abs(error[est["time_s"] > end + 2e-4])) < 1.2e-2


def test_the_observer_coasts_on_the_front_end_faults_it_is_given():
    gains = angletrack.Gains([0.3, 0.04, 0.002], 1e-4)
    theta = 0.02 * np.arange(3000)
    y_c, y_s = np.cos(theta), np.sin(theta)
    faults = np.zeros(len(theta), dtype=np.uint8)
    faults[2000:2100] = 1  # loss of excitation: the pairs are noise
    y_c[2000:2100], y_s[2000:2100] = 0.01 * np.cos(7.0 * theta[2000:2100]), 0.01
    observer = angletrack.Observer(gains)
    est = observer.update(y_c, y_s, front_end_faults=faults)
    assert np.max(np.abs(wrapped(est.angle - theta)[2000:])) < 1e-6
    assert np.all(est.faults[2000:2100] & FRONT_END) and not np.any(est.faults[2100:] & FRONT_END)
    assert observer.latched_front_end_faults == 1
    with pytest.raises(ValueError, match="front_end_faults"):
        observer.update(y_c, y_s, front_end_faults=faults[:10])


@pytest.mark.parametrize("bad", [(1.0, 0.0), (0.0, math.nan)])
def test_the_adc_range_is_refused_naming_it(bad):
    with pytest.raises(angletrack.ConfigError, match="adc_range"):
        angletrack.Observer(angletrack.Gains([0.3, 0.04, 0.002], 1e-4), adc_range=bad)


def samples_capture(path, c, s, rate_hz=10_000.0):
    write_csv(path, time=np.arange(len(c)) / rate_hz, y_c=c, y_s=s)


def clipped_run(tmp_path, capsys, c, s, *options):
    capture, out = tmp_path / "capture.csv", tmp_path / "est.csv"
    samples_capture(capture, c, s)
    status = cli.main(["track", str(capture), "--gains", "0.3,0.04,0.002", "-o", str(out), *options])
    captured = capsys.readouterr()
    return status, captured, (read_csv(out) if status == 0 else None)


THETA = 0.3 + 0.0314 * np.arange(6000)


@pytest.mark.parametrize("options", [(), ("--adc-bits", "12", "--adc-unsigned"), ("--adc-range", "0,4095"),
                                     ("--dtype", "fixed"), ("--dtype", "fixed", "--adc-range", "0,4095")])
def test_both_channels_clipped_at_full_scale_are_flagged(tmp_path, capsys, options):
    # Unsigned 12-bit counts at 1.12 times full scale: 30 % of each channel's samples at a
    # rail, 60 % of the samples with a channel at one.
    amplitude = 2048 * 1.12
    c = np.clip(np.round(2048 + amplitude * np.cos(THETA)), 0, 4095)
    s = np.clip(np.round(2048 + amplitude * np.sin(THETA)), 0, 4095)
    at_rail = np.mean((c == 0) | (c == 4095) | (s == 0) | (s == 4095))
    assert 0.5 < at_rail < 0.7 and 0.25 < np.mean((c == 0) | (c == 4095)) < 0.35
    status, captured, est = clipped_run(tmp_path, capsys, c, s, *options)
    assert status == 0, captured.err
    flagged = (est["faults"].astype(int) & FRONT_END) != 0
    assert np.mean(flagged) == pytest.approx(at_rail, abs=0.01)
    stated = any(option.startswith("--adc") for option in options)
    assert "samples clipped" in captured.out and ("stated" in captured.out) == stated


def test_volts_clipped_at_0_9_are_flagged_against_the_stated_range(tmp_path, capsys):
    c, s = np.clip(np.cos(THETA), -0.9, 0.9), np.clip(np.sin(THETA), -0.9, 0.9)
    status, captured, est = clipped_run(tmp_path, capsys, c, s, "--adc-range", "-0.9,0.9")
    assert status == 0, captured.err
    flagged = (est["faults"].astype(int) & FRONT_END) != 0
    expected = np.mean((np.abs(c) >= 0.9) | (np.abs(s) >= 0.9))
    assert expected > 0.4 and np.mean(flagged) == pytest.approx(expected, abs=1e-9)
    # Without the range the clean part of the same signal is no clipping: a clean capture
    # measures no rail.
    status, captured, est = clipped_run(tmp_path, capsys, np.cos(THETA), np.sin(THETA))
    assert status == 0 and not np.any(est["faults"].astype(int) & FRONT_END)
    assert "rails measured as the samples come (extremes held flat over 4+ samples): 0 samples clipped" in (
        captured.out), captured.out


@pytest.mark.parametrize("options", [(), ("--dtype", "fixed")])
def test_clipping_that_starts_after_the_first_chunk_is_flagged(tmp_path, capsys, options):
    # Unsigned 12-bit counts, clean (amplitude 1800) for the first 70,000 samples, past the
    # first chunk of 65,536 rows; then at 1.3 times full scale, clipped at 0 and 4095. No
    # range stated, none held flat in the first chunk: the chain measures the rails as the
    # samples come and flags them from the first turn of the clipping on.
    theta = 0.3 + 0.0314 * np.arange(80_000)
    amplitude = np.where(np.arange(80_000) < 70_000, 1800.0, 2662.0)
    c = np.clip(np.round(2048 + amplitude * np.cos(theta)), 0, 4095)
    s = np.clip(np.round(2048 + amplitude * np.sin(theta)), 0, 4095)
    status, captured, est = clipped_run(tmp_path, capsys, c, s, *options)
    assert status == 0, captured.err
    flagged = (est["faults"].astype(int) & FRONT_END) != 0
    at_rail = (c == 0) | (c == 4095) | (s == 0) | (s == 4095)
    assert not np.any(flagged[:70_000])
    # A turn is 200 samples: from the second turn of the clipping on, every sample at a rail.
    late = np.arange(80_000) >= 70_400
    assert np.mean(at_rail[late]) > 0.5 and np.all(flagged[late] == at_rail[late])
    assert "rails measured as the samples come" in captured.out, captured.out


def test_clipping_is_flagged_with_an_angle_calibration_too(tmp_path, capsys):
    # The angle calibration's observer checks its raw samples against the stated range as
    # the plain observer does.
    gains = angletrack.Gains([0.3, 0.04, 0.002], 1e-4)
    theta = 0.3 + 0.0314 * np.arange(20_000)
    calibration = angletrack.calibrate(np.cos(theta), np.sin(theta), gains, reference=theta)
    (tmp_path / "cal.json").write_text(calibration.to_json())
    c, s = np.clip(np.cos(THETA), -0.9, 0.9), np.clip(np.sin(THETA), -0.9, 0.9)
    status, captured, est = clipped_run(tmp_path, capsys, c, s, "--adc-range", "-0.9,0.9", "--calibration",
                                        str(tmp_path / "cal.json"))
    assert status == 0, captured.err
    flagged = (est["faults"].astype(int) & FRONT_END) != 0
    expected = np.mean((np.abs(c) >= 0.9) | (np.abs(s) >= 0.9))
    assert expected > 0.4 and np.mean(flagged) == pytest.approx(expected, abs=1e-9)
    assert "samples clipped (flagged FRONT_END; those clipped in both channels coasted through)" in captured.out


def test_signed_12_bit_counts_clipped_from_the_start_are_flagged(tmp_path, capsys):
    # The first samples already at the rails: 1.5 times full scale.
    c = np.clip(np.round(3072 * np.cos(THETA)), -2048, 2047)
    s = np.clip(np.round(3072 * np.sin(THETA)), -2048, 2047)
    assert c[0] == 2047
    status, captured, est = clipped_run(tmp_path, capsys, c, s, "--adc-bits", "12", "--adc-signed")
    assert status == 0, captured.err
    assert est["faults"][0].astype(int) & FRONT_END
    flagged = (est["faults"].astype(int) & FRONT_END) != 0
    assert np.mean(flagged) == pytest.approx(np.mean((np.abs(c) >= 2047) | (np.abs(s) >= 2047)), abs=1e-3)
    assert "ADC range -2048 to 2047 (stated)" in captured.out


@pytest.mark.parametrize("options, message", [
    (("--adc-range", "1,0"), "adc_range: --adc-range 1,0: expected finite MIN < MAX"),
    (("--adc-range", "a,b"), "adc_range: --adc-range 'a,b': expected MIN,MAX"),
    (("--adc-bits", "12"), "adc_range: --adc-bits 12 needs --adc-signed or --adc-unsigned"),
    (("--adc-bits", "12", "--adc-signed", "--adc-range", "0,1"), "give --adc-range or --adc-bits"),
])
def test_a_bad_adc_range_is_refused_in_one_line(tmp_path, capsys, options, message):
    status, captured, _ = clipped_run(tmp_path, capsys, np.cos(THETA), np.sin(THETA), *options)
    assert status == 2
    assert message in captured.err and len(captured.err.strip().splitlines()) == 1


def refused(tmp_path, gains, capsys, t, c, s, *options):
    capture = tmp_path / "windings.csv"
    write_csv(capture, time=t, y_c=c, y_s=s)
    status = cli.main(["track", str(capture), "--gains-file", str(gains), "-o", str(tmp_path / "est.csv"),
                       *options])
    err = capsys.readouterr().err
    assert status == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "est.csv").exists()
    return err


def test_a_carrier_3_percent_from_the_declared_one_is_refused_naming_both(tmp_path, carrier_gains, capsys):
    t, _, c, s = windings(0.02, carrier_hz=10_300.0)
    err = refused(tmp_path, carrier_gains, capsys, t, c, s, "--carrier-hz", "10000")
    assert "carrier_hz: --carrier-hz 10000 is -2.91 % from the carrier measured in the capture, 10300" in err


def test_samples_per_period_against_the_time_column_is_refused_naming_both(tmp_path, carrier_gains, capsys):
    # A 150 kHz capture of a 10 kHz carrier: 15 samples per period, 16 forced.
    t, _, c, s = windings(0.02, adc_hz=150_000.0)
    err = refused(tmp_path, carrier_gains, capsys, t, c, s, "--carrier-hz", "10000", "--samples-per-period", "16")
    assert ("samples_per_period: --samples-per-period 16 contradicts the capture's time column: 150000 Hz over "
            "--carrier-hz 10000 is 15 samples per period") in err


def test_the_speed_is_at_the_tracked_carrier_rate(tmp_path, capsys):
    # Gains given at the declared carrier's rate (--gains: its sample period 1 / 10050 Hz),
    # the true carrier 0.5 % slower: the pairs come at the tracked rate and the speed is
    # rescaled to it (read 0.5 % fast before).
    t, theta, c, s = windings(0.1)
    capture, out = tmp_path / "windings.csv", tmp_path / "est.csv"
    write_csv(capture, time=t, y_c=c, y_s=s)
    design = angletrack.kalman_from_jerk_std(jerk_std_rad_s3=1e6, sensor_noise_std=2e-4, sample_period_s=1 / 10050)
    gains = ",".join(repr(g) for g in design.gains.gains)
    assert cli.main(["track", str(capture), "--gains", gains, "--carrier-hz", "10050", "-o", str(out)]) == 0
    speed = read_csv(out)["speed_rad_s"]
    # The mean over the second half (the loop's speed noise averages out): 0.5 % off unscaled.
    error = abs(np.mean(speed[len(speed) // 2:]) / OMEGA - 1.0)
    assert error < 5e-4, error


def test_the_time_stamps_come_from_the_time_column(tmp_path, carrier_gains, capsys):
    # A declared carrier 0.5 % off (within the 2 %): the rows are stamped by the capture's
    # clock (not the declared carrier's), at 16 samples a period at the centroids of their
    # windows of an even number of samples (half a sample off the grid) to within the loop's
    # phase noise (measured: 0.001 samples), one tracked period (16 samples) apart.
    scenario = windings(0.05)
    est, error, _ = track_windings(tmp_path, carrier_gains, *scenario, capsys, "--carrier-hz", "10050")
    position = est["time_s"] * ADC_HZ - 0.5
    np.testing.assert_allclose(position, np.round(position), rtol=0, atol=0.01)
    np.testing.assert_allclose(np.diff(est["time_s"]) * ADC_HZ, 16.0, rtol=0, atol=0.02)
    # The speed at the tracked carrier's rate, not the declared one's (0.5 % fast before).
    speed = est["speed_rad_s"][-len(est) // 4:]
    assert np.max(np.abs(speed / OMEGA - 1.0)) < 2e-3
    assert np.max(np.abs(error[len(error) // 2:])) < 5e-3


def test_fixed_and_float_observers_measure_the_rails_or_take_the_range():
    # 12-bit codes at 1.3 times full scale: both observers find the rails as the samples come,
    # or flag against the stated codes; both at once are refused, naming the argument.
    theta = 0.3 + 0.0314 * np.arange(4000)
    c = np.clip(np.round(2048 + 2662 * np.cos(theta)), 0, 4095).astype(np.int16)
    s = np.clip(np.round(2048 + 2662 * np.sin(theta)), 0, 4095).astype(np.int16)
    at_rail = (c == 0) | (c == 4095) | (s == 0) | (s == 4095)
    design = angletrack.third_order_butterworth(2e-3, 1e-4)
    gains = angletrack.Gains([0.3, 0.04, 0.002], 1e-4)
    fixed = dict(mid_scale_counts=2048, input_shift=3, nominal_amplitude=None)
    for observer in (angletrack.FixedObserver(design, measure_adc_range=True, **fixed),
                     angletrack.FixedObserver(design, adc_range=(0, 4095), **fixed),
                     angletrack.Observer(gains, adc_mid_scale=2048, measure_adc_range=True,
                                         fault_thresholds=angletrack.FaultThresholds(nominal_amplitude=2662.0))):
        est = observer.update(c, s)
        flagged = (np.asarray(est.faults).astype(int) & FRONT_END) != 0
        assert np.all(flagged[400:] == at_rail[400:]), observer
        assert observer.latched_front_end_faults == 4
    with pytest.raises(ValueError, match="measure_adc_range: give adc_range or measure_adc_range, not both"):
        angletrack.FixedObserver(design, adc_range=(0, 4095), measure_adc_range=True)
    with pytest.raises(ValueError, match="measure_adc_range: give adc_range or measure_adc_range, not both"):
        angletrack.Observer(gains, adc_range=(0.0, 4095.0), measure_adc_range=True)
