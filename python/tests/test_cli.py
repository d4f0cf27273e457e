"""The `angletrack` command line: each command runs and writes its files; the C header
compiles, the Rust block compiles, the JSON round-trips into the same gains."""

import json
import math
import pathlib
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

import angletrack
from angletrack import capture, cli, export

SCRIPT = pathlib.Path(sys.executable).parent / "angletrack"


def run_cli(*args, capsys=None):
    status = cli.main([str(a) for a in args])
    return status


def test_console_script_is_installed():
    out = subprocess.run([str(SCRIPT), "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"angletrack {angletrack.__version__}"


def test_design_c_header_compiles_and_holds_the_float32_gains(tmp_path, capsys):
    header = tmp_path / "rdc_gains.h"
    status = run_cli(
        "design", "third-order", "--sample-rate", 20000, "--pole-ratio", 39.04, "--pole-time-constant", 0.02,
        "--format", "c", "--output", header, "--name", "rdc",
    )
    assert status == 0
    printed = capsys.readouterr().out
    assert "| -3 dB bandwidth" in printed and f"wrote the gains (c, float32) to {header}" in printed
    text = header.read_text()
    assert "#define RDC_ORDER 3" in text
    source = tmp_path / "use.c"
    source.write_text(
        '#include "rdc_gains.h"\n'
        "float first_gain(void) { return rdc_gains[0] * RDC_SAMPLE_PERIOD_S * RDC_SAMPLE_RATE_HZ; }\n"
        "_Static_assert(sizeof(rdc_gains) / sizeof(rdc_gains[0]) == RDC_ORDER, \"order\");\n"
    )
    cc = shutil.which("cc")
    assert cc is not None, "a C compiler (cc) is needed for this test"
    subprocess.run([cc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-c", str(source), "-o", str(tmp_path / "use.o")],
                   check=True, cwd=tmp_path)
    # The literals are the float32 roundings of the designed float64 gains.
    design = angletrack.third_order_from_poles(
        pole_ratio=39.04, pole_time_constant_s=0.02, pole_frequency_ratio=3 * math.pi / 2, sample_period_s=1 / 20000
    )
    body = re.search(r"rdc_gains\[RDC_ORDER\] = \{(.*)\};", text).group(1)
    values = [np.float32(v.strip().rstrip("f")) for v in body.split(",")]
    assert values == [np.float32(g) for g in design.gains.gains]


def test_design_json_round_trips_into_the_same_gains(tmp_path):
    path = tmp_path / "gains.json"
    status = run_cli("design", "kalman", "--sample-rate", 10000, "--jerk-std", 1e5, "--noise-std", 0.01,
                     "--format", "json", "--output", path)
    assert status == 0
    loaded = export.gains_from_json(path.read_text())
    design = angletrack.kalman_from_jerk_std(jerk_std_rad_s3=1e5, sensor_noise_std=0.01, sample_period_s=1e-4)
    assert loaded == design.gains  # exact, float64
    assert loaded.gains == design.gains.gains and loaded.sample_period_s == design.gains.sample_period_s
    doc = json.loads(path.read_text())
    assert doc["design"]["specification"]["function"] == "kalman_from_jerk_std"


def test_design_sampled_second_order_when_the_overshoot_is_given(tmp_path):
    path = tmp_path / "gains.json"
    assert run_cli("design", "second-order", "--sample-rate", 20000, "--max-error", 1e-3, "--acceleration", 2000,
                   "--overshoot", 0.05, "--format", "json", "--output", path) == 0
    doc = json.loads(path.read_text())
    assert doc["design"]["specification"]["function"] == "second_order_from_tracking_error_sampled"
    assert "discretisation" not in doc["design"]["specification"]
    assert run_cli("design", "second-order", "--sample-rate", 20000, "--max-error", 1e-3, "--acceleration", 2000,
                   "--discretisation", "zoh") == 2


def test_design_rust_block_compiles(tmp_path):
    path = tmp_path / "gains.rs"
    assert run_cli("design", "second-order", "--sample-rate", 10000, "--bandwidth", 100, "--damping", 1.945,
                   "--format", "rust", "--output", path) == 0
    text = path.read_text()
    assert "pub const ANGLETRACK_GAINS: [f32; 2] = [" in text
    rustc = shutil.which("rustc")
    assert rustc is not None, "rustc is needed for this test"
    subprocess.run([rustc, "--edition", "2021", "--crate-type", "lib", "--emit", "metadata", "-o",
                    str(tmp_path / "gains.rmeta"), str(path)], check=True)


def test_design_prints_to_stdout_without_output(capsys):
    assert run_cli("design", "second-order", "--sample-rate", 10000, "--butterworth-time-constant", 0.005,
                   "--format", "json") == 0
    out = capsys.readouterr().out
    doc = json.loads(out[out.index("{"):])
    assert doc["order"] == 2 and doc["sample_period_s"] == 1e-4


@pytest.mark.parametrize(
    "name, marker",
    [("gains.json", '"format": "angletrack-gains"'), ("gains.H", "#define ANGLETRACK_ORDER 3"),
     ("gains.rs", "pub const ANGLETRACK_GAINS: [f32; 3] = ["), ("gains.txt", "#define ANGLETRACK_ORDER 3")],
)
def test_design_writes_the_format_its_output_names(tmp_path, name, marker):
    # Without --format, the output's extension names the format (C for any other).
    path = tmp_path / name
    assert run_cli("design", "kalman", "--sample-rate", 10000, "--jerk-std", 1e5, "--noise-std", 0.01,
                   "--output", path) == 0
    assert marker in path.read_text()


def test_design_refuses_a_format_its_output_does_not_name(tmp_path, capsys):
    path = tmp_path / "gains.h"
    assert run_cli("design", "kalman", "--sample-rate", 10000, "--jerk-std", 1e5, "--noise-std", 0.01,
                   "--format", "json", "--output", path) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--format json does not match --output" in err and "(c)" in err
    assert not path.exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["design", "second-order", "--sample-rate", "10000"], "no complete specification"),
        (["design", "second-order", "--sample-rate", "10000", "--bandwidth", "100", "--max-error", "1e-3",
          "--acceleration", "10"], "several specifications"),
        (["design", "kalman", "--sample-rate", "10000", "--q", "1e-9", "--r", "1", "--bandwidth", "3"], "--bandwidth not used"),
        (["design", "second-order", "--sample-rate", "10000", "--bandwidth", "-5"], "error: --bandwidth must be positive"),
        (["design", "kalman", "--sample-rate", "10000", "--jerk-std", "1e5", "--noise-std", "-1"],
         "error: --noise-std must be positive"),
        (["design", "kalman", "--sample-rate", "0", "--q", "1e-9", "--r", "1"], "sample_rate"),
    ],
)
def test_design_refuses_bad_specifications(args, message, capsys):
    assert cli.main(args) == 2
    assert message in capsys.readouterr().err


