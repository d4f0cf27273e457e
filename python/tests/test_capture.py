"""Reading captures (angletrack.read_capture, CaptureReader) and `angletrack track` on real
layouts: every malformed input is one line naming the file, line and column, exit 2."""

import json

import math

import numpy as np
import pytest

import angletrack
from angletrack import cli, export

SAMPLE_PERIOD = 1e-4


def gains_file(tmp_path, sample_period_s=SAMPLE_PERIOD, gains=(0.1, 0.005, 1e-4)):
    path = tmp_path / "gains.json"
    path.write_text(export.to_json(angletrack.Gains(list(gains), sample_period_s)))
    return path


def motion(n, sample_period_s=SAMPLE_PERIOD):
    t = np.arange(n) * sample_period_s
    return t, 0.5 + 20.0 * t + 150.0 * t**2


def write_text(path, header, rows, delimiter=","):
    lines = [delimiter.join(header)] if header else []
    lines += [delimiter.join(repr(float(v)) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def track(*args):
    return cli.main(["track", *map(str, args)])


def one_error_line(capsys):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("angletrack: error: "), err
    return err


def test_read_capture_gives_arrays_and_metadata(tmp_path):
    t, theta = motion(500)
    path = write_text(tmp_path / "run.csv", ["t", "sin", "cos", "ref"], zip(t, np.sin(theta), np.cos(theta), theta), ";")
    cap = angletrack.read_capture(path, columns="time=t,y_s=sin,y_c=cos,reference=ref")
    np.testing.assert_array_equal(cap.y_c, np.cos(theta))
    np.testing.assert_array_equal(cap.reference_rad, theta)
    assert len(cap) == cap.rows == 500 and cap.sample_dtype == "float64"
    assert cap.sample_rate_hz == pytest.approx(1e4, rel=1e-9)
    assert cap.columns == {"time": "t", "y_c": "cos", "y_s": "sin", "reference": "ref"}
    assert cap.format == "text, delimiter ;"
    # The same mapping as a dict, with indices.
    same = angletrack.read_capture(path, columns={"y_c": 2, "y_s": 1, "time": 0})
    np.testing.assert_array_equal(same.y_s, cap.y_s)


def test_npy_and_npz_captures_keep_their_dtype(tmp_path):
    counts = np.array([[2048, 3548], [2049, 3547], [2051, 3546]], dtype=np.int16)
    np.save(tmp_path / "counts.npy", counts)
    cap = angletrack.read_capture(tmp_path / "counts.npy", columns="y_c=0,y_s=1")
    assert cap.sample_dtype == "int16" and cap.y_c.dtype == np.float64
    np.testing.assert_array_equal(cap.y_s, counts[:, 1])
    t, theta = motion(100)
    np.savez_compressed(tmp_path / "run.npz", time=t, cos=np.cos(theta).astype(np.float32), sin=np.sin(theta))
    cap = angletrack.read_capture(tmp_path / "run.npz", columns="y_c=cos,y_s=sin")
    assert cap.sample_dtype == "float32" and cap.sample_rate_hz == pytest.approx(1e4)
    np.testing.assert_array_equal(cap.y_c, np.cos(theta).astype(np.float32))


def test_a_record_npy_capture_reads_its_fields_by_name(tmp_path, capsys):
    t, theta = motion(300)
    counts = (2048 + 1800 * np.column_stack([np.cos(theta), np.sin(theta)])).round()
    # Packed, mixed types and byte orders, as numpy.save writes a record array.
    packed = np.zeros(300, dtype=[("t", "<f8"), ("cos", "<i2"), ("sin", ">i4"), ("ref", "<f4")])
    packed["t"], packed["cos"], packed["sin"], packed["ref"] = t, counts[:, 0], counts[:, 1], theta
    np.save(tmp_path / "packed.npy", packed)
    # Aligned: padding between the fields.
    aligned = np.zeros(300, dtype=np.dtype([("cos", "u1"), ("sin", "<f8")], align=True))
    aligned["cos"], aligned["sin"] = np.arange(300) % 200, np.sin(theta)
    np.save(tmp_path / "aligned.npy", aligned)
    cap = angletrack.read_capture(tmp_path / "packed.npy", columns="y_c=cos,y_s=sin,reference=ref")
    np.testing.assert_array_equal(cap.y_c, counts[:, 0])
    np.testing.assert_array_equal(cap.y_s, counts[:, 1])
    np.testing.assert_array_equal(cap.reference_rad, theta.astype(np.float32))
    assert cap.sample_dtype == "int16" and cap.sample_rate_hz == pytest.approx(1e4, rel=1e-9)
    assert cap.columns == {"time": "t", "y_c": "cos", "y_s": "sin", "reference": "ref"}
    cap = angletrack.read_capture(tmp_path / "aligned.npy", columns="y_c=cos,y_s=sin", sample_rate_hz=1e4)
    np.testing.assert_array_equal(cap.y_c, np.arange(300) % 200)
    np.testing.assert_array_equal(cap.y_s, np.sin(theta))
    assert cap.sample_dtype == "uint8"
    # A text field is named, in one line.
    labelled = np.zeros(3, dtype=[("cos", "<f8"), ("label", "<U4")])
    np.save(tmp_path / "labelled.npy", labelled)
    with pytest.raises(angletrack.CaptureError, match='field "label" has dtype <U4'):
        angletrack.read_capture(tmp_path / "labelled.npy", columns="y_c=cos,y_s=cos")


def test_the_reader_streams_chunks_that_track_like_one_call(tmp_path):
    t, theta = motion(3000)
    path = write_text(tmp_path / "run.txt", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)), "  ")
    gains = angletrack.Gains([0.1, 0.005, 1e-4], SAMPLE_PERIOD)
    observer = angletrack.Observer(gains)
    reader = angletrack.CaptureReader(path, chunk_rows=700)
    positions = [observer.update(c.y_c, c.y_s).position for c in reader]
    assert [len(p) for p in positions] == [700] * 4 + [200]
    whole = angletrack.track(gains, np.cos(theta), np.sin(theta))
    np.testing.assert_array_equal(np.concatenate(positions), whole.position)


