"""``angletrack report``: the paper's comparison of the three observers, reproduced.

Every figure comes from the Rust crates (design functions, ``DesignReport``, scenarios,
observers, metrics); this module chooses the settings, calls them, and writes
``report.md`` with its tables and PNG plots (matplotlib).

Settings:

* Overshoot of the paper's four settings (section 1), at 100 kHz, at least 200 times each
  loop's bandwidth: the 2nd-order ATO with damping m = 1.945 and m = sqrt(2)/2, the
  3rd-order ATO with K = 39.04, psi = 3 pi / 2, and the 3rd-order Butterworth setting.
* The three observers compared on the same signals (sections 2 and 3), at 10 kHz with
  about 100 Hz of -3 dB bandwidth each: the 2nd-order ATO (m = 1.945), the 3rd-order ATO
  (K = 39.04, psi = 3 pi / 2) and the time-invariant Kalman ATO for a sensor noise of 0.01
  per channel.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import sys
import time
from typing import Callable, Optional

import numpy as np

import angletrack as at

#: The paper's overshoot figures (percent) for its four settings.
PAPER_OVERSHOOT_PERCENT = {
    "2nd order, m = 1.945": 5.0,
    "2nd order, Butterworth m = sqrt(2)/2": 20.8,
    "3rd order, K = 39.04, psi = 3 pi/2": 10.0,
    "3rd order, Butterworth": 30.9,
}

OVERSHOOT_SAMPLE_PERIOD_S = 1e-5  # 100 kHz
COMPARISON_SAMPLE_PERIOD_S = 1e-4  # 10 kHz
SENSOR_NOISE_STD = 0.01
PSI = 3.0 * math.pi / 2.0


def paper_settings() -> dict[str, at.Design]:
    """The four settings whose overshoot the paper quotes, at 100 kHz."""
    ts = OVERSHOOT_SAMPLE_PERIOD_S
    return {
        # Tolerated error 1 mrad at 100 rad/s^2: Ka = 1e5 1/s^2.
        "2nd order, m = 1.945": at.second_order_from_tracking_error(
            max_error_rad=1e-3, acceleration_rad_s2=100.0, damping=1.945, sample_period_s=ts
        ),
        "2nd order, Butterworth m = sqrt(2)/2": at.second_order_from_tracking_error(
            max_error_rad=1e-3, acceleration_rad_s2=100.0, damping=math.sqrt(2.0) / 2.0, sample_period_s=ts
        ),
        "3rd order, K = 39.04, psi = 3 pi/2": at.third_order_from_poles(
            pole_ratio=39.04, pole_time_constant_s=0.02, pole_frequency_ratio=PSI, sample_period_s=ts
        ),
        "3rd order, Butterworth": at.third_order_butterworth(time_constant_s=0.005, sample_period_s=ts),
    }


def compared_observers() -> dict[str, at.Design]:
    """The three observers of the comparison, at 10 kHz, each about 100 Hz wide."""
    ts = COMPARISON_SAMPLE_PERIOD_S
    return {
        "2nd-order ATO": at.second_order_from_bandwidth(bandwidth_hz=100.0, damping=1.945, sample_period_s=ts),
        "3rd-order ATO": at.third_order_from_poles(
            pole_ratio=39.04, pole_time_constant_s=0.068, pole_frequency_ratio=PSI, sample_period_s=ts
        ),
        "Kalman ATO": at.kalman_from_jerk_std(
            jerk_std_rad_s3=1e5, sensor_noise_std=SENSOR_NOISE_STD, sample_period_s=ts
        ),
    }


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


HOLD_S = 0.01  # rest before the step: the observers start locked

#: The paper's loops have no diagnostics: the comparison runs the bare loop.
BARE_LOOP = at.FaultThresholds.disabled()


def scenarios() -> list[ScenarioSpec]:
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
            "Constant acceleration: 2000 rad/s^2 from 10 rad/s for 0.6 s",
            at.MotionProfile(0.0, 10.0).constant_acceleration(2000.0, 0.6),
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


def _pct(x: Optional[float]) -> str:
    return "-" if x is None else f"{100.0 * x:.2f} %"


def _num(x: Optional[float], fmt: str = ".3g", scale: float = 1.0) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return format(x * scale, fmt)


def _table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(" --- " for _ in header) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def _plots_module():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise RuntimeError(
            "the report's plots need matplotlib: pip install 'angletrack[plot]' (or run with --no-plots)"
        ) from None
    return plt


def write_report(out_dir: pathlib.Path, *, plots: bool = True, progress: Optional[Progress] = None) -> pathlib.Path:
    """Runs the comparison and writes ``out_dir/report.md`` (and PNG plots). Returns the
    path of ``report.md``."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    plt = _plots_module() if plots else None
    specs = scenarios()
    observers = compared_observers()
    settings = paper_settings()
    total = len(settings) + len(observers) + len(specs) * len(observers) + (len(specs) + 1 if plots else 0) + 1
    progress = progress or Progress(total)
    started = time.perf_counter()
    md: list[str] = []

    md.append("# angletrack report: the three observers of Auger, Mansouri-Toudert and Chibah (2011)")
    md.append("")
    md.append(
        f"Generated by `angletrack report` (angletrack {at.__version__}). Every figure is computed by "
        "the Rust crates: the design functions and `DesignReport` of `angletrack`, the observers of "
        "`angletrack-core` (float64, exact sin/cos), seeded scenarios and metrics."
    )

    # 1. The paper's overshoot figures.
    md += ["", "## 1. Step-response overshoot of the paper's four settings", ""]
    md.append(
        f"Designed at {1 / OVERSHOOT_SAMPLE_PERIOD_S / 1e3:.0f} kHz and carried to the discrete loop by pole "
        "matching. *Continuous* is the continuous design's step response, *discrete* the linear "
        "(small-signal) response of the sampled loop, *179 degree step* the nonlinear loop (the "
        "core's recursion with its phase detector) after a 179 degree step."
    )
    md.append("")
    rows = []
    small_steps = {}
    for name, design in settings.items():
        r = design.report(sensor_noise_std=0.0)
        progress.step(f"design report: {name}")
        paper = PAPER_OVERSHOOT_PERCENT[name]
        ratio = (1.0 / r.sample_period_s) / r.bandwidth_hz if r.bandwidth_hz else float("nan")
        rows.append(
            [
                name,
                f"{paper:.1f} %",
                _pct(r.continuous_step.overshoot if r.continuous_step else None),
                _pct(r.linear_step.overshoot),
                f"{100.0 * r.linear_step.overshoot - paper:+.2f}",
                _pct(r.large_step.overshoot),
                _num(r.bandwidth_hz, ".1f") + " Hz",
                f"{ratio:.0f}",
                _num(r.linear_step.settling_time_s, ".4g", 1e3) + " ms",
            ]
        )
        small_steps[name] = design
    md.append(
        _table(
            [
                "setting",
                "paper",
                "continuous",
                "discrete (linear)",
                "discrete - paper (points)",
                "179 degree step",
                "-3 dB bandwidth",
                "fs / bandwidth",
                "2 % settling",
            ],
            rows,
        )
    )
    if plots:
        md += ["", "![small-signal step responses of the four settings](overshoot.png)"]

    # 2. The three observers.
    md += ["", "## 2. The three observers compared", ""]
    md.append(
        f"All three at {1 / COMPARISON_SAMPLE_PERIOD_S / 1e3:.0f} kHz with about 100 Hz of -3 dB bandwidth; "
        f"noise figures for white noise of {SENSOR_NOISE_STD} per channel (amplitude 1)."
    )
    md.append("")
    reports = {}
    rows = []
    for name, design in observers.items():
        r = design.report(sensor_noise_std=SENSOR_NOISE_STD)
        reports[name] = r
        progress.step(f"design report: {name}")
        rows.append(
            [
                name,
                design.method,
                ", ".join(f"{g:.6g}" for g in design.gains.gains),
                _num(r.bandwidth_hz, ".1f") + " Hz",
                _num(r.acceleration_constant_per_s2, ".4g") if r.order == 2 else "inf (type III)",
                _num(r.error_per_unit_jerk_s3, ".3g") if r.order == 3 else "-",
                _pct(r.linear_step.overshoot),
                _num(r.angle_error_rms_rad, ".3g", 1e3),
                _num(r.kalman_angle_floor_rad, ".3g", 1e3),
                _num(r.acquisition_speed_rad_s, ".4g"),
            ]
        )
    md.append(
        _table(
            [
                "observer",
                "design",
                "gains l",
                "bandwidth",
                "Ka (1/s^2)",
                "error per jerk (s^3)",
                "linear overshoot",
                "predicted RMS angle error (mrad)",
                "Kalman floor (mrad)",
                "speed step acquired (rad/s)",
            ],
            rows,
        )
    )

    # 3. Scenarios.
    md += ["", "## 3. Scenarios", ""]
    md.append(
        "The observers run as the paper's bare loops (float64, exact sin/cos, no diagnostics) on "
        f"seeded scenarios at {1 / COMPARISON_SAMPLE_PERIOD_S / 1e3:.0f} kHz. Errors are truth - estimate; "
        "the angle error is wrapped to [-pi, pi)."
    )
    md.append("")
    results: dict[str, dict[str, tuple[at.Estimates, at.Metrics]]] = {}
    scenario_data: dict[str, at.Scenario] = {}
    with_diagnostics: dict[str, tuple[at.Estimates, at.Metrics]] = {}
    for seed, spec in enumerate(specs, start=1):
        sc = at.Scenario.generate(spec.profile, spec.sensor, sample_period_s=COMPARISON_SAMPLE_PERIOD_S, seed=seed)
        scenario_data[spec.key] = sc
        results[spec.key] = {}
        for name, design in observers.items():
            # The bare loop of the paper: no diagnostics, no false-lock re-acquisition.
            est = at.track(design.gains, sc.y_c, sc.y_s, fault_thresholds=BARE_LOOP)
            m = at.metrics(sc, est, skip_s=spec.skip_s)
            results[spec.key][name] = (est, m)
            if spec.key == "step":
                # The same loop with the core's diagnostics (false-lock detection re-acquires).
                est_d = at.track(design.gains, sc.y_c, sc.y_s)
                with_diagnostics[name] = (est_d, at.metrics(sc, est_d, skip_s=spec.skip_s))
            progress.step(f"{spec.key}: {name} ({len(sc)} samples)")

    def scenario_table(spec: ScenarioSpec, extra_header, extra) -> str:
        rows = []
        for name in observers:
            est, m = results[spec.key][name]
            rows.append(
                [
                    name,
                    _num(m.angle_error_rad.rms, ".3g", 1e3),
                    _num(m.angle_error_rad.max, ".3g", 1e3),
                    _num(m.angle_error_rad.mean, ".3g", 1e3),
                    _num(m.speed_error_rad_s.rms if m.speed_error_rad_s else None, ".3g"),
                    *extra(name, est, m),
                ]
            )
        return _table(
            ["observer", "RMS angle error (mrad)", "max (mrad)", "mean (mrad)", "RMS speed error (rad/s)", *extra_header],
            rows,
        )

    step, ramp, accel, noise = specs
    md += [f"### {step.title}", ""]
    md.append(
        f"At rest for {HOLD_S * 1e3:.0f} ms, then the angle jumps by 179 degrees (a 180 degree step "
        "would start on the loop's unstable equilibrium)."
    )
    md.append("")
    after = lambda t: None if t is None else t - step.move_at_s  # noqa: E731
    md.append(
        scenario_table(
            step,
            [
                "overshoot",
                "2 % settling after the step (ms)",
                "locked (0.01 rad) after the step (ms)",
                "with diagnostics: overshoot",
                "with diagnostics: locked after (ms)",
            ],
            lambda name, est, m: [
                _pct(m.overshoot),
                _num(after(m.settling_time_s), ".4g", 1e3),
                _num(after(m.time_to_lock_s), ".4g", 1e3),
                _pct(with_diagnostics[name][1].overshoot),
                _num(after(with_diagnostics[name][1].time_to_lock_s), ".4g", 1e3),
            ],
        )
    )
    md.append("")
    md.append(
        "*With diagnostics*: the same observers with the core's default fault thresholds, whose "
        "false-lock detection sees the error beyond 90 degrees and re-acquires the angle from atan2."
    )
    md += ["", "![179 degree step](step_179.png)" if plots else "", ""]

    md += [f"### {ramp.title}", ""]
    md.append(
        "The 2nd-order (type II) loop lags by acceleration / Ka while the speed ramps; the type III "
        "loops follow a ramp of speed without steady error."
    )
    md.append("")
    md.append(scenario_table(ramp, ["locked from (ms)"], lambda name, est, m: [_num(m.time_to_lock_s, ".4g", 1e3)]))
    md += ["", "![speed ramp](speed_ramp.png)" if plots else "", ""]

    md += [f"### {accel.title}", ""]
    alpha = 2000.0
    md.append(
        f"Statistics after {accel.skip_s} s. Predicted steady-state error of the 2nd-order loop: "
        f"alpha / Ka = {alpha:.0f} / {reports['2nd-order ATO'].acceleration_constant_per_s2:.6g} = "
        f"{1e3 * alpha / reports['2nd-order ATO'].acceleration_constant_per_s2:.4g} mrad; the 3rd-order loops: 0."
    )
    md.append("")
    md.append(
        scenario_table(
            accel,
            ["predicted mean (mrad)"],
            lambda name, est, m: [
                _num(alpha / reports[name].acceleration_constant_per_s2, ".4g", 1e3) if reports[name].order == 2 else "0"
            ],
        )
    )
    md += ["", "![constant acceleration](acceleration.png)" if plots else "", ""]

    md += [f"### {noise.title}", ""]
    md.append(
        f"Statistics after {noise.skip_s} s, beside the RMS errors the design reports predict from the "
        "discrete Lyapunov equation of the linearised loop."
    )
    md.append("")
    md.append(
        scenario_table(
            noise,
            ["predicted RMS angle (mrad)", "measured / predicted", "predicted RMS speed (rad/s)"],
            lambda name, est, m: [
                _num(reports[name].angle_error_rms_rad, ".3g", 1e3),
                f"{m.angle_error_rad.rms / reports[name].angle_error_rms_rad:.3f}",
                _num(reports[name].speed_error_rms_rad_s, ".3g"),
            ],
        )
    )
    md += ["", "![noise](noise.png)" if plots else "", ""]

    # 4. Datasheets.
    md += ["## 4. Design datasheets (`DesignReport`)", ""]
    for name, r in reports.items():
        md += [f"### {name}", "", "| quantity | value |", "| --- | --- |", str(r).rstrip(), ""]

    if plots:
        _plot_all(plt, out_dir, specs, scenario_data, results, small_steps, progress)

    elapsed = time.perf_counter() - started
    md.append(f"_Computed in {elapsed:.1f} s._")
    path = out_dir / "report.md"
    path.write_text("\n".join(md) + "\n")
    progress.step(f"wrote {path}")
    return path


