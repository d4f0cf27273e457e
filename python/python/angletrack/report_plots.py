"""The PNG figures of ``angletrack report`` (matplotlib), one function per figure."""

from __future__ import annotations

import math
import pathlib
from typing import TYPE_CHECKING, Callable

import numpy as np

import angletrack as at
from angletrack import plots

if TYPE_CHECKING:
    from angletrack.report import ScenarioResult
    from angletrack.report_harmonics import HarmonicsResult
    from angletrack.report_sensor import SensorResult

COLOURS = {"2nd-order ATO": "tab:blue", "3rd-order ATO": "tab:orange", "Kalman ATO": "tab:green"}

#: The scenarios plotted as errors over time.
ERROR_FIGURES = ("speed_ramp", "acceleration", "noise")


def pyplot():
    """matplotlib's pyplot on the file-only Agg backend, or a ``RuntimeError`` saying how to
    get it."""
    return plots.pyplot(" (or run with --no-plots)")


def _pct(x) -> str:
    return "-" if x is None else f"{100.0 * x:.2f} %"


def _save(plt, fig, path: pathlib.Path, top: float = 1.0) -> None:
    """Lays out the axes below ``top`` (figure fraction), writes the PNG and closes the figure."""
    fig.tight_layout(rect=(0, 0, 1, top))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _error_mrad(sc: at.Scenario, est: at.Estimates) -> np.ndarray:
    return 1e3 * np.angle(np.exp(1j * (sc.angle_rad - est.position)))


def _robust_limits(values: np.ndarray) -> tuple[float, float]:
    """Limits that show the bulk of a series (ignoring the first-sample transient)."""
    lo, hi = np.percentile(values, [0.5, 99.5])
    pad = 0.1 * (hi - lo) + 1e-12
    return float(lo - pad), float(hi + pad)


def plot_step(plt, result: ScenarioResult, path: pathlib.Path) -> None:
    """The 179 degree step: the angle and speed estimates of every observer."""
    sc = result.scenario
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    t_ms = 1e3 * sc.time_s
    a1.plot(t_ms, np.degrees(sc.angle_rad), "k--", lw=1, label="true angle")
    for name, (est, m) in result.runs.items():
        a1.plot(t_ms, np.degrees(est.position), color=COLOURS[name], label=f"{name} (overshoot {_pct(m.overshoot)})")
        a2.plot(t_ms, est.speed, color=COLOURS[name], label=name)
    a1.set_ylabel("angle (deg)")
    a1.set_title(f"Step of 179 degrees at {1e-3 / sc.sample_period_s:.0f} kHz")
    a1.legend(loc="lower right", fontsize=8)
    a2.set_ylabel("speed estimate (rad/s)")
    a2.set_xlabel("time (ms)")
    a1.grid(alpha=0.3), a2.grid(alpha=0.3)
    _save(plt, fig, path)


def _figure_legend(fig, ax) -> None:
    """One legend for the whole figure, above the axes, so that it covers no trace."""
    fig.legend(*ax.get_legend_handles_labels(), loc="upper center", ncol=3, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 0.945))


def plot_errors(plt, result: ScenarioResult, path: pathlib.Path) -> None:
    """The angle and speed errors of every observer over one scenario, overlaid."""
    sc = result.scenario
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6.4), sharex=True)
    t_ms = 1e3 * sc.time_s
    for name, (est, m) in result.runs.items():
        a1.plot(t_ms, _error_mrad(sc, est), color=COLOURS[name], lw=0.8, label=name)
        a2.plot(t_ms, sc.speed_rad_s - est.speed, color=COLOURS[name], lw=0.8, label=name)
    a1.set_ylabel("angle error (mrad)")
    a2.set_ylabel("speed error (rad/s)")
    a2.set_xlabel("time (ms)")
    fig.suptitle(result.spec.title, fontsize=11)
    _figure_legend(fig, a1)
    for a in (a1, a2):
        a.grid(alpha=0.3)
    runs = result.runs.values()
    # The start-up transient would flatten the rest.
    a1.set_ylim(*_robust_limits(np.concatenate([_error_mrad(sc, e) for e, _ in runs])))
    a2.set_ylim(*_robust_limits(np.concatenate([sc.speed_rad_s - e.speed for e, _ in runs])))
    _save(plt, fig, path, top=0.975)


