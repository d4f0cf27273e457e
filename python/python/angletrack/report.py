"""``angletrack report``: the paper's comparison of the three observers, reproduced, a
real sensor's errors corrected by the online calibration, and its angle-dependent errors by
the calibration of ``angletrack calibrate``.

Every figure comes from the Rust crates: the paper's settings and the compared observers
(``angletrack::paper``, through ``paper_settings`` and ``paper_compared_observers``), their
``DesignReport``s, scenarios, observers and metrics. This module runs them and writes
``report.md``, one function per section, with the PNG plots of ``report_plots``.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import sys
import time
from typing import Callable, Optional

import angletrack as at
from angletrack import report_harmonics, report_plots, report_sensor
from angletrack.report_markdown import figure as _figure
from angletrack.report_markdown import khz as _khz
from angletrack.report_markdown import num as _num
from angletrack.report_markdown import pct
from angletrack.report_markdown import table as _table
from angletrack.report_sensor import SensorResult

SAMPLE_PERIOD_S = at.PAPER_COMPARISON_SAMPLE_PERIOD_S
SENSOR_NOISE_STD = at.PAPER_COMPARISON_SENSOR_NOISE_STD
HOLD_S = 0.01  # rest before the step: the observers start locked
ACCELERATION_RAD_S2 = 2000.0  # of the constant-acceleration scenario

#: The paper's loops have no diagnostics: the comparison runs the bare loop.
BARE_LOOP = at.FaultThresholds.disabled()


@dataclasses.dataclass
class ScenarioSpec:
    """One test signal of the comparison."""

    key: str
    title: str
    profile: at.MotionProfile
    sensor: at.SensorModel
    skip_s: float
    #: Time of the move's start (s), for the step's settling time.
    move_at_s: float = 0.0


@dataclasses.dataclass
class ScenarioResult:
    """The compared observers run over one scenario: ``runs[name] = (estimates, metrics)``
    of the bare loop, ``with_diagnostics`` the same with the core's default diagnostics
    (filled for the step only)."""

    spec: ScenarioSpec
    scenario: at.Scenario
    runs: dict[str, tuple[at.Estimates, at.Metrics]]
    with_diagnostics: dict[str, tuple[at.Estimates, at.Metrics]]


def scenarios() -> list[ScenarioSpec]:
    """The four test signals of the comparison: step, speed ramp, acceleration, noise."""
    ideal = at.SensorModel()
    return [
        ScenarioSpec(
            "step",
            "Step of 179 degrees",
            at.MotionProfile(0.0, 0.0).constant_speed(0.0, HOLD_S).step(math.radians(179.0), 0.4),
            ideal,
            skip_s=0.0,
            move_at_s=HOLD_S,
        ),
        ScenarioSpec(
            "speed_ramp",
            "Speed ramp: 1000 rad/s^2 from rest for 0.2 s, then 200 rad/s",
            at.MotionProfile(0.0, 0.0).constant_acceleration(1000.0, 0.2).constant_speed(200.0, 0.3),
            ideal,
            skip_s=0.0,
        ),
        ScenarioSpec(
            "acceleration",
            f"Constant acceleration: {ACCELERATION_RAD_S2:.0f} rad/s^2 from 10 rad/s for 0.6 s",
            at.MotionProfile(0.0, 10.0).constant_acceleration(ACCELERATION_RAD_S2, 0.6),
            ideal,
            skip_s=0.3,
        ),
        ScenarioSpec(
            "noise",
            f"Noise: constant 100 rad/s, white noise {SENSOR_NOISE_STD} per channel",
            at.MotionProfile(0.0, 100.0).constant_speed(100.0, 10.0),
            at.SensorModel(noise_std=SENSOR_NOISE_STD),
            skip_s=1.0,
        ),
    ]


class Progress:
    """Numbered progress lines on stderr, with the elapsed time."""

    def __init__(self, total: int, stream=sys.stderr) -> None:
        self.total, self.done, self.start, self.stream = total, 0, time.perf_counter(), stream

    def step(self, what: str) -> None:
        self.done += 1
        elapsed = time.perf_counter() - self.start
        print(f"[{self.done:>2}/{self.total}] {elapsed:6.2f} s  {what}", file=self.stream, flush=True)


def run_scenarios(
    specs: list[ScenarioSpec], observers: dict[str, at.Design], progress: Progress
) -> dict[str, ScenarioResult]:
    """Runs every observer over every scenario (seeded 1, 2, ... in order)."""
    results = {}
    for seed, spec in enumerate(specs, start=1):
        sc = at.Scenario.generate(spec.profile, spec.sensor, sample_period_s=SAMPLE_PERIOD_S, seed=seed)
        result = results[spec.key] = ScenarioResult(spec, sc, {}, {})
        for name, design in observers.items():
            est = at.track(design.gains, sc.y_c, sc.y_s, fault_thresholds=BARE_LOOP)
            result.runs[name] = (est, at.metrics(sc, est, skip_s=spec.skip_s))
            if spec.key == "step":
                # False-lock detection re-acquires the angle: the step seen with diagnostics.
                est_d = at.track(design.gains, sc.y_c, sc.y_s)
                result.with_diagnostics[name] = (est_d, at.metrics(sc, est_d, skip_s=spec.skip_s))
            progress.step(f"{spec.key}: {name} ({len(sc)} samples)")
    return results


def section_header() -> list[str]:
    """The title and what computed the figures."""
    return [
        "# angletrack report: the three observers of Auger, Mansouri-Toudert and Chibah (2011)",
        "",
        f"Generated by `angletrack report` (angletrack {at.__version__}). Every figure is computed by "
        "the Rust crates: the design functions and `DesignReport` of `angletrack`, the observers of "
        "`angletrack-core` (float64, exact sin/cos), seeded scenarios and metrics.",
    ]


def section_overshoot(settings: list[at.PaperSetting], progress: Progress, plots: bool) -> list[str]:
    """Section 1: the step-response overshoot of the paper's four settings."""
    rows = []
    for setting in settings:
        r = setting.design.report(sensor_noise_std=0.0)
        progress.step(f"design report: {setting.name}")
        paper = setting.paper_overshoot_percent
        ratio = (1.0 / r.sample_period_s) / r.bandwidth_hz if r.bandwidth_hz else float("nan")
        rows.append(
            [
                setting.name,
                f"{paper:.1f} %",
                pct(r.continuous_step.overshoot if r.continuous_step else None),
                pct(r.linear_step.overshoot),
                f"{100.0 * r.linear_step.overshoot - paper:+.2f}",
                pct(r.large_step.overshoot),
                _num(r.bandwidth_hz, ".1f") + " Hz",
                f"{ratio:.0f}",
                _num(r.linear_step.settling_time_s, ".4g", 1e3) + " ms",
            ]
        )
    header = [
        "setting",
        "paper",
        "continuous",
        "discrete (linear)",
        "discrete - paper (points)",
        "179 degree step",
        "-3 dB bandwidth",
        "fs / bandwidth",
        "2 % settling",
    ]
    md = [
        "",
        "## 1. Step-response overshoot of the paper's four settings",
        "",
        f"Designed at {_khz(settings[0].design.sample_period_s)} and carried to the discrete loop by "
        "pole matching. *Continuous* is the continuous design's step response, *discrete* the linear "
        "(small-signal) response of the sampled loop, *179 degree step* the nonlinear loop (the "
        "core's recursion with its phase detector) after a 179 degree step.",
        "",
        _table(header, rows),
    ]
    if plots:
        md += ["", "![small-signal step responses of the four settings](overshoot.png)"]
    return md