def _plot_all(plt, out_dir, specs, scenario_data, results, small_steps, progress) -> None:
    colours = {"2nd-order ATO": "tab:blue", "3rd-order ATO": "tab:orange", "Kalman ATO": "tab:green"}

    def save(fig, name: str) -> None:
        fig.tight_layout()
        fig.savefig(out_dir / name, dpi=110)
        plt.close(fig)
        progress.step(f"plot {name}")

    def error_mrad(sc, est):
        return 1e3 * np.angle(np.exp(1j * (sc.angle_rad - est.position)))

    # Step of 179 degrees.
    sc = scenario_data["step"]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    t_ms = 1e3 * sc.time_s
    a1.plot(t_ms, np.degrees(sc.angle_rad), "k--", lw=1, label="true angle")
    for name, (est, m) in results["step"].items():
        a1.plot(t_ms, np.degrees(est.position), color=colours[name], label=f"{name} (overshoot {_pct(m.overshoot)})")
        a2.plot(t_ms, np.degrees(est.speed) / 1e3, color=colours[name], label=name)
    a1.set_ylabel("angle (deg)")
    a1.set_title("Step of 179 degrees at 10 kHz")
    a1.legend(loc="lower right", fontsize=8)
    a2.set_ylabel("speed estimate (10^3 deg/s)")
    a2.set_xlabel("time (ms)")
    a1.grid(alpha=0.3), a2.grid(alpha=0.3)
    save(fig, "step_179.png")

    for key, title in (("speed_ramp", "Speed ramp"), ("acceleration", "Constant acceleration"), ("noise", "Noise")):
        sc = scenario_data[key]
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        t_ms = 1e3 * sc.time_s
        for name, (est, m) in results[key].items():
            a1.plot(t_ms, error_mrad(sc, est), color=colours[name], lw=0.8, label=name)
            a2.plot(t_ms, sc.speed_rad_s - est.speed, color=colours[name], lw=0.8, label=name)
        a1.set_ylabel("angle error (mrad)")
        a2.set_ylabel("speed error (rad/s)")
        a2.set_xlabel("time (ms)")
        spec = next(s for s in specs if s.key == key)
        a1.set_title(spec.title)
        for a in (a1, a2):
            a.grid(alpha=0.3)
            a.legend(loc="upper right", fontsize=8)
        if key != "noise":
            a1.set_ylim(*_robust_limits(np.concatenate([error_mrad(sc, e) for e, _ in results[key].values()])))
        a2.set_ylim(*_robust_limits(np.concatenate([sc.speed_rad_s - e.speed for e, _ in results[key].values()])))
        save(fig, f"{key}.png")

    # Small-signal step responses of the paper's four settings.
    fig, ax = plt.subplots(figsize=(8, 4.5))
    step_rad = 1e-3
    for name, design in small_steps.items():
        hold = 0.001
        profile = at.MotionProfile(0.0, 0.0).constant_speed(0.0, hold).step(step_rad, 0.12)
        sc = at.Scenario.generate(profile, sample_period_s=design.sample_period_s)
        est = at.track(design.gains, sc.y_c, sc.y_s, fault_thresholds=BARE_LOOP)
        m = at.metrics(sc, est)
        ax.plot(1e3 * (sc.time_s - hold), est.position / step_rad, label=f"{name}: {_pct(m.overshoot)} (paper {PAPER_OVERSHOOT_PERCENT[name]} %)")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set_xlim(-1, 120)
    ax.set_xlabel("time after the step (ms)")
    ax.set_ylabel("angle / step")
    ax.set_title("Small-signal step responses of the paper's settings (100 kHz)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    save(fig, "overshoot.png")


def _robust_limits(values: np.ndarray) -> tuple[float, float]:
    """Limits that show the bulk of a series (ignoring the first-sample transient)."""
    lo, hi = np.percentile(values, [0.5, 99.5])
    pad = 0.1 * (hi - lo) + 1e-12
    return float(lo - pad), float(hi + pad)