def plot_noise(plt, result: ScenarioResult, path: pathlib.Path) -> None:
    """The angle and speed errors of each observer under noise, one row per observer on
    shared axes: overlaid, the last trace drawn would hide the others."""
    sc = result.scenario
    runs = result.runs
    fig, axes = plt.subplots(len(runs), 2, figsize=(10, 2.3 * len(runs) + 0.8), sharex=True, sharey="col",
                             squeeze=False)
    t_ms = 1e3 * sc.time_s
    kept = sc.time_s >= result.spec.skip_s
    for (name, (est, m)), (a1, a2) in zip(runs.items(), axes):
        speed = m.speed_error_rad_s.rms if m.speed_error_rad_s else float("nan")
        a1.plot(t_ms, _error_mrad(sc, est), color=COLOURS[name], lw=0.5)
        a2.plot(t_ms, sc.speed_rad_s - est.speed, color=COLOURS[name], lw=0.5)
        a1.set_title(f"{name}: RMS {1e3 * m.angle_error_rad.rms:.3g} mrad", fontsize=9, loc="left")
        a2.set_title(f"{name}: RMS {speed:.3g} rad/s", fontsize=9, loc="left")
        a1.set_ylabel("angle error (mrad)")
        a2.set_ylabel("speed error (rad/s)")
        for a in (a1, a2):
            a.grid(alpha=0.3)
            # The start-up transient, left out of the statistics, would flatten the noise.
            a.axvspan(t_ms[0], 1e3 * result.spec.skip_s, color="0.92", zorder=0)
    # Shared axes per column: limits from the noise after the start-up of every observer.
    for column, error in enumerate((lambda e: _error_mrad(sc, e), lambda e: sc.speed_rad_s - e.speed)):
        peak = max(float(np.max(np.abs(error(e)[kept]))) for e, _ in runs.values())
        axes[0, column].set_ylim(-1.05 * peak, 1.05 * peak)
    axes[-1, 0].set_xlabel("time (ms)")
    axes[-1, 1].set_xlabel("time (ms)")
    fig.suptitle(f"{result.spec.title}\n(statistics after {1e3 * result.spec.skip_s:.0f} ms, the start-up shaded and "
                 "clipped)", fontsize=10)
    _save(plt, fig, path)


