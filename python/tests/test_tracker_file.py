"""Tracker files (issue 35, item 4): `angletrack design --format tracker`, `angletrack
calibrate --tracker`, `angletrack track --tracker` and `angletrack.Tracker`. The format's own
checks are the Rust crate's tests (`angletrack::tracker_file`); these hold the doors: the
file runs as the flags, gains file and calibration file it replaces, bit for bit, and an
option beside it that says otherwise is refused naming both."""

import json
import math
import pathlib
import re

import numpy as np
import pytest

import angletrack
from angletrack import cli

SAMPLE_RATE_HZ = 20_000.0


def counts_capture(path, *, duration_s=0.2, seed=1):
    """12-bit offset-binary counts of a sensor at 200 turns/s with offsets, imbalance,
    quadrature and a 3rd harmonic (amplitude 1800 counts around mid-scale 2048), and the
    reference; returns (y_c, y_s)."""
    t = np.arange(int(duration_s * SAMPLE_RATE_HZ)) / SAMPLE_RATE_HZ
    theta = 0.3 + 2 * math.pi * 200.0 * t
    read = theta + 4e-3 * np.sin(3 * theta + 0.3)
    rng = np.random.default_rng(seed)
    y_c = np.round(2048 + 1800 * (0.02 + np.cos(read) + 1e-3 * rng.normal(size=len(t)))).astype(np.int64)
    y_s = np.round(2048 + 1800 * (-0.02 + 1.03 * np.sin(read + 0.01) + 1e-3 * rng.normal(size=len(t))))
    y_s = y_s.astype(np.int64)
    reference = np.remainder(theta + math.pi, 2 * math.pi) - math.pi
    np.savetxt(path, np.column_stack([t, y_c, y_s, reference]), fmt=["%.17g", "%d", "%d", "%.17g"],
               delimiter=",", header="time,y_c,y_s,reference", comments="")
    return y_c, y_s


def run(*args):
    """The command's exit status (argparse's refusals exit)."""
    try:
        return cli.main([str(a) for a in args])
    except SystemExit as e:
        return e.code


def design(tmp_path, fmt, name, dtype="float32"):
    path = tmp_path / name
    assert run("design", "third-order", "--sample-rate", SAMPLE_RATE_HZ, "--butterworth-time-constant", "2e-3",
               "--dtype", dtype, "--format", fmt, "--output", path) == 0
    return path


def estimates(path):
    with np.load(path) as data:
        return {name: data[name] for name in data.files}


@pytest.fixture
def setup(tmp_path, capsys):
    """The same setup twice: a gains file, a calibration file and flags; and a tracker file
    from `design --format tracker` whose input is stated as 12-bit offset-binary counts (the
    ADC's full scale its range), completed by `calibrate --tracker`."""
    cap = tmp_path / "cap.csv"
    counts_capture(cap)
    gains, cal = design(tmp_path, "json", "g.json"), tmp_path / "cal.json"
    assert run("calibrate", cap, "--gains-file", gains, "-o", cal) == 0
    first = design(tmp_path, "tracker", "t.json")
    document = json.loads(first.read_text())
    document["input"] = {"kind": "counts", "bits": 12, "signed": False}
    document["adc_range"] = {"rule": "full_scale"}
    first.write_text(json.dumps(document))
    tracker = tmp_path / "t2.json"
    assert run("calibrate", cap, "--tracker", first, "-o", tracker) == 0
    capsys.readouterr()
    return {"capture": cap, "gains": gains, "calibration": cal, "tracker": tracker, "first": first}


@pytest.mark.parametrize("dtype, number_type, observer", [("float32", "f32", "(f32, 3rd order"),
                                                          ("fixed", "fixed", "(fixed point, 3rd order)")])