def section_observers(observers: dict[str, at.Design], reports: dict[str, at.DesignReport]) -> list[str]:
    """Section 2: the three observers' designs side by side, their noise figures on two stated
    models: the sensor noise alone, and the Kalman ATO's own model (noise and random jerk)."""
    jerk_q = observers["Kalman ATO"].kalman.process_noise_q
    rows = []
    for name, design in observers.items():
        r = reports[name]
        on_kalman_model = at.predicted_error_on_kalman_model(design.gains, SENSOR_NOISE_STD, jerk_q)
        rows.append(
            [
                name,
                design.method,
                ", ".join(f"{g:.6g}" for g in design.gains.gains),
                _num(r.bandwidth_hz, ".1f") + " Hz",
                _num(r.acceleration_constant_per_s2, ".4g") if r.order == 2 else "inf (type III)",
                _num(r.error_per_unit_jerk_s3, ".3g") if r.order == 3 else "-",
                pct(r.linear_step.overshoot),
                _num(r.angle_error_rms_rad, ".3g", 1e3),
                "unbounded" if on_kalman_model is None else _num(on_kalman_model.angle_rms_rad, ".3g", 1e3),
                _num(r.acquisition_speed_rad_s, ".4g"),
            ]
        )
    jerk_std = math.sqrt(jerk_q) / SAMPLE_PERIOD_S**3
    header = [
        "observer",
        "design",
        "gains l",
        "bandwidth",
        "Ka (1/s^2)",
        "error per jerk (s^3)",
        "linear overshoot",
        f"RMS angle error, sensor noise {SENSOR_NOISE_STD} only (mrad)",
        f"RMS angle error on the Kalman model: noise {SENSOR_NOISE_STD} + random jerk "
        f"{jerk_std:.0e}".replace("e+0", "e") + " rad/s^3 (mrad)",
        "speed step acquired (rad/s)",
    ]
    return [
        "",
        "## 2. The three observers compared",
        "",
        f"All three at {_khz(SAMPLE_PERIOD_S)} with about {at.PAPER_COMPARISON_BANDWIDTH_HZ:.0f} Hz of "
        f"-3 dB bandwidth; noise figures for white noise of {SENSOR_NOISE_STD} per channel (amplitude 1).",
        "",
        _table(header, rows),
        "",
        "The second noise column is the Kalman design's own model; the Kalman ATO's entry is its floor "
        "sqrt(P11), the smallest RMS error any linear observer reaches on that model, and larger than its "
        "sensor-noise-only figure because it includes the random jerk. On that model the 2nd-order ATO has "
        "no steady state: a random jerk makes the acceleration a random walk, which a type II loop does not "
        "follow with a bounded error.",
    ]