def test_track_streams_a_semicolon_capture_to_npy(tmp_path, capsys):
    t, theta = motion(3000)
    cap = write_text(tmp_path / "run.csv", ["t", "sin", "cos"], zip(t, np.sin(theta), np.cos(theta)), ";")
    out = tmp_path / "est.npy"
    assert track(cap, "--columns", "time=t,y_s=sin,y_c=cos", "--gains-file", gains_file(tmp_path), "-o", out) == 0
    est = np.load(out)
    assert est.dtype.names == ("time_s", "angle_rad", "position_rad", "speed_rad_s", "acceleration_rad_s2",
                               "phase_error", "faults")
    assert len(est) == 3000 and est["faults"].dtype == np.uint8
    assert np.max(np.abs(est["position_rad"][1000:] - theta[1000:])) < 1e-4
    assert "columns time=t, y_c=cos, y_s=sin" in capsys.readouterr().out


def test_track_writes_the_shortest_round_trip_digits(tmp_path):
    t, theta = motion(200)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)))
    out = tmp_path / "est.csv"
    assert track(cap, "--gains-file", gains_file(tmp_path), "--dtype", "float32", "-o", out) == 0
    rows = out.read_text().splitlines()[1:]
    est = angletrack.track(angletrack.Gains([0.1, 0.005, 1e-4], SAMPLE_PERIOD), np.cos(theta).astype(np.float32),
                           np.sin(theta).astype(np.float32))
    angles = [r.split(",")[1] for r in rows]
    # Each float32 reads back exactly from at most 9 significant digits (not %.17g's 17).
    assert [np.float32(a) for a in angles] == list(est.angle)
    digits = [len(a.lstrip("-").split("e")[0].replace(".", "").strip("0")) for a in angles]
    assert max(digits) <= 9


def test_raw_unsigned_adc_counts_track_with_their_mid_scale_removed(tmp_path, capsys):
    t, theta = motion(2000)
    counts = np.column_stack([t, np.round(2048 + 1500 * np.cos(theta)), np.round(2048 + 1500 * np.sin(theta))])
    cap = tmp_path / "adc.csv"
    cap.write_text("time,y_c,y_s\n" + "\n".join(f"{float(a)!r},{int(b)},{int(c)}" for a, b, c in counts) + "\n")
    out = tmp_path / "est.csv"
    assert track(cap, "--gains-file", gains_file(tmp_path), "-o", out) == 0
    printed = capsys.readouterr().out
    assert "counts (AdcScaling, mid-scale 2048)" in printed
    assert "faults latched: none; 0 samples rejected" in printed
    est = np.genfromtxt(out, delimiter=",", names=True)
    error = np.angle(np.exp(1j * (est["angle_rad"] - theta)))
    # Quantised to 1 count of 1500 (about 0.2 mrad): once the start-up transient from rest has
    # settled (half the capture), the angle is within 1 mrad.
    assert np.max(np.abs(error[1000:])) < 1e-3