def test_track_with_the_tracker_file_gives_the_flags_numbers_bit_for_bit(tmp_path, setup, capsys, dtype,
                                                                         number_type, observer):
    cap, tracker = setup["capture"], tmp_path / f"{number_type}.json"
    angletrack.Tracker.from_file(setup["tracker"]).replaced(number_type=number_type).write(tracker)
    flags = ["--gains-file", setup["gains"], "--calibration", setup["calibration"], "--dtype", dtype,
             "--adc-bits", "12", "--adc-unsigned"]
    assert run("track", cap, *flags, "-o", tmp_path / "flags.npz") == 0
    assert run("track", cap, "--tracker", tracker, "-o", tmp_path / "tracker.npz") == 0
    printed = capsys.readouterr().out
    assert observer in printed and "ADC range 0 to 4095 (stated)" in printed, printed
    by_flags, by_tracker = estimates(tmp_path / "flags.npz"), estimates(tmp_path / "tracker.npz")
    assert by_flags.keys() == by_tracker.keys()
    for name in by_flags:
        np.testing.assert_array_equal(by_tracker[name], by_flags[name], err_msg=name)
    assert by_tracker["angle_rad"].dtype == (np.float32 if dtype == "float32" else np.float64)
    # Not trivially equal: the calibration and the angle correction were applied.
    assert np.count_nonzero(by_tracker["faults"]) < len(by_tracker["faults"])


def test_calibrate_adds_the_calibration_learned_to_the_tracker_file(setup):
    tracker = angletrack.Tracker.from_file(setup["tracker"])
    first = angletrack.Tracker.from_file(setup["first"])
    learned = angletrack.Calibration.from_json(setup["calibration"].read_text())
    d = tracker.document
    assert d["calibration"]["kind"] == "stored" and d["correction"]["kind"] == "harmonics"
    assert tuple(d["calibration"]["sensor"].values()) == tuple(learned.sensor)
    assert (tuple(d["correction"]["cos"]), tuple(d["correction"]["sin"])) == (learned.cos, learned.sin)
    # The rest of the setup is the first file's.
    for field in ("gains", "sample_period_s", "number_type", "input", "adc_range", "design"):
        assert d[field] == first.document[field], field


def test_the_python_tracker_tracks_arrays_as_track_does(tmp_path, setup):
    y_c, y_s = counts_capture(tmp_path / "again.csv")
    assert run("track", setup["capture"], "--tracker", setup["tracker"], "-o", tmp_path / "cli.npz") == 0
    tracker = angletrack.Tracker.from_file(setup["tracker"])
    est = tracker.track(y_c, y_s)
    by_cli = estimates(tmp_path / "cli.npz")
    np.testing.assert_array_equal(est.angle, by_cli["angle_rad"])
    np.testing.assert_array_equal(est.faults, by_cli["faults"])


def test_a_tracker_file_reads_back_and_writes_the_same_text(tmp_path, setup):
    tracker = angletrack.Tracker.from_file(setup["tracker"])
    tracker.write(tmp_path / "copy.json")
    assert (tmp_path / "copy.json").read_text() == setup["tracker"].read_text()
    assert angletrack.Tracker.from_files(setup["gains"], setup["calibration"], number_type="f32",
                                         input=tracker.document["input"],
                                         adc_range=tracker.document["adc_range"]).document == tracker.document


@pytest.mark.parametrize("extra, message", [
    (["--dtype", "float64"], '--dtype float64 contradicts --tracker {t}, whose number_type is "f32"'),
    (["--adc-range", "0,1023"], "--adc-range 0,1023 contradicts --tracker {t}, whose adc_range is"),
    (["--sample-rate", "10000"], "--sample-rate 10000.0 contradicts --tracker {t}, whose sample_period_s is 5e-05"),
    (["--calibrate"], '--calibrate (learn online) contradicts --tracker {t}, whose calibration.kind is "stored"'),
    (["--calibration", "{cal}"], "--calibration {cal} with --tracker {t}: the tracker file holds the calibration"),
    (["--gains-file", "{gains}"], "argument --gains-file: not allowed with argument --tracker"),
    (["-o", "{t}"], "--tracker"),
])
def test_options_that_contradict_the_file_are_refused_naming_both(tmp_path, setup, capsys, extra, message):
    names = {"t": setup["tracker"], "cal": setup["calibration"], "gains": setup["gains"]}
    extra = [e.format(**names) for e in extra]
    before = setup["tracker"].read_text()
    out = [] if "-o" in extra else ["-o", tmp_path / "est.csv"]
    assert run("track", setup["capture"], "--tracker", setup["tracker"], *extra, *out) == 2
    err = capsys.readouterr().err
    assert message.format(**names) in err and err.count("\n") == 1, err
    assert setup["tracker"].read_text() == before
    # The same value as the file's is no contradiction.
    assert run("track", setup["capture"], "--tracker", setup["tracker"], "--dtype", "float32", "--adc-bits", "12",
               "--adc-unsigned", "--sample-rate", SAMPLE_RATE_HZ, "-o", tmp_path / "same.csv") == 0


