"""``angletrack study`` and ``angletrack lot`` on Dask: the guide's example spec gives the same
rows on one local worker, on two (resuming a study stopped part way) and on a real scheduler
with two worker processes; a lot with a corrupt capture among good ones gives a row each and the outlier
report; the yield and lot plots are written; without the extra, one line says how to
install it."""

import dataclasses
import json
import math
import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from angletrack import capture, cli, study, study_dask, study_plots, study_timing

pq = pytest.importorskip("pyarrow.parquet", reason="the study extra (angletrack[study]) is installed by the tests")

ROOT = pathlib.Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide" / "studies.md"
TRACKER_DESIGN = ["design", "third-order", "--sample-rate", "20000", "--butterworth-time-constant", "2e-3",
                  "--format", "tracker"]


def guide_spec(directory: pathlib.Path) -> pathlib.Path:
    """The guide's example spec (its ```toml block) and the tracker files it names."""
    text = GUIDE.read_text(encoding="utf-8")
    spec = text.split("```toml\n", 1)[1].split("```", 1)[0]
    (directory / "study.toml").write_text(spec)
    for dtype, name in (("float64", "tracker64.json"), ("float32", "tracker32.json")):
        assert cli.main([*TRACKER_DESIGN, "--dtype", dtype, "-o", str(directory / name)]) == 0
    return directory / "study.toml"


def rows(results: pathlib.Path) -> dict:
    """The results by column, sorted by run, without the time each run took."""
    table = pq.read_table(results).sort_by("run")
    return {name: table.column(name).to_pylist() for name in table.column_names if name != "seconds"}


def same(a: dict, b: dict) -> bool:
    """Equal column by column, NaN equal to NaN (the learned calibration of a setup without one)."""
    return a.keys() == b.keys() and all(
        all(x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)) for x, y in zip(a[k], b[k]))
        and len(a[k]) == len(b[k]) for k in a)


@dataclasses.dataclass
class Scheduler:
    """A real Dask scheduler's file, and its two worker processes."""

    file: pathlib.Path
    workers: list