def test_mostly_rejected_samples_are_an_error(tmp_path, capsys):
    t, theta = motion(2000)
    rows = [f"{float(a)!r},{'nan' if k % 4 else repr(math.cos(b))},{math.sin(b)!r}" for k, (a, b) in enumerate(zip(t, theta))]
    cap = tmp_path / "holes.csv"
    cap.write_text("time,y_c,y_s\n" + "\n".join(rows) + "\n")
    assert track(cap, "--gains-file", gains_file(tmp_path)) == 2
    err = one_error_line(capsys)
    assert "1500 of 2000 samples (75 %) were rejected as bad samples (fault BAD_SAMPLE)" in err


def test_a_rate_mismatch_is_refused_naming_both_rates_and_sample_rate_states_the_truth(tmp_path, capsys):
    t, theta = motion(2000, sample_period_s=5e-5)  # 20 kHz
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)))
    g = gains_file(tmp_path, sample_period_s=1e-4)  # 10 kHz
    out = tmp_path / "est.csv"
    assert track(cap, "--gains-file", g, "-o", out) == 2
    err = one_error_line(capsys)
    assert "the capture's time column says 20000 Hz but the gains are designed for 10000 Hz" in err
    assert not out.exists()  # refused before anything was written
    assert track(cap, "--gains-file", g, "--sample-rate", 20000, "-o", out) == 0
    assert "the gains designed for 10000 Hz run at the stated 20000 Hz" in capsys.readouterr().out


def test_track_reads_the_gains_file_once(tmp_path, capsys, file_reads):
    # At a stated rate other than the design's, both the gains and the note need the file.
    t, theta = motion(2000, sample_period_s=5e-5)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)))
    g = gains_file(tmp_path, sample_period_s=1e-4)
    assert track(cap, "--gains-file", g, "--sample-rate", 20000, "-o", tmp_path / "est.csv") == 0
    assert "the gains designed for 10000 Hz run at the stated 20000 Hz" in capsys.readouterr().out
    assert file_reads.count("gains.json") == 1


def test_a_time_column_in_microseconds_needs_its_unit(tmp_path, capsys):
    t, theta = motion(1000)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(np.round(t * 1e6), np.cos(theta), np.sin(theta)))
    g = gains_file(tmp_path)
    assert track(cap, "--gains-file", g) == 2
    assert "give --time-unit us" in one_error_line(capsys)
    assert track(cap, "--gains", "0.06,0.001") == 2
    assert "is the time column in ms, us or ns? give --time-unit" in one_error_line(capsys)
    assert track(cap, "--gains-file", g, "--time-unit", "us") == 0


def test_jittered_stamps_are_refused_unless_the_rate_is_stated(tmp_path, capsys):
    t, theta = motion(1000)
    jittered = t + np.random.default_rng(1).uniform(-2e-6, 2e-6, t.size)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(jittered, np.cos(theta), np.sin(theta)))
    assert track(cap, "--gains-file", gains_file(tmp_path)) == 2
    assert "differs from the capture's" in one_error_line(capsys)
    assert track(cap, "--gains-file", gains_file(tmp_path), "--sample-rate", 1e4) == 0


@pytest.mark.parametrize(
    "name, content, expected",
    [
        ("empty.csv", b"", "empty.csv:1: empty file"),
        ("header.csv", b"time,y_c,y_s\n", "header.csv:1: header only: no data rows"),
        ("one.csv", b"time,y_c,y_s\n0,1,0\n", "one.csv:2: only one data row"),
        ("bom_one.csv", b"\xef\xbb\xbftime,y_c,y_s\n0,1,0\n", "bom_one.csv:2: only one data row"),
        ("text.csv", b"time,y_c,y_s\n0,1,0\n1e-4,x,0\n", 'text.csv:3:2: column "y_c": "x" is not a number'),
        ("missing.csv", b"time,y_c,y_s\n0,1,0\n1e-4,1,\n", 'missing.csv:3:3: column "y_s": missing value'),
        ("unsorted.csv", b"time,y_c,y_s\n0,1,0\n2e-4,1,0\n1e-4,1,0\n", 'unsorted.csv:4:1: column "time": unsorted time'),
        ("dup.csv", b"time,y_c,y_s\n0,1,0\n1e-4,1,0\n1e-4,1,0\n", 'dup.csv:4:1: column "time": duplicated time'),
        ("nan_t.csv", b"time,y_c,y_s\n0,1,0\nnan,1,0\n", 'nan_t.csv:3:1: column "time": the time is NaN'),
        ("nan_r.csv", b"time,y_c,y_s,reference\n0,1,0,0\n1e-4,1,0,nan\n",
         'nan_r.csv:3:4: column "reference": the reference angle is NaN'),
        ("binary.csv", bytes(range(256)) * 4, "binary.csv:1:1: not a text capture: binary data"),
        ("scope.csv", b"t1,ch1,t2,ch2\n0,1,0,0\n1e-4,1,2e-4,0\n", 'scope.csv:3:3: time column "t2"'),
    ],
)
def test_malformed_captures_are_one_line_naming_file_line_and_column(tmp_path, capsys, name, content, expected):
    cap = tmp_path / name
    cap.write_bytes(content)
    columns = ["--columns", "y_c=ch1,y_s=ch2"] if name == "scope.csv" else []
    assert track(cap, "--gains-file", gains_file(tmp_path), *columns) == 2
    assert expected in one_error_line(capsys)
    with pytest.raises(angletrack.CaptureError) as raised:
        angletrack.read_capture(cap, columns=columns[1] if columns else None)
    e = raised.value
    assert isinstance(e, ValueError) and e.path == str(cap)
    assert expected.split(":")[1] == str(e.line)