def test_another_document_or_an_unfit_setup_is_refused_in_one_line(tmp_path, setup, capsys):
    cap = setup["capture"]
    assert run("track", cap, "--tracker", setup["gains"], "-o", tmp_path / "e.csv") == 2
    err = capsys.readouterr().err
    assert f'{setup["gains"]}: format: not an angletrack-tracker document but an "angletrack-gains" one' in err
    # Counts tracked as units would keep their mid-scale: refused, naming the input.
    assert run("track", cap, "--tracker", design(tmp_path, "tracker", "units.json"), "-o", tmp_path / "e.csv") == 2
    assert "input: the tracker file says units" in capsys.readouterr().err
    # The binding's refusal: the crate's, naming the file and the field as written.
    document = {**json.loads(setup["tracker"].read_text()), "calibration": {"kind": "online", "max_offset": -1.0}}
    with pytest.raises(ValueError, match=r"^t\.json: calibration\.max_offset: "):
        angletrack.Tracker(document, "t.json")


def test_the_guides_example_is_a_tracker_file_and_the_pages_block():
    guide = pathlib.Path(__file__).resolve().parents[2] / "docs" / "guide"
    example = (guide / "tracker-example.json").read_text(encoding="utf-8")
    assert angletrack.Tracker.from_json(example, "tracker-example.json").to_json() == example
    page = (guide / "tracker-file.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```text\n(.*?)```\n", page, flags=re.S)
    assert example in blocks


def test_online_calibration_by_the_file_is_the_flags_calibrate(tmp_path, capsys):
    cap = tmp_path / "volts.csv"
    y_c, y_s = counts_capture(tmp_path / "counts.csv")
    t = np.arange(len(y_c)) / SAMPLE_RATE_HZ
    np.savetxt(cap, np.column_stack([t, (y_c - 2048) / 4000.0, (y_s - 2048) / 4000.0]), fmt="%.17g",
               delimiter=",", header="time,y_c,y_s", comments="")
    gains = design(tmp_path, "json", "g.json")
    tracker = angletrack.Tracker.from_gains_json(gains.read_text(), "g.json").replaced(
        calibration={"kind": "online"})
    tracker.write(tmp_path / "online.json")
    assert run("track", cap, "--gains-file", gains, "--calibrate", "--calibration-out", tmp_path / "c1.json",
               "-o", tmp_path / "flags.npz") == 0
    assert run("track", cap, "--tracker", tmp_path / "online.json", "--calibrate", "--calibration-out",
               tmp_path / "c2.json", "-o", tmp_path / "tracker.npz") == 0
    capsys.readouterr()
    by_flags, by_tracker = estimates(tmp_path / "flags.npz"), estimates(tmp_path / "tracker.npz")
    for name in by_flags:
        np.testing.assert_array_equal(by_tracker[name], by_flags[name], err_msg=name)
    assert (tmp_path / "c1.json").read_text() == (tmp_path / "c2.json").read_text()