#: Extra columns of a scenario table: (observer name, estimates, metrics) -> cells.
ExtraColumns = Callable[[str, at.Estimates, at.Metrics], list[str]]


def scenario_table(result: ScenarioResult, extra_header: list[str], extra: ExtraColumns) -> str:
    """The error statistics of every observer over one scenario, then ``extra`` columns."""
    rows = []
    for name, (est, m) in result.runs.items():
        speed = m.speed_error_rad_s.rms if m.speed_error_rad_s else None
        e = m.angle_error_rad
        rows.append(
            [name, _num(e.rms, ".3g", 1e3), _num(e.max, ".3g", 1e3), _num(e.mean, ".3g", 1e3), _num(speed, ".3g")]
            + extra(name, est, m)
        )
    header = ["observer", "RMS angle error (mrad)", "max (mrad)", "mean (mrad)", "RMS speed error (rad/s)"]
    return _table(header + extra_header, rows)


def section_step(result: ScenarioResult, plots: bool) -> list[str]:
    """Section 3, the 179 degree step, bare and with diagnostics."""
    spec = result.spec

    def after(t: Optional[float]) -> Optional[float]:
        return None if t is None else t - spec.move_at_s

    def extra(name: str, est: at.Estimates, m: at.Metrics) -> list[str]:
        diagnosed = result.with_diagnostics[name][1]
        return [
            pct(m.overshoot),
            _num(after(m.settling_time_s), ".4g", 1e3),
            _num(after(m.time_to_lock_s), ".4g", 1e3),
            pct(diagnosed.overshoot),
            _num(after(diagnosed.time_to_lock_s), ".4g", 1e3),
        ]

    header = [
        "overshoot",
        "2 % settling after the step (ms)",
        "locked (0.01 rad) after the step (ms)",
        "with diagnostics: overshoot",
        "with diagnostics: locked after (ms)",
    ]
    return [
        f"### {spec.title}",
        "",
        f"At rest for {HOLD_S * 1e3:.0f} ms, then the angle jumps by 179 degrees (a 180 degree step "
        "would start on the loop's unstable equilibrium).",
        "",
        scenario_table(result, header, extra),
        "",
        "*With diagnostics*: the same observers with the core's default fault thresholds, whose "
        "false-lock detection sees the error beyond 90 degrees and re-acquires the angle from atan2.",
        *_figure(plots, "179 degree step", "step_179.png"),
    ]


