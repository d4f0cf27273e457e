"""``angletrack design --plot``: the designed loop's Bode plot and its noise-against-bandwidth
trade-off.

The Bode plot is the closed-loop angle transfer ``X1_e / Theta`` of the discrete loop
(:func:`angletrack.closed_loop_response`, ``docs/theory.md §5``) up to the Nyquist frequency.
The trade-off runs the design's own loop faster and slower: every pole's continuous
equivalent ``s_i = ln(z_i) / Ts`` is scaled by one factor (the step response keeps its shape,
time scaled), and each scaled loop's ``DesignReport`` gives its bandwidth, its RMS angle
error from the sensor noise and its steady tracking error at a stated acceleration (2nd
order) or jerk (3rd order).
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import textwrap

import numpy as np

import angletrack

#: The trade-off's pole scale factors: a decade of bandwidth centred on the design.
SCALES = np.logspace(-0.5, 0.5, 21)
#: Points of the Bode plot.
BODE_POINTS = 1500
FIGURE_SIZE_IN = (14.0, 7.0)
DPI = 100


def scaled_gains(gains: angletrack.Gains, factor: float) -> angletrack.Gains:
    """The loop of ``gains`` with every pole's continuous equivalent times ``factor``,
    computed in ``u = z - 1`` (``docs/theory.md §6``) to keep slow loops' precision."""
    ts = gains.sample_period_s
    shifted = np.roots(np.concatenate([[1.0], gains.loop_polynomial[::-1]]))
    scaled = np.expm1(factor * np.log1p(shifted.astype(complex)))
    coefficients = np.real(np.poly(scaled))[1:][::-1]
    return angletrack.Gains.from_loop_polynomial(coefficients.tolist(), ts)


@dataclasses.dataclass
class TradeOffPoint:
    """One loop of the trade-off."""

    scale: float
    bandwidth_hz: float
    noise_rms_rad: float
    tracking_error_rad: float


def _point(report: angletrack.DesignReport, scale: float, acceleration_rad_s2: float, jerk_rad_s3: float) -> TradeOffPoint:
    """The loop of ``report``: a type II loop lags a constant acceleration, a type III loop a
    constant jerk (``docs/theory.md §5``, error constants)."""
    if report.order == 2:
        tracking = acceleration_rad_s2 / report.acceleration_constant_per_s2
    else:
        tracking = jerk_rad_s3 * report.error_per_unit_jerk_s3
    return TradeOffPoint(scale, report.bandwidth_hz, report.angle_error_rms_rad, abs(tracking))


def trade_off(
    gains: angletrack.Gains, sensor_noise_std: float, acceleration_rad_s2: float, jerk_rad_s3: float
) -> list[TradeOffPoint]:
    """The design scaled by :data:`SCALES`; loops that leave the stability region (too fast
    for the sample rate) are left out."""
    points = []
    for factor in SCALES:
        try:
            report = angletrack.Design.from_gains(scaled_gains(gains, float(factor))).report(sensor_noise_std)
        except ValueError:
            continue
        if report.bandwidth_hz is not None:
            points.append(_point(report, float(factor), acceleration_rad_s2, jerk_rad_s3))
    return points