def write_capture(path, n=3000, with_reference=True):
    t = np.arange(n) * 1e-4
    theta = 0.5 + 20.0 * t + 0.5 * 300.0 * t**2
    cols = {"time": t, "y_c": np.cos(theta), "y_s": np.sin(theta)}
    if with_reference:
        cols["reference"] = theta
    capture.write_capture(path, cols)
    return theta


def test_track_writes_estimates_and_prints_metrics(tmp_path, capsys):
    cap = tmp_path / "capture.csv"
    theta = write_capture(cap)
    gains_file = tmp_path / "gains.json"
    gains_file.write_text(export.to_json(angletrack.Gains([0.1, 0.005, 1e-4], 1e-4)))
    out = tmp_path / "est.csv"
    assert run_cli("track", cap, "--gains-file", gains_file, "--output", out, "--skip", 0.1) == 0
    printed = capsys.readouterr().out
    assert "angle error" in printed and "RMS" in printed
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data.dtype.names == ("time_s", "angle_rad", "position_rad", "speed_rad_s", "acceleration_rad_s2",
                                "phase_error", "faults")
    assert len(data) == len(theta)
    # The type III loop follows the constant acceleration: the position matches the reference.
    assert np.max(np.abs(data["position_rad"][1000:] - theta[1000:])) < 1e-4
    direct = angletrack.track(angletrack.Gains([0.1, 0.005, 1e-4], 1e-4), np.cos(theta), np.sin(theta))
    np.testing.assert_allclose(data["position_rad"], direct.position, rtol=0, atol=1e-12)


def test_track_float32_with_gains_and_sample_rate(tmp_path, capsys):
    cap = tmp_path / "capture.csv"
    write_capture(cap, with_reference=False)
    assert run_cli("track", cap, "--gains", "0.06,0.001", "--dtype", "float32") == 0
    assert (tmp_path / "capture_estimates.csv").exists()
    assert "(f32, " in capsys.readouterr().out


def test_track_refuses_a_capture_without_signals(tmp_path, capsys):
    cap = tmp_path / "bad.csv"
    cap.write_text("time,a,b\n0,1,2\n")
    assert cli.main(["track", str(cap), "--gains", "0.06,0.001", "--sample-rate", "1e4"]) == 2
    assert "y_c and y_s" in capsys.readouterr().err


@pytest.mark.parametrize("flag, value, expected", [
    ("--gains-file", "missing.json", "--gains-file: {dir}/missing.json: No such file or directory"),
    ("--calibration", "missing.json", "--calibration: {dir}/missing.json: No such file or directory"),
    ("--calibration", "", "--calibration: {dir}: Is a directory"),
])
def test_track_names_the_flag_of_a_file_it_cannot_read(tmp_path, capsys, flag, value, expected):
    cap = tmp_path / "capture.csv"
    write_capture(cap, with_reference=False)
    gains = [] if flag == "--gains-file" else ["--gains", "0.06,0.001"]
    status = cli.main(["track", str(cap), *gains, flag, str(tmp_path / value) if value else str(tmp_path)])
    err = capsys.readouterr().err
    assert status == 2 and err.strip() == "angletrack: error: " + expected.format(dir=tmp_path), err