def section_speed_ramp(result: ScenarioResult, plots: bool) -> list[str]:
    """Section 3, the speed ramp."""
    return [
        f"### {result.spec.title}",
        "",
        "The 2nd-order (type II) loop lags by acceleration / Ka while the speed ramps; the type III "
        "loops follow a ramp of speed without steady error.",
        "",
        scenario_table(result, ["locked from (ms)"], lambda name, est, m: [_num(m.time_to_lock_s, ".4g", 1e3)]),
        *_figure(plots, "speed ramp", "speed_ramp.png"),
    ]


def section_acceleration(result: ScenarioResult, reports: dict[str, at.DesignReport], plots: bool) -> list[str]:
    """Section 3, the constant acceleration, beside the 2nd-order loop's predicted lag."""
    alpha = ACCELERATION_RAD_S2
    ka = reports["2nd-order ATO"].acceleration_constant_per_s2

    def predicted_mean(name: str, est: at.Estimates, m: at.Metrics) -> list[str]:
        r = reports[name]
        return [_num(alpha / r.acceleration_constant_per_s2, ".4g", 1e3) if r.order == 2 else "0"]

    return [
        f"### {result.spec.title}",
        "",
        f"Statistics after {result.spec.skip_s} s. Predicted steady-state error of the 2nd-order loop: "
        f"alpha / Ka = {alpha:.0f} / {ka:.6g} = {1e3 * alpha / ka:.4g} mrad; the 3rd-order loops: 0.",
        "",
        scenario_table(result, ["predicted mean (mrad)"], predicted_mean),
        *_figure(plots, "constant acceleration", "acceleration.png"),
    ]


def section_noise(result: ScenarioResult, reports: dict[str, at.DesignReport], plots: bool) -> list[str]:
    """Section 3, the noise, beside the RMS errors the design reports predict."""

    def predicted(name: str, est: at.Estimates, m: at.Metrics) -> list[str]:
        r = reports[name]
        return [
            _num(r.angle_error_rms_rad, ".3g", 1e3),
            f"{m.angle_error_rad.rms / r.angle_error_rms_rad:.3f}",
            _num(r.speed_error_rms_rad_s, ".3g"),
        ]

    header = ["predicted RMS angle (mrad)", "measured / predicted", "predicted RMS speed (rad/s)"]
    return [
        f"### {result.spec.title}",
        "",
        f"Statistics after {result.spec.skip_s} s, beside the RMS errors the design reports predict from "
        "the discrete Lyapunov equation of the linearised loop.",
        "",
        scenario_table(result, header, predicted),
        *_figure(plots, "noise", "noise.png"),
    ]


def section_scenarios(
    results: dict[str, ScenarioResult], reports: dict[str, at.DesignReport], plots: bool
) -> list[str]:
    """Section 3: the observers on the four scenarios."""
    return [
        "",
        "## 3. Scenarios",
        "",
        "The observers run as the paper's bare loops (float64, exact sin/cos, no diagnostics) on "
        f"seeded scenarios at {_khz(SAMPLE_PERIOD_S)}. Errors are truth - estimate; "
        "the angle error is wrapped to [-pi, pi).",
        "",
        *section_step(results["step"], plots),
        *section_speed_ramp(results["speed_ramp"], plots),
        *section_acceleration(results["acceleration"], reports, plots),
        *section_noise(results["noise"], reports, plots),
    ]