def plot_overshoot(plt, settings: list[at.PaperSetting], path: pathlib.Path) -> None:
    """Small-signal step responses of the paper's settings, each run by the observer."""
    fig, ax = plt.subplots(figsize=(8, 4.5))
    step_rad, hold_s = 1e-3, 0.001
    for setting in settings:
        design = setting.design
        profile = at.MotionProfile(0.0, 0.0).constant_speed(0.0, hold_s).step(step_rad, 0.12)
        sc = at.Scenario.generate(profile, sample_period_s=design.sample_period_s)
        est = at.track(design.gains, sc.y_c, sc.y_s, fault_thresholds=at.FaultThresholds.disabled())
        m = at.metrics(sc, est)
        label = f"{setting.name}: {_pct(m.overshoot)} (paper {setting.paper_overshoot_percent} %)"
        ax.plot(1e3 * (sc.time_s - hold_s), est.position / step_rad, label=label)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set_xlim(-1, 120)
    ax.set_xlabel("time after the step (ms)")
    ax.set_ylabel("angle / step")
    rate_khz = 1e-3 / settings[0].design.sample_period_s
    ax.set_title(f"Small-signal step responses of the paper's settings ({rate_khz:.0f} kHz)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    _save(plt, fig, path)


def plot_sensor_errors(plt, result: SensorResult, path: pathlib.Path) -> None:
    """Section 5: the angle error (mean removed) against the true electrical angle, without
    and with the online calibration, after the calibration has converged."""
    sc, k = result.scenario, result.first
    angle_deg = np.degrees(np.mod(sc.angle_rad[k:], 2 * np.pi))
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name, est, colour in (
        ("uncorrected", result.uncorrected, "tab:red"),
        ("online calibration", result.corrected, "tab:green"),
    ):
        error = _error_mrad(sc, est)[k:]
        ax.plot(angle_deg, error - error.mean(), ",", color=colour, alpha=0.5)
        ax.plot([], [], "o", color=colour, label=f"{name}: RMS {np.std(error):.3g} mrad")
    ax.set_xlim(0, 360)
    ax.set_xticks(range(0, 361, 45))
    ax.set_xlabel("true electrical angle (deg)")
    ax.set_ylabel("angle error, mean removed (mrad)")
    ax.set_title("Offsets 5 %, gain imbalance 10 %, quadrature 3 degrees (Kalman ATO)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    _save(plt, fig, path)


def log_limits(values: np.ndarray) -> tuple[float, float]:
    """Limits of a log axis on which every positive value shows as a bar: the floor a decade
    boundary at least a factor 2 below the smallest (a bar at the floor has no height), the
    top room for the legend above the largest."""
    positive = values[np.isfinite(values) & (values > 0)]
    if len(positive) == 0:
        return 1e-3, 1.0
    floor = 10.0 ** math.floor(math.log10(0.5 * positive.min()))
    return floor, 6.0 * positive.max()


def plot_harmonic_errors(plt, result: HarmonicsResult, path: pathlib.Path) -> None:
    """Section 6: the angle error (mean removed) against the true electrical angle without
    and with the calibration, one panel each (their scales differ a hundredfold), and the
    harmonic spectra of both beside the sensor's own angle error, on a log scale."""
    from angletrack.capture_analysis import HARMONIC_ORDERS
    from angletrack.report_harmonics import HARMONICS

    fig = plt.figure(figsize=(11, 6))
    grid = fig.add_gridspec(2, 2, width_ratios=(3, 2))
    spectrum = fig.add_subplot(grid[:, 1])
    orders = np.asarray(HARMONIC_ORDERS, dtype=float)
    runs = (("uncorrected", result.uncorrected_error_rad, "tab:red", -0.2),
            ("with the calibration", result.calibrated_error_rad, "tab:green", 0.2))
    heights = []
    for row, (name, error, colour, shift) in enumerate(runs):
        ax = fig.add_subplot(grid[row, 0])
        bins = result.binned(error)
        kept = error[result.first:] - np.mean(error[result.first:])
        angle_deg = np.degrees(np.mod(result.scenario.angle_rad[result.first:], 2 * np.pi))
        ax.plot(angle_deg[::3], 1e3 * kept[::3], ".", ms=1, color=colour, alpha=0.25, rasterized=True)
        ax.plot(np.degrees(bins.centres_rad()), 1e3 * bins.mean_error_rad(), color="k", lw=1)
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 45))
        ax.set_ylabel("angle error (mrad)")
        ax.set_title(f"{name}: RMS {1e3 * result.statistics(error)[0]:.3g} mrad", fontsize=10, loc="left")
        ax.grid(alpha=0.3)
        heights.append(1e3 * bins.harmonics_rad())
        spectrum.bar(orders + shift, heights[-1], width=0.4, color=colour, label=name)
    ax.set_xlabel("true electrical angle (deg)")
    truth = [(k, a) for k, a, _ in HARMONICS]
    spectrum.plot([k for k, _ in truth], [1e3 * a for _, a in truth], "kx", ms=8, mew=2,
                  label="the sensor's angle error d(theta)")
    spectrum.set_yscale("log")
    spectrum.set_ylim(*log_limits(np.concatenate(heights + [[1e3 * a for _, a in truth]])))
    spectrum.set_xticks(HARMONIC_ORDERS)
    spectrum.set_xlabel("harmonic order of the electrical angle")
    spectrum.set_ylabel("amplitude (mrad, peak)")
    spectrum.set_title("Harmonics of the angle error", fontsize=10, loc="left")
    spectrum.grid(alpha=0.3, axis="y", which="both")
    spectrum.legend(loc="upper right", fontsize=8, framealpha=0.9)
    fig.suptitle(f"Tracked with a +-5 % speed ripple after the calibration (noise floor predicted "
                 f"{1e3 * result.predicted_noise_rad:.3g} mrad RMS); dots: samples, black: mean per 0.5 degree",
                 fontsize=10)
    _save(plt, fig, path)


def plot_all(
    plt,
    out_dir: pathlib.Path,
    results: dict[str, ScenarioResult],
    settings: list[at.PaperSetting],
    done: Callable[[str], None],
) -> None:
    """Writes every figure into ``out_dir``, calling ``done`` with a line after each."""
    plot_step(plt, results["step"], out_dir / "step_179.png")
    done("plot step_179.png")
    for key in ERROR_FIGURES:
        (plot_noise if key == "noise" else plot_errors)(plt, results[key], out_dir / f"{key}.png")
        done(f"plot {key}.png")
    plot_overshoot(plt, settings, out_dir / "overshoot.png")
    done("plot overshoot.png")