def test_the_files_front_end_settings_reach_the_observer():
    theta = 0.3 + 2 * math.pi * 200.0 * np.arange(4000) / SAMPLE_RATE_HZ
    y_c, y_s = 0.9 * np.cos(theta), 0.9 * np.sin(theta)
    thresholds = {"nominal_amplitude": 0.9, "max_speed_rad_s": 3000.0, "re_acquire": False}
    tracker = angletrack.Tracker({"format": "angletrack-tracker", "version": 1, "sample_period_s": 5e-5,
                                  "gains": [0.0487706, 0.0012192, 1.52392e-5], "fault_thresholds": thresholds,
                                  "winding_check": {"amplitude": 0.9}, "calibration": {"kind": "online"}})
    est = tracker.track(y_c, y_s)
    direct = angletrack.Observer(tracker.gains, dtype=np.float64, fault_thresholds=angletrack.FaultThresholds(
        **thresholds), winding_amplitude=0.9, calibration="learn", measure_adc_range=True)
    expected = direct.update(y_c, y_s)
    np.testing.assert_array_equal(est.angle, expected.angle)
    np.testing.assert_array_equal(est.faults, expected.faults)
    assert tracker.observer.calibration_turns_learned == direct.calibration_turns_learned > 0


@pytest.mark.parametrize("fields", [
    {"correction": {"kind": "table", "errors_rad": [2e-3] * 8}},
    {"correction": {"kind": "harmonics", "cos": [0.0] * 8, "sin": [2e-3] + [0.0] * 7}},
    {"calibration": {"kind": "online", "max_offset": 0.05}, "correction": {"kind": "table", "errors_rad": [2e-3] * 8}},
])
def test_the_files_stages_run_as_a_firmware_runs_them(fields):
    """A correction table, harmonics without a stored calibration and an online calibration
    of its own settings run in Python as in the core's chain: the angle error they state is
    taken off the angle."""
    # 20 turns/s: the harmonic's 20 Hz well inside the loop's 220 Hz bandwidth.
    theta = 0.3 + 2 * math.pi * 20.0 * np.arange(8000) / SAMPLE_RATE_HZ
    base = {"format": "angletrack-tracker", "version": 1, "sample_period_s": 5e-5,
            "gains": [0.0487706, 0.0012192, 1.52392e-5]}
    plain = angletrack.Tracker(base, "t.json").track(np.cos(theta), np.sin(theta))
    corrected = angletrack.Tracker({**base, **fields}, "t.json").track(np.cos(theta), np.sin(theta))
    shift = np.remainder(plain.angle[4000:] - corrected.angle[4000:] + math.pi, 2 * math.pi) - math.pi
    if "sin" in fields["correction"]:  # a first harmonic of 2 mrad: 1.41 mrad RMS
        assert math.sqrt(np.mean(shift**2)) == pytest.approx(2e-3 / math.sqrt(2), rel=0.03)
    else:  # a constant 2 mrad
        np.testing.assert_allclose(shift, 2e-3, atol=1e-4)
    assert not np.any(corrected.faults[4000:])


def test_export_writes_the_firmware_constants_design_and_calibrate_write(tmp_path, setup, capsys):
    header = tmp_path / "motor.h"
    assert run("export", setup["tracker"], "--name", "motor", "-o", header) == 0
    text = header.read_text()
    gains = design(tmp_path, "c", "gains.h").read_text()
    learned = angletrack.Calibration.from_json(setup["calibration"].read_text())
    assert text.endswith(learned.to_c_header(name="motor", dtype="float32"))
    # The gains' declarations, as `design` writes them (float32, the file's number type).
    declarations = gains[gains.index("#ifndef"):].replace("ANGLETRACK", "MOTOR").replace("angletrack_", "motor_")
    assert declarations in text
    assert " * Input: 12-bit counts: AdcScaling::offset_binary(12); ADC range: the full scale.\n" in text
    # A tracker file is not an export format; a setting no generator writes is refused.
    assert run("export", setup["tracker"], "-o", tmp_path / "x.json") == 2
    online = angletrack.Tracker.from_file(setup["first"]).replaced(calibration={"kind": "online"})
    online.write(tmp_path / "online.json")
    assert run("export", tmp_path / "online.json") == 2
    assert "calibration.kind: an online calibration: no firmware constants" in capsys.readouterr().err
