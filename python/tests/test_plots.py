"""Seeing the error: the capture figure's numbers (ellipse fit, harmonic spectrum,
decimation), the discrete loop's frequency response (docs/theory.md §5), and the PNGs of
``angletrack plot``, ``track --plot`` and ``design --plot``."""

import json
import math
import struct
import sys

import numpy as np
import pytest

import angletrack
from angletrack import cli, export, plots, tracking
from angletrack.capture_analysis import (
    AngleErrorBins,
    ConicMoments,
    Envelope,
    LockDetector,
    RandomSample,
    slowest_time_constant_samples,
)

RATE_HZ = 10_000.0


def png_size(path):
    """(width, height) in pixels from a PNG's IHDR chunk."""
    header = path.read_bytes()[:24]
    assert header[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return struct.unpack(">II", header[16:24])


def sensor(theta, *, offsets=(0.0, 0.0), imbalance=0.0, quadrature=0.0, error=None, noise=0.0, seed=3):
    """The scenario generator's sensor model; ``error(theta)`` an angle-dependent error (rad)."""
    rng = np.random.default_rng(seed)
    seen = theta + (error(theta) if error else 0.0)
    y_c = offsets[0] + np.cos(seen) + noise * rng.standard_normal(len(theta))
    y_s = offsets[1] + (1 + imbalance) * np.sin(seen + quadrature) + noise * rng.standard_normal(len(theta))
    return y_c, y_s


def third_harmonic(theta):
    return 5e-3 * np.cos(3 * theta + 0.4)


def write_npz(path, n=60_000, reference=True, **model):
    t = np.arange(n) / RATE_HZ
    theta = 2 * math.pi * 20.0 * t  # 20 electrical turns per second
    y_c, y_s = sensor(theta, **model)
    columns = {"time": t, "y_c": y_c, "y_s": y_s}
    if reference:
        columns["reference"] = theta
    np.savez(path, **columns)
    return path


@pytest.mark.parametrize("noise, tolerance", [(0.0, 1e-9), (1e-3, 5e-4)])
def test_ellipse_fit_recovers_offsets_imbalance_and_quadrature(noise, tolerance):
    theta = np.linspace(0.0, 40 * math.pi, 200_000)
    y_c, y_s = sensor(theta, offsets=(0.05, -0.03), imbalance=0.02, quadrature=0.01, noise=noise)
    moments = ConicMoments()
    for part in np.array_split(np.arange(len(theta)), 7):  # chunk by chunk
        moments.add(y_c[part], y_s[part])
    fit = moments.fit()
    assert abs(fit.offset_cos - 0.05) < tolerance and abs(fit.offset_sin + 0.03) < tolerance
    assert abs(fit.amplitude_ratio - 1.02) < tolerance
    assert abs(fit.amplitude_cos - 1.0) < tolerance
    assert abs(fit.quadrature_rad - 0.01) < tolerance


def test_ellipse_fit_of_points_on_a_line_is_none():
    x = np.linspace(-1, 1, 100)
    moments = ConicMoments()
    moments.add(x, 2 * x)
    assert moments.fit() is None


def test_harmonic_spectrum_recovers_a_third_harmonic():
    rng = np.random.default_rng(0)
    angle = rng.uniform(0, 2 * math.pi, 400_000)
    bins = AngleErrorBins()
    bins.add(angle, third_harmonic(angle) + 1e-3 * np.sin(angle))
    amplitudes = bins.harmonics_rad()
    assert abs(amplitudes[2] - 5e-3) < 5e-5  # 1 %
    assert abs(amplitudes[0] - 1e-3) < 2e-5
    assert np.all(np.delete(amplitudes, [0, 2]) < 5e-5)


def test_no_spectrum_from_less_than_a_turn():
    bins = AngleErrorBins()
    angle = np.linspace(0.0, math.pi, 1000)
    bins.add(angle, 1e-3 * np.cos(3 * angle))
    assert 0.49 < bins.widest_gap() < 0.51
    assert np.isnan(bins.harmonics_rad()).all()


def test_envelope_keeps_a_spike_of_one_sample_and_at_most_max_points():
    env = Envelope(max_points=1000)
    values = np.zeros(1_000_000)
    values[123_457] = 7.0
    for start in range(0, len(values), 65_536):
        env.add(np.arange(start, min(start + 65_536, len(values))) * 1e-4, values[start:start + 65_536])
    t, low, high = env.series()
    assert len(t) <= 1001 and high.max() == 7.0 and low.min() == 0.0
    assert np.all(np.diff(t) > 0)


def test_random_sample_keeps_max_points_in_order_without_aliasing():
    # 200 samples per turn: every 8th sample would keep 25 angles of the turn.
    sample = RandomSample(max_points=5000)
    n = 200_000
    for start in range(0, n, 7000):
        index = np.arange(start, min(start + 7000, n))
        sample.add(index, np.remainder(index, 200))
    kept, angle = sample.points()
    assert len(kept) == 5000 and np.all(np.diff(kept) > 0)
    assert len(np.unique(angle)) == 200
    # Uniform over the capture: each tenth of it holds about a tenth of the points.
    counts = np.bincount((kept * 10 // n).astype(int), minlength=10)
    assert np.all(np.abs(counts - 500) < 100), counts


@pytest.mark.parametrize("chunk", [1000, 65_536])
def test_lock_detector_finds_the_first_hold_within_the_tolerance_across_chunks(chunk):
    # Blocks of one sample: the error itself.
    error = np.full(10_000, 0.5)
    error[2000:2100] = 0.0  # too short a run
    error[3000:] = 0.001
    error[3500] = np.nan  # a bad sample restarts the hold
    error[9000] = 0.5  # after the lock: still counted
    lock = LockDetector(tolerance_rad=0.01, hold=600)
    masks = [lock.add(start, error[start:start + chunk]) for start in range(0, len(error), chunk)]
    assert lock.lock_index == 3501 + 600
    assert np.flatnonzero(np.concatenate(masks))[0] == 4101 and np.concatenate(masks)[9000]


@pytest.mark.parametrize("chunk", [1000, 4096])
def test_lock_detector_averages_the_noise_over_blocks(chunk):
    # A start-up decaying from 1 rad with a time constant of 400 samples, under noise of
    # 5 mrad RMS (3.5 % of samples beyond 0.01 rad: per sample, 1600 in a row would not
    # come), then a bad sample.
    k = np.arange(20_000)
    error = np.exp(-k / 400) + 5e-3 * np.random.default_rng(1).standard_normal(len(k))
    error[2500] = np.nan
    lock = LockDetector(tolerance_rad=0.01, hold=1600, block=50)
    masks = [lock.add(start, error[start:start + chunk]) for start in range(0, len(error), chunk)]
    assert lock.hold == 1600
    # Block means within 0.01 rad from block 37 (1850: exp(-1850/400) = 0.0098); the NaN
    # block 50 restarts the hold: blocks 51 to 82, locked at sample 4150.
    assert lock.lock_index == 4150
    assert np.flatnonzero(np.concatenate(masks))[0] == lock.lock_index
    assert not LockDetector(tolerance_rad=0.01, hold=1600).add(0, error).any()


def test_lock_detector_block_across_chunks_locks_at_the_chunks_first_sample():
    # Locked at the start of the block after two blocks within the tolerance, once it is
    # complete.
    lock = LockDetector(tolerance_rad=0.01, hold=100, block=50)
    assert not lock.add(0, np.zeros(130)).any()  # blocks 0 and 1; samples 100 to 129 pending
    # Block 2 (100 to 149) completes in the next chunk: the lock at its start, 100, is past;
    # it is the chunk's first sample.
    assert lock.add(130, np.zeros(100)).all() and lock.lock_index == 130


def test_slowest_time_constant_of_a_first_order_loop():
    # A loop polynomial s + 0.01 is the pole z = 0.99: time constant -1 / ln 0.99 samples.
    assert abs(slowest_time_constant_samples([0.01, 1.0]) - (-1 / math.log(0.99))) < 1e-9


def analytic_h(l, z):
    """H(z) of docs/theory.md §5."""
    if len(l) == 2:
        l1, l2 = l
        return (l1 * z**2 + (l2 - l1) * z) / (z**2 + (l1 + l2 - 2) * z + 1 - l1)
    l1, l2, l3 = l
    num = l1 * z**3 + (l2 - 2 * l1 + l3 / 2) * z**2 + (l1 - l2 + l3 / 2) * z
    return num / (z**3 + (l1 + l2 + l3 / 2 - 3) * z**2 + (3 - 2 * l1 - l2 + l3 / 2) * z + l1 - 1)


def minus_3_db_hz(gains, high_hz):
    """The frequency where |H| falls through 1/sqrt(2), by bisection on a log scale."""
    lo, hi = 1e-3, high_hz
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        if abs(angletrack.closed_loop_response(gains, [mid])[0]) < 1 / math.sqrt(2):
            hi = mid
        else:
            lo = mid
    return math.sqrt(lo * hi)


def test_frequency_response_is_the_analytic_transfer_function(gains):
    freqs = [0.0, 10.0, 200.0, 1000.0, 0.5 * gains.sample_rate_hz]
    h = angletrack.closed_loop_response(gains, freqs)
    assert h.dtype == np.complex128 and h.shape == (5,)
    assert abs(h[0] - 1.0) < 1e-12
    z = np.exp(2j * math.pi * np.array(freqs) * gains.sample_period_s)
    np.testing.assert_allclose(h, analytic_h(gains.gains, z), rtol=1e-9, atol=1e-12)


def test_frequency_response_falls_3_db_at_the_reported_bandwidth():
    for design in (angletrack.second_order_from_bandwidth(50.0, 1.0, 1e-4), angletrack.paper_compared_observers()[1][1]):
        bandwidth = design.report().bandwidth_hz
        assert abs(minus_3_db_hz(design.gains, 0.5 / design.sample_period_s) / bandwidth - 1) < 0.01


def test_frequency_response_refuses_a_negative_frequency():
    with pytest.raises(ValueError, match="frequency_hz"):
        angletrack.closed_loop_response(angletrack.Gains([0.06, 0.001], 1e-4), [-1.0])


def settings(path, **kw):
    return tracking.TrackSettings(capture=path, output=path, **kw)


def test_capture_analysis_against_the_reference_column(tmp_path):
    cap = write_npz(tmp_path / "c.npz", offsets=(0.02, 0.0), error=third_harmonic)
    a = plots.analyse_capture(settings(cap))
    assert a.reference == "the reference column" and a.rows == 60_000
    harmonics = a.errors.harmonics_rad()
    assert abs(harmonics[2] - 5e-3) < 5e-5
    # A cosine offset o gives atan2 an error of o sin(theta): the first harmonic.
    assert abs(harmonics[0] - 0.02) < 5e-4
    assert abs(a.fit.offset_cos - 0.02) < 1e-3
    assert a.speed_source == "the reference's differences"
    np.testing.assert_allclose(a.speed.series()[1], 2 * math.pi * 20.0, rtol=1e-9)


def test_capture_analysis_draws_at_most_max_points_per_series(tmp_path):
    cap = write_npz(tmp_path / "c.npz", error=third_harmonic)
    gains_file = tmp_path / "g.json"
    gains_file.write_text(export.to_json(angletrack.second_order_from_bandwidth(20.0, 1.0, 1 / RATE_HZ).gains))
    a = plots.analyse_capture(settings(cap, gains_file=gains_file, chunk_rows=7000), max_points=1000)
    assert a.rows == 60_000
    assert 500 < len(a.lissajous.points()[0]) <= 1000 and len(a.error_scatter.points()[0]) <= 1000
    assert len(a.speed.series()[0]) <= 1001
    assert all(len(env.series()[0]) <= 1001 for env in a.faults.values())
    # The binned error uses every sample, whatever is drawn.
    assert a.errors.count == 60_000


def test_capture_analysis_against_the_observer_without_reference(tmp_path):
    cap = write_npz(tmp_path / "c.npz", reference=False, error=third_harmonic, noise=1e-3)
    gains_file = tmp_path / "g.json"
    gains = angletrack.second_order_from_bandwidth(5.0, 1.0, 1 / RATE_HZ).gains
    gains_file.write_text(export.to_json(gains))
    a = plots.analyse_capture(settings(cap, gains_file=gains_file, skip_s=2.0))
    assert a.reference.startswith("the observer's angle")
    # After the pull-in from rest (about 1.2 s for this slow loop), the observer follows H(f)
    # of the 3rd harmonic (60 Hz at 20 turns/s, above the 5 Hz loop), so atan2 minus its
    # angle keeps (1 - H) of it.
    seen = 5e-3 * abs(1 - angletrack.closed_loop_response(gains, [60.0])[0])
    assert abs(a.errors.harmonics_rad()[2] / seen - 1) < 0.02
    assert set(a.faults) == {name for name, _ in angletrack.FAULT_BITS}


def test_plot_command_writes_the_figure_and_its_numbers(tmp_path, capsys):
    cap = write_npz(tmp_path / "c.npz", offsets=(0.05, -0.03), imbalance=0.02, quadrature=0.01,
                    error=third_harmonic, noise=1e-3)
    gains_file = tmp_path / "g.json"
    gains_file.write_text(export.to_json(angletrack.second_order_from_bandwidth(20.0, 1.0, 1 / RATE_HZ).gains))
    out = tmp_path / "figs"
    assert cli.main(["plot", str(cap), "--gains-file", str(gains_file), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "amplitude ratio a_s/a_c 1.02" in printed and "plot:" in printed
    png = out / "c_plot.png"
    assert png_size(png) == (1500, 1050) and png.stat().st_size > 60_000
    numbers = json.loads((out / "c_plot.json").read_text())
    assert abs(numbers["ellipse"]["quadrature_rad"] - 0.01) < 5e-4
    assert abs(numbers["harmonics_rad"]["3"] - 5e-3) < 5e-4
    # Without gains: the figure still has the Lissajous and the reference's error.
    assert cli.main(["plot", str(cap), "-o", str(tmp_path / "bare.png"), "--max-points", "1000"]) == 0
    assert png_size(tmp_path / "bare.png") == (1500, 1050)


def test_track_plot_draws_the_tracked_capture(tmp_path, capsys):
    cap = write_npz(tmp_path / "c.npz")
    out = tmp_path / "est.npy"
    assert cli.main(["track", str(cap), "--gains", "0.06,0.001", "-o", str(out), "--plot"]) == 0
    assert out.exists() and png_size(tmp_path / "est.png") == (1500, 1050)
    assert "plot:" in capsys.readouterr().out


def test_design_plot_draws_bode_and_trade_off(tmp_path, capsys):
    png = tmp_path / "design.png"
    args = ["design", "third-order", "--sample-rate", "10000", "--pole-ratio", "4", "--pole-time-constant",
            "0.002", "--format", "json", "-o", str(tmp_path / "g.json"), "--plot", str(png)]
    assert cli.main(args) == 0
    assert png_size(png) == (1400, 700) and png.stat().st_size > 40_000
    assert f"plot: {png}" in capsys.readouterr().out


def test_trade_off_scales_the_bandwidth_and_trades_noise_for_tracking():
    from angletrack import design_plots

    design = angletrack.second_order_from_bandwidth(50.0, 1.0, 1e-4)
    points = design_plots.trade_off(design.gains, 1e-3, 1000.0, 1e5)
    middle = next(p for p in points if p.scale == 1.0)
    assert abs(middle.bandwidth_hz / design.report().bandwidth_hz - 1) < 1e-6
    bandwidths = [p.bandwidth_hz for p in points]
    assert bandwidths == sorted(bandwidths) and bandwidths[-1] / bandwidths[0] > 9
    noise = [p.noise_rms_rad for p in points]
    tracking_error = [p.tracking_error_rad for p in points]
    assert noise == sorted(noise) and tracking_error == sorted(tracking_error, reverse=True)


def status_of(args):
    """The exit status of the CLI, argparse's refusals included."""
    try:
        return cli.main(args)
    except SystemExit as e:
        return e.code


@pytest.mark.parametrize(
    "args, message",
    [
        (["plot", "missing.csv"], "missing.csv"),
        (["plot", "{cap}", "--max-points", "1"], "max_points"),
        (["plot", "{cap}", "--gains-file", "{gains_20khz}"], "designed for 20000 Hz"),
        (["plot", "{cap}", "-o", "x.jpg"], ".png"),
        (["design", "second-order", "--sample-rate", "1e4", "--bandwidth", "50", "--plot", "x.jpg"], ".png"),
    ],
)
def test_plot_commands_refuse_bad_input_in_one_line(tmp_path, capsys, args, message):
    cap = write_npz(tmp_path / "c.npz", n=2000)
    gains_20khz = tmp_path / "g.json"
    gains_20khz.write_text(export.to_json(angletrack.Gains([0.06, 0.001], 5e-5)))
    assert status_of([a.format(cap=cap, gains_20khz=gains_20khz) for a in args]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "Traceback" not in err
    # One line, also for an option argparse refuses itself.
    assert err.count("\n") == 0 and err.count(message) == 1


def test_missing_matplotlib_is_a_one_line_error(tmp_path, capsys, monkeypatch):
    cap = write_npz(tmp_path / "c.npz", n=2000)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert cli.main(["plot", str(cap)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "pip install 'angletrack[plot]'" in err


def gains_20hz(tmp_path):
    path = tmp_path / "g.json"
    path.write_text(export.to_json(angletrack.second_order_from_bandwidth(20.0, 1.0, 1 / RATE_HZ).gains))
    return path


def test_plot_leaves_the_observers_start_up_out_of_a_clean_capture(tmp_path):
    cap = write_npz(tmp_path / "c.npz", n=20_000, reference=False)
    gains_file = gains_20hz(tmp_path)
    assert cli.main(["plot", str(cap), "--gains-file", str(gains_file), "--out", str(tmp_path)]) == 0
    numbers = json.loads((tmp_path / "c_plot.json").read_text())
    # The 20 Hz loop (slowest time constant 40 ms) is within 0.01 rad after about 0.14 s,
    # then held 4 time constants (measured: locked at 0.304 s).
    assert numbers["start_up"] == "skipped" and 0.2 < numbers["lock_s"] < 0.4
    assert numbers["statistics_from_s"] == numbers["lock_s"]
    assert max(numbers["harmonics_rad"].values()) < 2e-4 * 1e-3  # measured 4.0e-8 rad
    # Counted, the start-up from rest would read as a sensor error of tens of mrad.
    a = plots.analyse_capture(settings(cap, gains_file=gains_file), include_start_up=True)
    assert a.start_up == "included" and a.errors.harmonics_rad().max() > 0.01  # measured 0.022 rad


def test_plot_counts_the_start_up_when_the_observer_never_locks(tmp_path):
    # Noise of 0.05 per channel (50 mrad of angle noise, 7 mrad in the means of the 49-sample
    # blocks): some block is beyond 0.01 rad in every hold (noise 0.03 still locks).
    cap = write_npz(tmp_path / "c.npz", n=5000, reference=False, noise=0.05)
    a = plots.analyse_capture(settings(cap, gains_file=gains_20hz(tmp_path)))
    assert a.start_up == "never locked" and a.lock_s is None and a.statistics_from_s == 0.0
    assert "never locked" in a.describe()
    # A looser tolerance locks.
    a = plots.analyse_capture(settings(cap, gains_file=gains_20hz(tmp_path), lock_tolerance_rad=0.05))
    assert a.start_up == "skipped" and a.lock_s is not None


def test_a_fault_of_one_sample_shows_at_least_two_pixels_wide(tmp_path):
    n = 60_000  # about 46 samples per pixel column of the time axes
    t = np.arange(n) / RATE_HZ
    y_c, y_s = sensor(2 * math.pi * 20.0 * t)
    y_c[45_000] = np.nan  # one bad sample: the observer coasts
    np.savez(tmp_path / "c.npz", time=t, y_c=y_c, y_s=y_s)
    a = plots.analyse_capture(settings(tmp_path / "c.npz", gains_file=gains_20hz(tmp_path)))
    plt = plots.pyplot()
    fig = plots.draw_capture(plt, a)  # laid out, not written
    ax_faults = fig.axes[4]
    row = [name for name, _ in angletrack.FAULT_BITS].index("BAD_SAMPLE")
    spans = [bar for bar in ax_faults.collections
             if abs(np.mean(bar.get_paths()[0].get_extents().intervaly) - row) < 0.01]
    assert len(spans) == 1
    corners = ax_faults.transData.transform(spans[0].get_paths()[0].vertices)
    assert np.ptp(corners[:, 0]) >= plots.MIN_FAULT_PX - 1e-6
    left = ax_faults.transData.transform([[4.5, row]])[0, 0]
    assert abs(corners[:, 0].min() - left) < 1.0  # where the sample is
    # Every time axis is labelled in seconds.
    assert fig.axes[3].get_xlabel() == fig.axes[4].get_xlabel() == "time from the first sample (s)"
    plt.close(fig)