@pytest.fixture
def scheduler(tmp_path):
    """A real Dask scheduler and two worker processes, started as separate commands."""
    dask = pathlib.Path(sys.executable).parent / "dask"
    file = tmp_path / "scheduler.json"
    common = ["--no-dashboard", "--dashboard-address", ":0"]
    # The workers wait for the scheduler's file: all three start at once.
    started = [subprocess.Popen([str(dask), "scheduler", "--scheduler-file", str(file), "--port", "0",
                                 "--host", "127.0.0.1", *common], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        for _ in range(2):
            started.append(subprocess.Popen([str(dask), "worker", "--scheduler-file", str(file), "--nthreads", "1",
                                             "--no-nanny", *common],
                                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        deadline = time.monotonic() + 60
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        from dask.distributed import Client

        with Client(scheduler_file=str(file), timeout="60s") as client:
            client.wait_for_workers(2, timeout=60)
        yield Scheduler(file, started[1:])
    finally:
        for process in started:
            process.kill()
        for process in started:
            process.wait(timeout=30)


def test_the_guide_spec_gives_the_same_rows_on_any_workers(tmp_path, scheduler, capsys):
    spec = guide_spec(tmp_path)
    one, two, remote = tmp_path / "one.parquet", tmp_path / "two.parquet", tmp_path / "remote.parquet"
    assert cli.main(["study", str(spec), "-o", str(one), "--workers", "1", "--no-progress"]) == 0
    # Interrupted after 10 runs (on the scheduler, whose workers are up already) and resumed
    # on two local workers: the runs done are skipped.
    study.run_study(spec, two, study_dask.Cluster(scheduler_file=scheduler.file), progress=False, first_runs=10)
    assert len(pq.read_table(two)) == 10
    assert cli.main(["study", str(spec), "-o", str(two), "--workers", "2", "--resume", "--no-progress"]) == 0
    assert "64 runs" not in capsys.readouterr().out.splitlines()[-1] and len(pq.read_table(two)) == 64
    address = json.loads(scheduler.file.read_text())["address"]
    assert cli.main(["study", str(spec), "-o", str(remote), "--scheduler", address, "--no-progress"]) == 0
    reference = rows(one)
    assert reference["run"] == list(range(64)) and set(reference["error"]) == {""}
    assert same(reference, rows(two)) and same(reference, rows(remote))
    # Every sensor is the same sensor in each profile and setup; the spreads were drawn.
    assert len(set(reference["offset_cos"])) == 8 and len(set(reference["angle_error_h2_rad"])) == 8
    assert max(reference["max_error_rad"]) < 0.1 and "fixed" in reference["number_type"]
    # The online calibration learned each sensor's offset (within 2 mrad of the 5 mrad spread).
    online = [k for k, setup in enumerate(reference["setup"]) if setup == "f32_online"]
    assert all(abs(reference["learned_offset_c"][k] - reference["offset_cos"][k]) < 2e-3 for k in online)
    # Results already there: refused without --resume; with it, nothing is left to do.
    assert cli.main(["study", str(spec), "-o", str(one), "--workers", "1"]) == 2
    assert "give --resume" in capsys.readouterr().err
    # The plot's parameters: the drawn ones, in the crate's column order.
    assert study_plots.sensor_parameters(pq.read_table(one)) == [
        "amplitude", "offset_cos", "offset_sin", "amplitude_imbalance", "quadrature_error_rad", "third_harmonic",
        "noise_std", "angle_error_h2_rad"]
    png = tmp_path / "yield.png"
    assert cli.main(["plot", str(one), "-o", str(png)]) == 0
    assert png.stat().st_size > 10_000 and "f32: 8 sensors" in capsys.readouterr().out


def cruise_spec(directory: pathlib.Path, sensors: int, samples: int) -> pathlib.Path:
    """A study of ``sensors`` runs of ``samples`` samples each (one f64 tracker, one profile)."""
    assert cli.main([*TRACKER_DESIGN, "--dtype", "float64", "-o", str(directory / "tracker64.json")]) == 0
    document = {
        "format": "angletrack-study", "version": 1, "seed": 7, "sensors": sensors, "sample_period_s": 5e-5,
        "skip_s": 0.02, "sensor": {"offset_cos": {"normal": {"mean": 0.0, "std": 0.005}}, "noise_std": 0.001},
        "profiles": {"cruise": {"initial_speed_rad_s": 300.0, "segments": [
            {"constant_speed": {"speed_rad_s": 300.0, "duration_s": (samples - 1) * 5e-5}}]}},
        "setups": {"f64": {"tracker": "tracker64.json"}},
    }
    (directory / "cruise.json").write_text(json.dumps(document))
    return directory / "cruise.json"


def test_a_worker_lost_mid_study_loses_no_row_and_its_runs_are_redone(tmp_path, scheduler, monkeypatch):
    # 24 runs of about 15 ms, a few to a task, each task's rows a part file as it completes.
    spec = cruise_spec(tmp_path, sensors=24, samples=100_000)
    monkeypatch.setattr(study_dask, "TASK_SECONDS", 0.1)
    monkeypatch.setattr(study_dask, "PART_ROWS", 1)
    lost, survived = tmp_path / "lost.parquet", tmp_path / "one.parquet"
    cluster = study_dask.Cluster(scheduler_file=scheduler.file)
    outcome: dict = {}

    def run() -> None:
        try:
            outcome["summary"] = study.run_study(spec, lost, cluster, progress=False)[0]
        except BaseException as e:  # noqa: BLE001 - reported by the assertion below
            outcome["error"] = e

    from dask.distributed import Client

    with Client(scheduler_file=str(scheduler.file), timeout="30s") as watcher:
        pids = watcher.run(os.getpid)
        assert sorted(pids.values()) == sorted(w.pid for w in scheduler.workers)
        study_run = threading.Thread(target=run)
        study_run.start()
        # Once some rows are on disk, the worker busy with a task is killed mid-run.
        victim, deadline = None, time.monotonic() + 60
        while victim is None and study_run.is_alive() and time.monotonic() < deadline:
            if any(lost.glob("part-*.parquet")):
                victim = next((w for w, keys in watcher.processing().items() if keys), None)
            time.sleep(0.01)
        assert victim is not None, outcome
        os.kill(pids[victim], signal.SIGKILL)
        written = len(pq.read_table(lost))
        study_run.join(timeout=120)
        assert "error" not in outcome and 0 < written < 24, (outcome, written)
        assert "24 runs" in outcome["summary"]
        assert len(watcher.scheduler_info()["workers"]) == 1
    # The same study on the one worker left.
    study.run_study(spec, survived, cluster, progress=False)
    reference = rows(survived)
    assert reference["run"] == list(range(24)) and set(reference["error"]) == {""}
    assert same(rows(lost), reference)


def write_unit(path: pathlib.Path, offset_c: float, seed: int) -> None:
    """An end-of-line capture: 10 turns at 200 Hz electrical, 20 kHz, with a reference."""
    rng = np.random.default_rng(seed)
    t = np.arange(1000) / 20e3
    theta = 0.3 + 2 * math.pi * 200.0 * t
    seen = theta + 0.003 * np.sin(3 * theta)
    y_c = offset_c + np.cos(seen) + 1e-3 * rng.standard_normal(t.size)
    y_s = -0.01 + 1.02 * np.sin(seen) + 1e-3 * rng.standard_normal(t.size)
    capture.write_capture(path, {"time": t, "y_c": y_c, "y_s": y_s, "reference": theta})


def test_a_lot_with_a_corrupt_capture_gives_a_row_each_and_the_outliers(tmp_path, capsys):
    units = tmp_path / "captures"
    units.mkdir()
    for k in range(6):
        write_unit(units / f"unit{k}.csv", 0.02 + 0.001 * k, k)
    write_unit(units / "unit9.csv", 0.2, 9)  # an offset ten times the lot's
    (units / "unit5.csv").write_text("time,y_c,y_s\n0,1,0\n5e-5,oops,0.1\n")
    tracker = tmp_path / "tracker.json"
    assert cli.main([*TRACKER_DESIGN, "--dtype", "float64", "-o", str(tracker)]) == 0
    output = tmp_path / "lot.parquet"
    assert cli.main(["lot", str(units / "*.csv"), "--tracker", str(tracker), "-o", str(output), "--workers", "1",
                     "--no-progress", "--limit", "residual_rms_rad=,0.002"]) == 0
    report = capsys.readouterr().out
    table = pq.read_table(output).sort_by("file")
    files = [pathlib.Path(f).name for f in table.column("file").to_pylist()]
    assert files == ["unit0.csv", "unit1.csv", "unit2.csv", "unit3.csv", "unit4.csv", "unit5.csv", "unit9.csv"]
    status, errors = table.column("status").to_pylist(), table.column("error").to_pylist()
    assert status == ["ok"] * 5 + ["error", "ok"] and "unit5.csv" in errors[5] and "oops" in errors[5]
    offsets = table.column("offset_c").to_pylist()
    assert abs(offsets[2] - 0.022) < 2e-3 and abs(offsets[6] - 0.2) < 5e-3
    assert abs(table.column("h3_amplitude_rad").to_pylist()[0] - 0.003) < 5e-4
    assert all(u > 0 for u in table.column("h3_uncertainty_rad").to_pylist()[:5])
    assert "6 calibrated and tracked, 1 failed" in report
    assert "outlier" in report and "unit9.csv: offset_c" in report and "failed" in report and "unit5.csv" in report
    assert not any(f"unit{k}.csv: offset_c" in report for k in range(5))
    assert cli.main(["lot", str(units / "*.csv"), "--tracker", str(tracker), "-o", str(tmp_path / "x.parquet"),
                     "--limit", "offset=0,1"]) == 2
    assert "limit: offset is not a number column" in capsys.readouterr().err
    png = tmp_path / "lot.png"
    assert cli.main(["plot", str(output), "-o", str(png)]) == 0 and png.stat().st_size > 10_000


def test_without_the_extra_the_commands_say_how_to_install_it(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "dask", None)
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    for argv in (["study", "spec.toml", "-o", "r.parquet"],
                 ["lot", "c.csv", "--tracker", "t.json", "-o", "l.parquet"]):
        assert cli.main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "pip install 'angletrack[study]'" in err and "Traceback" not in err
    assert not (tmp_path / "r.parquet").exists()


def test_a_bad_spec_is_one_line_naming_the_field(tmp_path, capsys):
    spec = guide_spec(tmp_path)
    spec.write_text(spec.read_text().replace("std = 0.005 } }\noffset_sin", "std = -1 } }\noffset_sin"))
    assert cli.main(["study", str(spec), "-o", str(tmp_path / "r.parquet"), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err == (f"angletrack: error: {spec}: sensor.offset_cos.normal.std: must be a finite number of at "
                   "least 0, got -1\n")
    spec.write_text(spec.read_text().replace("std = -1", "std = 0.005"))
    other = tmp_path / "other.parquet"
    other.mkdir()
    writer = study_dask.PartWriter(other, "another specification")
    writer.add([{"run": 0}])
    writer.flush()
    assert cli.main(["study", str(spec), "-o", str(other), "--resume", "--workers", "1"]) == 2
    assert "holds results of another specification or lot" in capsys.readouterr().err
    os.remove(tmp_path / "tracker32.json")
    assert cli.main(["study", str(spec), "-o", str(tmp_path / "r.parquet"), "--workers", "1"]) == 2
    assert "setups.f32.tracker" in capsys.readouterr().err


def test_batches_hold_each_key_once_single_until_timed_then_a_task_long_then_shorter_to_the_end():
    batches = study_dask.Batches(iter(range(1000)), 1000)
    batches.threads = 2
    first = next(batches)
    assert first == [0]
    batches.observe(1, 1 / 64)  # 64 keys to a task of TASK_SECONDS
    rest = list(batches)
    sizes = [len(b) for b in rest]
    assert first + [k for b in rest for k in b] == list(range(1000))
    assert sizes[0] == round(study_dask.TASK_SECONDS * 64) and sizes == sorted(sizes, reverse=True)
    assert sizes[-1] == 1
    short = study_dask.Batches(iter(range(100)), 100, largest=4)
    next(short)
    short.observe(1, 1e-6)
    assert max(len(b) for b in short) == 4


def test_the_timeline_parts_the_workers_time_into_runs_tasks_waits_start_and_tail():
    timeline = study_timing.Timeline(100.0)
    timeline.add([{"seconds": 1.0}, {"seconds": 0.4}], ("a", 100.5, 102.0, 1.2))
    timeline.add([{"seconds": 3.0}], ("b", 100.4, 103.5, 2.5))
    timeline.add([{"seconds": 0.8}], ("a", 102.1, 103.0, 0.7))
    m = timeline.account(wall_s=3.6, threads=2, client_cpu_s=0.52)
    assert m["tasks"] == 3 and m["runs_s"] == pytest.approx(5.2)
    assert m["in_tasks_s"] == pytest.approx(0.3) and m["between_s"] == pytest.approx(0.1)
    assert m["first_s"] == pytest.approx(0.9) and m["tail_s"] == pytest.approx(0.5)
    assert m["per_run_overhead"] == pytest.approx(0.4 / 5.2) and m["overhead"] == pytest.approx(2.0 / 5.2)
    assert m["client_cpu_s"] == 0.52 and m["tasks_cpu_s"] == pytest.approx(4.4)
