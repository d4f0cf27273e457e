"""Inputs never destroyed, no silent wrong answer, real exports read (issue 24), and the
Python API's refusals naming their argument."""

import inspect
import json
import math
import os

import numpy as np
import pytest

import angletrack
from angletrack import cli, export, harmonics

SAMPLE_PERIOD = 1e-4
N = 3000


def gains_file(tmp_path, **fields):
    path = tmp_path / "gains.json"
    path.write_text(export.to_json(angletrack.Gains([0.1, 0.005, 1e-4], SAMPLE_PERIOD)))
    if fields:
        text = path.read_text()
        for key, value in fields.items():
            import json

            doc = json.loads(text)
            doc[key] = value
            text = json.dumps(doc)
        path.write_text(text)
    return path


def motion(n=N):
    t = np.arange(n) * SAMPLE_PERIOD
    return t, 0.5 + 40.0 * t + 150.0 * t**2


def csv_capture(path, reference_scale=None, counts=False):
    t, theta = motion()
    columns = [t, np.cos(theta), np.sin(theta)]
    header = "time,y_c,y_s"
    if reference_scale is not None:
        columns.append(theta * reference_scale)
        header += ",reference"
    if counts:  # signed ADC counts of amplitude 1800, as integers
        columns[1:3] = [np.round(1800 * y).astype(int) for y in columns[1:3]]
    rows = "\n".join(",".join(repr(v.item()) for v in row) for row in zip(*columns))
    path.write_text(header + "\n" + rows + "\n")
    return path


def columns(*arrays):
    """The arrays as lists of Python floats (whose repr is the plain number)."""
    return [a.tolist() for a in arrays]


def track(*args):
    return cli.main(["track", *map(str, args)])


def error_line(capsys):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("angletrack: error: "), err
    return err


# ------------------------------------------------------------------ never destroy input