def section_sensor(result: SensorResult, plots: bool) -> list[str]:
    """Section 5: a sensor with offsets, gain imbalance and quadrature error, tracked with
    and without the online calibration (docs/theory.md §12)."""
    sc, k = result.scenario, result.first
    truth = sc.angle_rad[k:]
    rows = []
    for name, est in (("uncorrected", result.uncorrected), ("online calibration", result.corrected)):
        rms, first, second = report_sensor.angle_error_harmonics(truth, est.position[k:])
        rows.append([name, _num(rms, ".3g", 1e3), _num(first, ".3g", 1e3), _num(second, ".3g", 1e3)])
    true_cal, learned = result.sensor.calibration(), result.learned
    parameters = [
        ("offset_c (counts)", "offset_c", ".4g", 1.0),
        ("offset_s (counts)", "offset_s", ".4g", 1.0),
        ("amplitude_s / amplitude_c", "amplitude_ratio", ".5f", 1.0),
        ("quadrature (degrees)", "quadrature_rad", ".4f", 180.0 / math.pi),
    ]
    param_rows = [
        [label, _num(getattr(true_cal, attr), fmt, scale), _num(getattr(learned, attr), fmt, scale)]
        for label, attr, fmt, scale in parameters
    ]
    s = result.sensor
    return [
        "",
        "## 5. A real sensor: offsets, gain imbalance and quadrature error",
        "",
        f"Raw counts of amplitude {s.amplitude:.0f} (a 12-bit ADC, mid-scale removed), offsets "
        f"{s.offset_cos:+.0f} and {s.offset_sin:+.0f} counts (5 %), gain imbalance "
        f"{100 * s.amplitude_imbalance:.0f} %, quadrature {math.degrees(s.quadrature_error_rad):.0f} degrees, "
        f"noise {s.noise_std:.0f} counts, at a constant {report_sensor.ELECTRICAL_HZ:.0f} Hz electrical for "
        f"{report_sensor.TURNS} turns. The Kalman ATO (float64, the amplitude-invariant loop, diagnostics "
        "scaled to the signal's own amplitude) tracks it as it is, and with the online calibration "
        "learning the sensor's errors while it tracks and correcting each sample before the phase "
        f"detector (`Observer(..., calibration=\"learn\")`). Statistics from turn {report_sensor.CONVERGED_TURNS} "
        "to the end, after removing the mean angle error (a constant offset is a mounting matter); "
        "harmonics of the true electrical angle.",
        "",
        _table(["observer", "RMS angle error (mrad)", "1x harmonic (mrad)", "2x harmonic (mrad)"], rows),
        "",
        f"Learned over {result.turns_learned} turns (a turn over which the estimated speed changed by more "
        "than 1/64 is dropped), against the sensor's true parameters:",
        "",
        _table(["parameter", "true", "learned"], param_rows),
        *_figure(plots, "angle error against angle, with and without the online calibration", "sensor_errors.png"),
    ]


def section_datasheets(reports: dict[str, at.DesignReport]) -> list[str]:
    """Section 4: each observer's ``DesignReport`` as a table."""
    md = ["## 4. Design datasheets (`DesignReport`)", ""]
    for name, r in reports.items():
        md += [f"### {name}", "", "| quantity | value |", "| --- | --- |", str(r).rstrip(), ""]
    return md


def write_report(out_dir: pathlib.Path, *, plots: bool = True, progress: Optional[Progress] = None) -> pathlib.Path:
    """Runs the comparison and writes ``out_dir/report.md`` (and PNG plots). Returns the
    path of ``report.md``."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    plt = report_plots.pyplot() if plots else None
    specs = scenarios()
    observers = dict(at.paper_compared_observers())
    settings = at.paper_settings()
    total = len(settings) + len(observers) + len(specs) * len(observers) + 2 + (len(specs) + 3 if plots else 0) + 1
    progress = progress or Progress(total)
    started = time.perf_counter()

    md = section_header() + section_overshoot(settings, progress, plots)
    reports = {}
    for name, design in observers.items():
        reports[name] = design.report(sensor_noise_std=SENSOR_NOISE_STD)
        progress.step(f"design report: {name}")
    md += section_observers(observers, reports)
    results = run_scenarios(specs, observers, progress)
    sensor = report_sensor.run_sensor(observers["Kalman ATO"], SAMPLE_PERIOD_S)
    progress.step(f"imperfect sensor: uncorrected and calibrated ({len(sensor.scenario)} samples)")
    md += section_scenarios(results, reports, plots) + section_datasheets(reports) + section_sensor(sensor, plots)
    harmonic = report_harmonics.run_harmonics(out_dir / "harmonics")
    progress.step(f"angle-dependent errors: calibrate, track without and with the calibration "
                  f"({len(harmonic.scenario)} samples)")
    md += report_harmonics.section_harmonics(harmonic, plots)
    if plt is not None:
        report_plots.plot_all(plt, out_dir, results, settings, progress.step)
        report_plots.plot_sensor_errors(plt, sensor, out_dir / "sensor_errors.png")
        progress.step("plot sensor_errors.png")
        report_plots.plot_harmonic_errors(plt, harmonic, out_dir / "harmonics.png")
        progress.step("plot harmonics.png")

    md.append(f"_Computed in {time.perf_counter() - started:.1f} s._")
    path = out_dir / "report.md"
    path.write_text("\n".join(md) + "\n")
    progress.step(f"wrote {path}")
    return path
