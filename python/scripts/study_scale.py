"""Measures ``angletrack study`` on Dask (docs/guide/studies.md, "Scale"): one study of runs
of ``--samples`` samples each (one sensor through a third-order f64 tracker at 20 kHz),
run with 1 and then 2 local workers; prints the throughput of each, their ratio, and the
scheduling overhead: wall time x workers minus the runs' own time, over the runs' time.

    python python/scripts/study_scale.py --samples 1000000 --runs 16

Needs the package with its study extra installed; not part of the test command (it times).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pathlib
import resource
import tempfile

import numpy as np
import pyarrow.parquet as pq

from angletrack import capture, cli, lot, study, study_dask


def spec(directory: pathlib.Path, samples: int, runs: int, name: str = "scale.json") -> pathlib.Path:
    tracker = directory / "tracker.json"
    assert cli.main(["design", "third-order", "--sample-rate", "20000", "--butterworth-time-constant", "2e-3",
                     "--dtype", "float64", "--format", "tracker", "-o", str(tracker)]) == 0
    duration = (samples - 1) / 20e3
    document = {
        "format": "angletrack-study", "version": 1, "seed": 1, "sensors": runs, "sample_period_s": 5e-5,
        "skip_s": 0.02,
        "sensor": {"offset_cos": {"normal": {"mean": 0.0, "std": 0.005}}, "noise_std": 0.001},
        "profiles": {"cruise": {"initial_speed_rad_s": 300.0,
                                "segments": [{"constant_speed": {"speed_rad_s": 300.0, "duration_s": duration}}]}},
        "setups": {"f64": {"tracker": "tracker.json"}},
    }
    path = directory / name
    path.write_text(json.dumps(document))
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--runs", type=int, default=16)
    parser.add_argument("--lot-rows", type=int, default=0)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as scratch:
        directory = pathlib.Path(scratch)
        path = spec(directory, args.samples, args.runs)
        # The same number of runs of 2 samples: the workers' CPU time outside the runs
        # (starting, importing), taken off theirs.
        empty = spec(directory, 2, args.runs, "empty.json")
        throughput, cpu_per_run = {}, {}
        for workers in (1, 2):
            cpu = {}
            for name, study_spec in (("empty", empty), ("runs", path)):
                before = _children_cpu_s()
                _, measured = study.run_study(study_spec, directory / f"{name}{workers}.parquet",
                                              study_dask.Cluster(workers=workers), progress=False)
                cpu[name] = _children_cpu_s() - before
            output = directory / f"runs{workers}.parquet"
            wall = measured["seconds"]
            busy = sum(pq.read_table(output).column("seconds").to_pylist())
            throughput[workers] = args.runs * args.samples / wall
            cpu_per_run[workers] = (cpu["runs"] - cpu["empty"]) / args.runs
            print(f"{workers} worker(s): {args.runs} runs of {args.samples} samples in {wall:.2f} s wall, "
                  f"{busy:.2f} s in the runs: {throughput[workers] / 1e6:.2f} M samples/s, "
                  f"{busy / args.runs * 1e3:.1f} ms per run, scheduling overhead "
                  f"{100 * (wall * workers - busy) / busy:.1f} %; the workers' CPU time per run "
                  f"{cpu_per_run[workers] * 1e3:.1f} ms")
        print(f"2 workers / 1 worker: {throughput[2] / throughput[1]:.2f}x wall; CPU time per run "
              f"{cpu_per_run[2] / cpu_per_run[1]:.2f}x (1.00: the runs do not slow each other on two free cores)")
        if args.lot_rows:
            lot_capture(directory, args.lot_rows)
    print(f"load average after: {os.getloadavg()}")


def _children_cpu_s() -> float:
    """CPU time (user and system) of this process's finished children: the local cluster's
    workers once it is closed."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def lot_capture(directory: pathlib.Path, rows: int) -> None:
    """Times one capture of ``rows`` rows calibrated and tracked as a lot's unit."""
    t = np.arange(rows) / 20e3
    theta = 0.3 + 2 * math.pi * 50.0 * t
    seen = theta + 0.003 * np.sin(3 * theta)
    rng = np.random.default_rng(1)
    path = directory / "unit.npy"
    capture.write_capture(path, {"time": t, "y_c": 0.02 + np.cos(seen) + 1e-3 * rng.standard_normal(rows),
                                 "y_s": -0.01 + 1.02 * np.sin(seen) + 1e-3 * rng.standard_normal(rows),
                                 "reference": theta})
    tracker = directory / "tracker.json"
    row = lot.capture_row(str(path), tracker.read_text(), str(tracker), lot.Layout())
    print(f"lot: one capture of {rows} rows calibrated and tracked in {row['seconds']:.2f} s ({row['status']}, "
          f"load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