def test_an_output_naming_the_capture_is_refused_in_every_form(tmp_path, capsys):
    g = gains_file(tmp_path)
    cap = csv_capture(tmp_path / "capture.csv")
    t, theta = motion()
    np.save(tmp_path / "capture.npy", np.column_stack([t, np.cos(theta), np.sin(theta)]))
    np.savez(tmp_path / "capture.npz", time=t, y_c=np.cos(theta), y_s=np.sin(theta))
    (tmp_path / "out").mkdir()
    os.symlink(cap, tmp_path / "link.csv")
    os.link(cap, tmp_path / "hard.csv")
    before = {p: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    cases = [
        (cap, ["-o", cap]),
        (cap, ["-o", tmp_path / "out" / ".." / "capture.csv"]),
        (cap, ["-o", tmp_path / "link.csv"]),
        (cap, ["-o", tmp_path / "hard.csv"]),
        (tmp_path / "capture.npy", ["--columns", "time=0,y_c=1,y_s=2", "-o", tmp_path / "capture.npy"]),
        (tmp_path / "capture.npz", ["-o", tmp_path / "capture.npz"]),
        (cap, ["--calibrate", "--calibration-out", cap, "-o", tmp_path / "est.csv"]),
        (cap, ["--plot", tmp_path / "hard.png", "-o", tmp_path / "hard.png"]),
        (cap, ["-o", g]),
    ]
    for capture, options in cases:
        assert track(capture, "--gains-file", g, *options) == 2, options
        err = error_line(capsys)
        assert "is the" in err and "an output never replaces an" in err, err
    after = {p: p.read_bytes() for p in before}
    assert after == before
    assert not (tmp_path / "est.csv").exists()


@pytest.mark.parametrize("dtype", ["float64", "fixed"])
def test_a_failed_run_leaves_no_partial_output_and_the_old_file(tmp_path, capsys, monkeypatch, dtype):
    # Chunks of 1000 rows, so that the malformed row is found after the output was opened.
    reader = angletrack.CaptureReader
    monkeypatch.setattr(angletrack, "CaptureReader",
                        lambda *args, chunk_rows, **options: reader(*args, chunk_rows=1000, **options))
    g = gains_file(tmp_path)
    cap = csv_capture(tmp_path / "capture.csv", counts=dtype == "fixed")
    lines = cap.read_text().splitlines()
    lines[2500] = "0.25,abc,0"  # past the first chunk
    cap.write_text("\n".join(lines) + "\n")
    out = tmp_path / "est.csv"
    out.write_text("old estimates\n")
    assert track(cap, "--gains-file", g, "--dtype", dtype, "-o", out) == 2
    assert "capture.csv:2501:2" in error_line(capsys)
    assert out.read_text() == "old estimates\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["capture.csv", "est.csv", "gains.json"]


def test_python_check_outputs_and_output_file(tmp_path):
    cap = csv_capture(tmp_path / "capture.csv")
    with pytest.raises(angletrack.CaptureError, match=r"-o: is the capture .*the same file"):
        angletrack.capture.check_outputs({"-o": tmp_path / "." / "capture.csv"}, {"capture": cap})
    angletrack.capture.check_outputs({"-o": tmp_path / "a.csv", "--plot": None}, {"capture": cap})
    with pytest.raises(RuntimeError):
        with angletrack.OutputFile(cap) as target:
            open(target.temporary_path, "w").write("half")
            raise RuntimeError("a failure part way")
    assert cap.read_text().startswith("time,y_c,y_s\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["capture.csv"]


# ------------------------------------------------------------------ silent wrong answers


def test_one_column_for_two_roles_is_refused(tmp_path, capsys):
    cap = csv_capture(tmp_path / "capture.csv")
    assert track(cap, "--gains-file", gains_file(tmp_path), "--columns", "y_c=1,y_s=1") == 2
    assert "columns: y_c and y_s are both column 1 (\"y_c\")" in error_line(capsys)


def test_the_estimates_format_follows_the_extension(tmp_path, capsys):
    g = gains_file(tmp_path)
    cap = csv_capture(tmp_path / "capture.csv")
    assert track(cap, "--gains-file", g, "-o", tmp_path / "est.npz") == 0
    with np.load(tmp_path / "est.npz") as est:
        assert sorted(est.files) == sorted(["time_s", "angle_rad", "position_rad", "speed_rad_s",
                                            "acceleration_rad_s2", "phase_error", "faults"])
        assert est["faults"].dtype == np.uint8 and len(est["angle_rad"]) == N
        t, theta = motion()
        assert est["position_rad"][-1] == pytest.approx(theta[-1], abs=1e-3)
    for output, options in (("est.dat", []), ("est.txt", ["--dtype", "fixed"])):
        assert track(cap, "--gains-file", g, "-o", tmp_path / output, *options) == 2
        assert "the estimates' format follows the extension" in error_line(capsys)
        assert not (tmp_path / output).exists()


@pytest.mark.parametrize("unit, scale", [("degrees", 180 / math.pi), ("turns", 1 / (2 * math.pi))])
def test_a_reference_in_degrees_or_turns_is_named_in_the_summary(tmp_path, capsys, unit, scale):
    cap = csv_capture(tmp_path / f"{unit}.csv", reference_scale=scale)
    assert track(cap, "--gains-file", gains_file(tmp_path), "--skip", 0.1, "-o", tmp_path / "est.csv") == 0
    out = capsys.readouterr().out
    assert f"hint: the reference column looks like {unit}, not radians" in out, out
    radians = csv_capture(tmp_path / "radians.csv", reference_scale=1.0)
    assert track(radians, "--gains-file", gains_file(tmp_path), "-o", tmp_path / "est.csv") == 0
    assert "hint" not in capsys.readouterr().out


# ------------------------------------------------------------------ readers for real exports


def tracked_rms(capsys):
    out = capsys.readouterr().out
    line = next(row for row in out.splitlines() if row.strip().startswith("RMS "))
    return float(line.split()[1]), out


def test_decimal_commas_and_an_oscilloscope_export_track(tmp_path, capsys):
    g = gains_file(tmp_path)
    t, theta = motion()
    rows = [f"{a!r};{b!r};{c!r};{d!r}".replace(".", ",") for a, b, c, d in zip(*columns(t, np.cos(theta), np.sin(theta), theta))]
    comma = tmp_path / "comma.csv"
    comma.write_text("Zeit;cos;sin;theta\n" + "\n".join(rows) + "\n")
    assert track(comma, "--gains-file", g, "--columns", "time=Zeit", "--skip", 0.1, "-o", tmp_path / "e.csv") == 0
    rms, out = tracked_rms(capsys)
    assert rms < 1e-3 and "decimal comma" in out
    metadata = "Model,MSO44\nFirmware Version,1.24\nRecord Length,3000\nSample Interval,1e-4\nLabel,,,\n"
    scope = tmp_path / "scope.csv"
    scope.write_text(metadata + "TIME,CH1,CH2,REF\n" + "\n".join(
        f"{a!r},{b!r},{c!r},{d!r}" for a, b, c, d in zip(*columns(t, np.cos(theta), np.sin(theta), theta))) + "\n")
    assert track(scope, "--gains-file", g, "--columns", "y_c=CH1,y_s=CH2,reference=REF", "--skip", 0.1,
                 "-o", tmp_path / "e.csv") == 0
    rms, out = tracked_rms(capsys)
    assert rms < 1e-3 and "5 metadata lines skipped" in out


def test_skip_rows_latin1_utf16_ignored_time_and_rounded_stamps(tmp_path, capsys):
    g = gains_file(tmp_path)
    t, theta = motion()
    body = "\n".join(f"{a:.3f},{b!r},{c!r}" for a, b, c in zip(*columns(t, np.cos(theta), np.sin(theta))))  # ms rounding
    rounded = tmp_path / "rounded.csv"
    rounded.write_text("Rate,1e4,Hz\nProbe,10,x\ntime,y_c,y_s\n" + body + "\n")
    assert track(rounded, "--gains-file", g, "--skip-rows", 2, "-o", tmp_path / "e.csv") == 2
    assert "duplicated time" in error_line(capsys)
    assert track(rounded, "--gains-file", g, "--skip-rows", 2, "--sample-rate", 1e4, "-o", tmp_path / "e.csv") == 0
    assert track(rounded, "--gains-file", g, "--skip-rows", 2, "--columns", "time=-", "-o", tmp_path / "e.csv") == 0
    assert "columns y_c=y_c, y_s=y_s)" in capsys.readouterr().out
    latin1 = tmp_path / "latin1.csv"
    latin1.write_bytes("Zeit (µs);cos;sin\n".encode("latin-1") + "\n".join(
        f"{round(a * 1e6)};{b!r};{c!r}".replace(".", ",") for a, b, c in zip(*columns(t, np.cos(theta), np.sin(theta)))
    ).encode("latin-1"))
    cap = angletrack.read_capture(latin1, columns="time=Zeit (µs)", time_unit="us")
    assert cap.sample_rate_hz == pytest.approx(1e4) and "Latin-1" in cap.format
    utf16 = tmp_path / "utf16.csv"
    utf16.write_text("time\ty_c\ty_s\n" + body.replace(",", "\t") + "\n", encoding="utf-16")
    cap = angletrack.read_capture(utf16, sample_rate_hz=1e4)
    np.testing.assert_array_equal(cap.y_s, np.sin(theta))


def test_a_gains_file_error_names_the_file_and_the_field(tmp_path, capsys):
    cap = csv_capture(tmp_path / "capture.csv")
    for field, value in (("sample_period_s", "1e-4"), ("gains", [0.1, "x", 1e-4])):
        g = gains_file(tmp_path, **{field: value})
        assert track(cap, "--gains-file", g, "-o", tmp_path / "e.csv") == 2
        err = error_line(capsys)
        assert f"{g}: {field}: must be " in err and '"' in err, err


# ------------------------------------------------------------------ Python API


def test_refusals_name_their_argument_and_int64_counts_are_taken():
    g = angletrack.Gains([0.1, 0.005, 1e-4], SAMPLE_PERIOD)
    for make, parameter in ((lambda: angletrack.ObserverBatch(g, -1), "channels"),
                            (lambda: angletrack.ObserverBatch(g, "2"), "channels"),
                            (lambda: angletrack.CaptureReader("x.csv", chunk_rows=1), "chunk_rows"),
                            (lambda: angletrack.Gains(["a", 1], SAMPLE_PERIOD), "gains"),
                            (lambda: angletrack.Gains([0.1, 0.005], "1e-4"), "sample_period_s")):
        with pytest.raises(angletrack.ConfigError, match=rf"^{parameter}: ") as e:
            make()
        assert e.value.parameter == parameter
    with pytest.raises(TypeError, match=r"^gains: expected an angletrack.Gains.*got str 'gains'"):
        angletrack.track("gains", np.ones(3), np.zeros(3))
    assert angletrack.ObserverBatch(g, np.int64(3)).channels == 3
    t, theta = motion()
    c64 = np.round(2048 + 1500 * np.cos(theta)).astype(np.int64)
    s64 = np.round(2048 + 1500 * np.sin(theta)).astype(np.int64)
    as_u16 = angletrack.track(g, c64.astype(np.uint16), s64.astype(np.uint16))
    np.testing.assert_array_equal(angletrack.track(g, c64, s64).position, as_u16.position)
    signed = angletrack.track(g, c64 - 2048, s64 - 2048).position
    np.testing.assert_array_equal(signed, angletrack.track(g, (c64 - 2048).astype(np.int32),
                                                           (s64 - 2048).astype(np.int32)).position)
    # A batch takes floats of amplitude about 1, not counts (test_argument_checks.py).
    with pytest.raises(TypeError, match=r"^y_c: .*raw ADC counts of dtype int64"):
        angletrack.track_batch(g, np.stack([c64, c64]), np.stack([s64, s64]))
    with pytest.raises(angletrack.ConfigError, match=r"^y_s: int64 count 1099511627776 at index 1 is beyond"):
        angletrack.track(g, c64[:3], np.array([1, 2**40, 2]))
    # int64 counts that do not show their signedness (all non-negative, no swing about a
    # mid-scale) are refused naming adc_signed, not guessed; stated, they are tracked.
    with pytest.raises(angletrack.ConfigError, match=r"^adc_signed: .*adc_signed=True"):
        angletrack.track(g, c64[:3], np.array([1, 70000, 2]))
    still_c, still_s = np.full(2000, 2048 + 900), np.full(2000, 2048 + 1559)
    with pytest.raises(angletrack.ConfigError, match=r"^adc_signed: "):
        angletrack.track(g, still_c, still_s)
    at_rest = angletrack.track(g, still_c, still_s, adc_signed=False)
    assert abs(at_rest.angle[-1] - np.pi / 3) < 1e-3 and not np.any(at_rest.faults)


def test_constructors_show_their_signatures_and_stubs_return_types():
    assert str(inspect.signature(angletrack.ObserverBatch)) == "(gains, channels, *, dtype=None, sin_cos=None)"
    assert "decimal=None, skip_rows=0" in str(inspect.signature(angletrack.CaptureReader))
    assert str(inspect.signature(angletrack.OutputFile)) == "(path)"
    assert inspect.signature(harmonics.track_calibrated).return_annotation == "Estimates"


def test_a_table_writer_names_the_column_it_refuses(tmp_path):
    path = tmp_path / "table.npz"
    path.write_bytes(b"kept")
    columns = [("time_s", np.float64), ("angle_binary", "int32"), ("faults", np.dtype(np.uint8))]
    with pytest.raises(ValueError, match=r"columns: code: dtype int64: expected float64, float32, uint8 or int32"):
        angletrack.TableWriter(path, [("code", np.int64)])
    with pytest.raises(ValueError, match=r"arrays: angle_binary: expected a contiguous 1-D int32 array"):
        with angletrack.TableWriter(path, columns) as w:
            w.write([np.zeros(3), np.zeros(3, dtype=np.int64), np.zeros(3, dtype=np.uint8)])
    with pytest.raises(ValueError, match=r"faults: 2 values where the first column has 3"):
        with angletrack.TableWriter(path, columns) as w:
            w.write([np.zeros(3), np.zeros(3, dtype=np.int32), np.zeros(2, dtype=np.uint8)])
    assert path.read_bytes() == b"kept"
    with angletrack.TableWriter(path, columns) as w:
        w.write([np.array([0.0, 1e-4]), np.array([-7, 2**31 - 1], dtype=np.int32), np.array([0, 4], dtype=np.uint8)])
    with np.load(path) as table:
        assert table.files == ["time_s", "angle_binary", "faults"]
        assert table["angle_binary"].tolist() == [-7, 2**31 - 1] and table["faults"].dtype == np.uint8


def test_design_writes_gains_files_that_read_back_exactly(tmp_path):
    # Float gains and fixed-point constants, each with its design, read back by the crate.
    spec = ["design", "kalman", "--sample-rate", "10000", "--jerk-std", "1e5", "--noise-std", "0.01", "--format", "json"]
    assert cli.main([*spec, "--output", str(tmp_path / "g.json")]) == 0
    assert cli.main([*spec, "--dtype", "fixed", "--output", str(tmp_path / "f.json")]) == 0
    design = angletrack.kalman_from_jerk_std(1e5, 0.01, 1e-4)
    text = (tmp_path / "g.json").read_text()
    assert export.gains_from_json(text).gains == design.gains.gains
    assert json.loads(text)["design"]["specification"]["jerk_std_rad_s3"] == 1e5
    constants = export.fixed_from_json((tmp_path / "f.json").read_text(), "f.json")
    assert constants == design.fixed_constants()
    broken = (tmp_path / "f.json").read_text().replace('"acceleration_shift": ', '"acceleration_shift": -', 1)
    with pytest.raises(ValueError, match=r"^f\.json: acceleration_shift: must be an integer from 0 to 15$"):
        export.fixed_from_json(broken, "f.json")