def _bode(ax_mag, ax_phase, design: angletrack.Design, bandwidth_hz: float) -> None:
    nyquist = 0.5 / design.sample_period_s
    lowest = min(bandwidth_hz / 100.0, nyquist / 1e3)
    freqs = np.logspace(math.log10(lowest), math.log10(nyquist), BODE_POINTS)
    h = angletrack.closed_loop_response(design.gains, freqs)
    ax_mag.semilogx(freqs, 20 * np.log10(np.abs(h)), color="tab:blue", lw=1.5)
    ax_mag.axhline(-3.0103, color="0.5", ls="--", lw=0.8)
    ax_mag.axvline(bandwidth_hz, color="tab:red", ls="--", lw=0.8)
    ax_mag.plot([bandwidth_hz], [-3.0103], "o", color="tab:red",
                label=f"-3 dB bandwidth {bandwidth_hz:.4g} Hz")
    ax_mag.axvline(nyquist, color="k", lw=0.8, label=f"Nyquist {nyquist:.4g} Hz")
    ax_mag.set_ylabel("|X1_e / Theta| (dB)")
    ax_mag.set_ylim(max(-60.0, float(np.min(20 * np.log10(np.abs(h)))) - 3), None)
    ax_mag.set_title(f"Closed-loop angle transfer of the discrete loop (to Nyquist, {nyquist:.4g} Hz)", fontsize=10)
    ax_mag.legend(loc="lower left", fontsize=8)
    ax_phase.semilogx(freqs, np.degrees(np.unwrap(np.angle(h))), color="tab:blue", lw=1.5)
    ax_phase.axvline(bandwidth_hz, color="tab:red", ls="--", lw=0.8)
    ax_phase.axvline(nyquist, color="k", lw=0.8)
    ax_phase.set_ylabel("phase (deg)")
    ax_phase.set_xlabel("frequency (Hz)")
    for ax in (ax_mag, ax_phase):
        ax.grid(alpha=0.3, which="both")


def _trade_off(ax, points: list[TradeOffPoint], chosen: TradeOffPoint, noise_std: float, what: str) -> None:
    bw = np.array([p.bandwidth_hz for p in points])
    noise = 1e3 * np.array([p.noise_rms_rad for p in points])
    tracking = 1e3 * np.array([p.tracking_error_rad for p in points])
    total = np.hypot(noise, tracking)
    ax.loglog(bw, noise, color="tab:blue", label=f"RMS error from sensor noise {noise_std:g} per channel")
    ax.loglog(bw, tracking, color="tab:orange", label=f"steady tracking error at {what}")
    ax.loglog(bw, total, color="k", lw=1, ls="--", label="both (root sum of squares)")
    for value, colour in ((chosen.noise_rms_rad, "tab:blue"), (chosen.tracking_error_rad, "tab:orange")):
        ax.plot([chosen.bandwidth_hz], [1e3 * value], "o", color=colour, ms=7)
    ax.axvline(chosen.bandwidth_hz, color="tab:red", ls="--", lw=0.8, label=f"this design, {chosen.bandwidth_hz:.4g} Hz")
    from matplotlib.ticker import FormatStrFormatter, FuncFormatter

    # Plain numbers of Hz: the decade spans few major ticks, so 2, 3 and 5 times them are
    # labelled too (the others would run into each other).
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(FuncFormatter(lambda x, _: f"{x:g}" if f"{x:.0e}"[0] in "235" else ""))
    ax.tick_params(axis="x", which="minor", labelsize=7)
    ax.set_xlabel("-3 dB bandwidth (Hz)")
    ax.set_ylabel("angle error (mrad)")
    ax.set_title("Noise against tracking as the bandwidth varies\n(the design's poles scaled)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    # Below the axes: the curves cross the whole plot whatever the design.
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize=8, frameon=False)


def plot_design(
    design: angletrack.Design, png: pathlib.Path, *, sensor_noise_std: float, acceleration_rad_s2: float,
    jerk_rad_s3: float, title: str,
) -> str:
    """Writes the Bode plot and the trade-off of ``design`` to ``png``; returns the line to
    print."""
    from angletrack.plots import pyplot

    plt = pyplot()
    if png.suffix.lower() != ".png":
        raise ValueError(f"plot: {png} is not a .png file name")
    report = design.report(sensor_noise_std=sensor_noise_std)
    if report.bandwidth_hz is None:
        raise ValueError("plot: the loop has no -3 dB bandwidth below the Nyquist frequency")
    points = trade_off(design.gains, sensor_noise_std, acceleration_rad_s2, jerk_rad_s3)
    chosen = _point(report, 1.0, acceleration_rad_s2, jerk_rad_s3)
    what = f"{acceleration_rad_s2:g} rad/s^2" if design.order == 2 else f"jerk {jerk_rad_s3:g} rad/s^3"
    fig = plt.figure(figsize=FIGURE_SIZE_IN)
    grid = fig.add_gridspec(2, 2, width_ratios=[1.25, 1])
    ax_mag = fig.add_subplot(grid[0, 0])
    ax_phase = fig.add_subplot(grid[1, 0], sharex=ax_mag)
    _bode(ax_mag, ax_phase, design, report.bandwidth_hz)
    _trade_off(fig.add_subplot(grid[:, 1]), points, chosen, sensor_noise_std, what)
    fig.suptitle(textwrap.fill(title, 150), fontsize=10)
    fig.tight_layout()
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=DPI)
    plt.close(fig)
    return f"plot: {png}"