@pytest.mark.parametrize(
    "args, expected",
    [
        (["--sample-rate", "0"], "argument --sample-rate: expected a positive number, got 0"),
        (["--skip", "-5"], "argument --skip: expected a non-negative number, got -5"),
    ],
)
def test_bad_numbers_are_refused_before_anything_is_written(tmp_path, capsys, args, expected):
    t, theta = motion(100)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)))
    out = tmp_path / "est.csv"
    with pytest.raises(SystemExit) as exit_:
        track(cap, "--gains-file", gains_file(tmp_path), "-o", out, *args)
    assert exit_.value.code == 2 and not out.exists()
    assert expected in capsys.readouterr().err


def test_a_fault_part_way_leaves_no_partial_output(tmp_path, capsys):
    t, theta = motion(200_000)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)))
    with open(cap, "a") as f:
        f.write("20.0,1,oops\n")
    out = tmp_path / "est.csv"
    assert track(cap, "--gains-file", gains_file(tmp_path), "-o", out) == 2
    assert 'run.csv:200002:3: column "y_s": "oops" is not a number' in one_error_line(capsys)
    assert not out.exists()


def test_a_gains_file_whose_order_contradicts_its_gains_is_refused(tmp_path, capsys):
    path = gains_file(tmp_path)
    doc = json.loads(path.read_text())
    doc["order"] = 2
    path.write_text(json.dumps(doc))
    with pytest.raises(ValueError, match=r"^g\.json: order: 2, but the file holds 3 gains$"):
        export.gains_from_json(path.read_text(), "g.json")
    t, theta = motion(100)
    cap = write_text(tmp_path / "run.csv", ["time", "y_c", "y_s"], zip(t, np.cos(theta), np.sin(theta)))
    assert track(cap, "--gains-file", path) == 2
    assert "gains.json: order: 2, but the file holds 3 gains" in one_error_line(capsys)


def test_the_reader_refuses_bad_arguments_naming_them():
    for kwargs, parameter in [({"columns": "y_c"}, "columns"), ({"delimiter": "::"}, "delimiter"),
                              ({"time_unit": "h"}, "time_unit"), ({"sample_rate_hz": 0.0}, "sample_rate_hz")]:
        with pytest.raises(angletrack.ConfigError) as raised:
            angletrack.read_capture("unused.csv", **kwargs)
        assert raised.value.parameter == parameter and str(raised.value).startswith(parameter)


def test_a_headerless_capture_with_a_given_delimiter_and_progress(tmp_path, capsys):
    t, theta = motion(1000)
    cap = write_text(tmp_path / "run.dat", None, zip(np.cos(theta), t, np.sin(theta)), "|")
    assert track(cap, "--gains-file", gains_file(tmp_path)) == 2
    assert "the capture has no header line (3 columns): name the signals' columns" in one_error_line(capsys)
    out = tmp_path / "est.csv"
    assert track(cap, "--gains-file", gains_file(tmp_path), "--delimiter", "|", "--columns", "y_c=0,time=1,y_s=2",
                 "--progress", "-o", out) == 0
    captured = capsys.readouterr()
    assert "angletrack track: 100.0 % 1,000 samples" in captured.err
    assert "columns time=1, y_c=0, y_s=2" in captured.out
    est = np.genfromtxt(out, delimiter=",", names=True)
    np.testing.assert_array_equal(est["time_s"], t)