def test_track_names_the_output_flag_of_a_format_it_does_not_write(tmp_path, capsys):
    cap = tmp_path / "capture.csv"
    write_capture(cap, with_reference=False)
    for extra in ([], ["--dtype", "fixed"], ["--carrier-hz", "1000"]):
        status = cli.main(["track", str(cap), "--gains", "0.06,0.001", *extra, "-o", str(tmp_path / "e.dat")])
        err = capsys.readouterr().err
        assert status == 2 and "--output: " in err and "are CSV (.csv), NumPy (.npy) or .npz" in err, (extra, err)
        assert not (tmp_path / "e.dat").exists()


def test_report_writes_markdown_and_plots(tmp_path):
    out = tmp_path / "report"
    proc = subprocess.run([str(SCRIPT), "report", "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "[29/29]" in proc.stderr  # progress lines
    text = (out / "report.md").read_text()
    for paper in ("5.0 %", "20.8 %", "10.0 %", "30.9 %"):
        assert f"| {paper} |" in text
    # Section 2's noise columns, each on one stated model.
    assert "RMS angle error, sensor noise 0.01 only (mrad)" in text
    assert "RMS angle error on the Kalman model: noise 0.01 + random jerk 1e5 rad/s^3 (mrad)" in text
    assert "| unbounded |" in text
    # The discrete loop's overshoot is within 0.3 points of the paper's, row by row (section 1).
    section_1 = text.split("## 1. ", 1)[1].split("\n## 2. ", 1)[0]
    deltas = [float(d) for d in re.findall(r"\| ([+-]\d+\.\d\d) \|", section_1)]
    assert len(deltas) == 4 and all(abs(d) <= 0.3 for d in deltas)
    # Section 5: the imperfect sensor, with and without the online calibration.
    assert "## 5. A real sensor: offsets, gain imbalance and quadrature error" in text
    rows = re.findall(r"\| (uncorrected|online calibration) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|", text)
    (_, rms, first, second), (_, rms_c, first_c, second_c) = rows
    assert float(rms_c) < 3.0 < 50.0 < float(rms)  # mrad
    assert float(first) > 20 * float(first_c) and float(second) > 20 * float(second_c)
    # Section 6: the harmonic sensor, learned by `angletrack calibrate`, below 0.5 mrad after.
    assert "## 6. Angle-dependent errors" in text
    after = float(re.search(r"\| `angletrack track --calibration` \| ([\d.]+) \|", text).group(1))
    assert after < 0.5  # mrad
    assert (out / "harmonics" / "calibration.json").exists()
    for png in ("step_179.png", "speed_ramp.png", "acceleration.png", "noise.png", "overshoot.png",
                "sensor_errors.png", "harmonics.png"):
        data = (out / png).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000, png
        assert f"]({png})" in text


def test_design_fixed_constants_in_every_format(tmp_path):
    # The Kalman ATO at 10 kHz: its gains quantised for the fixed-point observer
    # (docs/theory.md §14), the same constants in C, Rust and JSON.
    spec = ["design", "kalman", "--sample-rate", 10000, "--jerk-std", 1e5, "--noise-std", 0.01, "--dtype", "fixed"]
    json_path, header, rust = tmp_path / "fixed.json", tmp_path / "fixed.h", tmp_path / "fixed.rs"
    assert run_cli(*spec, "--format", "json", "--output", json_path) == 0
    assert run_cli(*spec, "--format", "c", "--output", header, "--name", "rdc") == 0
    assert run_cli(*spec, "--format", "rust", "--output", rust) == 0
    doc = json.loads(json_path.read_text())
    assert doc["format"] == "angletrack-fixed-gains" and doc["order"] == 3
    # Each multiplier keeps at least 16 bits; the acceleration's shift is in 1..15.
    assert all(2**16 <= m < 2**31 for m in doc["multiplier"]) and 1 <= doc["acceleration_shift"] <= 15
    design = angletrack.kalman_from_jerk_std(1e5, 0.01, 1e-4)
    for q, g, m in zip(doc["quantised_gains"], design.gains.gains, doc["multiplier"]):
        # Within half a unit of the multiplier.
        assert abs(q / g - 1.0) <= 0.5 / m + 1e-15
    multiplier = ", ".join(str(m) for m in doc["multiplier"])
    assert f"rdc_gain_multiplier[RDC_ORDER] = {{{multiplier}}};" in header.read_text()
    assert f"multiplier: [{multiplier}], acceleration_shift: {doc['acceleration_shift']}" in rust.read_text()
    source = tmp_path / "use.c"
    source.write_text('#include "fixed.h"\nint first(void) { return rdc_gain_multiplier[0] + RDC_ACCELERATION_SHIFT; }\n')
    gcc = shutil.which("gcc")
    assert gcc is not None, "gcc is needed for this test"
    subprocess.run([gcc, "-std=c99", "-Wall", "-Werror", "-c", "-o", str(tmp_path / "use.o"), str(source)], check=True)