#: Colours of the observers in ``design --from-capture --plot``.
_OBSERVER_COLOURS = {"second-order": "tab:blue", "third-order": "tab:green", "kalman": "tab:purple"}


def plot_design_from_capture(result: dict, png: pathlib.Path, *, title: str) -> str:
    """Writes the plot of :func:`angletrack.design_from_capture`'s ``result`` to ``png``: the
    estimated noise and motion spectra, and the predicted RMS angle error against the
    bandwidth for each observer (refused designs hollow), the chosen one marked; returns the
    line to print."""
    from angletrack.plots import pyplot

    plt = pyplot()
    if png.suffix.lower() != ".png":
        raise ValueError(f"plot: {png} is not a .png file name")
    fig, (ax_spectra, ax_error) = plt.subplots(1, 2, figsize=FIGURE_SIZE_IN)
    spectra = result["spectra"]
    ax_spectra.loglog(spectra["frequency_hz"], spectra["noise_rad2_per_hz"], color="tab:blue",
                      label="phase detector noise (estimated)")
    ax_spectra.loglog(spectra["frequency_hz"], spectra["motion_rad2_per_hz"], color="tab:orange",
                      label="angle of the estimated white jerk")
    ax_spectra.set_xlabel("frequency (Hz)")
    ax_spectra.set_ylabel("one-sided spectrum (rad^2/Hz)")
    ax_spectra.set_title("Estimated spectra", fontsize=10)
    ax_spectra.grid(alpha=0.3, which="both")
    ax_spectra.legend(fontsize=8)
    for observer, colour in _OBSERVER_COLOURS.items():
        rows = [c for c in result["candidates"] if c["observer"] == observer]
        if not rows:
            continue
        bw = np.array([c["bandwidth_hz"] for c in rows])
        total = 1e3 * np.array([c["predicted_error_rms_rad"] for c in rows])
        ax_error.loglog(bw, total, color=colour, lw=1, label=observer)
        refused = np.array([c["refused_by"] is not None for c in rows])
        ax_error.plot(bw[~refused], total[~refused], "o", color=colour, ms=3)
        ax_error.plot(bw[refused], total[refused], "o", mfc="none", color=colour, ms=3)
    chosen = result["chosen"]
    ax_error.plot([chosen["bandwidth_hz"]], [1e3 * chosen["predicted_error_rms_rad"]], "*", color="tab:red", ms=14,
                  label=f"chosen: {chosen['observer']}, {chosen['bandwidth_hz']:.4g} Hz, "
                  f"{1e3 * chosen['predicted_error_rms_rad']:.4g} mrad")
    ax_error.set_xlabel("-3 dB bandwidth (Hz)")
    ax_error.set_ylabel("predicted RMS angle error (mrad)")
    ax_error.set_title("Predicted error against bandwidth (hollow: refused by a constraint)", fontsize=10)
    ax_error.grid(alpha=0.3, which="both")
    ax_error.legend(fontsize=8)
    fig.suptitle(textwrap.fill(f"design from {title}", 150), fontsize=10)
    fig.tight_layout()
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=DPI)
    plt.close(fig)
    return f"plot: {png}"
