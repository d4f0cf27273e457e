"""Measures ``angletrack study`` on Dask (docs/guide/studies.md, "Scale"): one study of runs
of ``--samples`` samples each (one sensor through a third-order f64 tracker at 20 kHz),
run with 1 and then 2 local workers, ``--repeat`` times. For each, it prints the machine's
load average before, the throughput, a run's own time (measured inside the run), and where
the rest of the workers' time went (angletrack.study_timing): the per-run overhead of the
scheduling (each task's time beside its runs and each worker's wait between two tasks, over
the runs' time), the waits for the first task and at the end, the CPU time of a run's
thread and of the client, and the whole overhead (wall time x workers less the runs' time,
over the runs' time); then the spread of the 2-worker / 1-worker throughput ratio, of the
per-run overhead, and of the ratio the CPU times allow on two free cores (what a loaded
machine's wall times cannot show). With ``--baseline``, the same runs first in 1 and then 2
plain processes (no Dask, no scheduler): what the machine's two cores give two independent
runs, the ceiling of the workers' ratio.

    python python/scripts/study_scale.py --samples 1000000 --runs 64 --repeat 3 --baseline

Needs the package with its study extra installed; not part of the test command (it times).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import json
import math
import os
import pathlib
import statistics
import tempfile
import time

import numpy as np

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
    parser.add_argument("--runs", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--lot-rows", type=int, default=0)
    parser.add_argument("--baseline", action="store_true")
    args = parser.parse_args()
    ratios, overheads, estimates = [], [], []
    with tempfile.TemporaryDirectory() as scratch:
        directory = pathlib.Path(scratch)
        path = spec(directory, args.samples, args.runs)
        if args.baseline:
            plain_processes(path, args.runs, args.samples, args.repeat)
        for repeat in range(args.repeat):
            throughput, run_s, cpu, client = {}, {}, {}, {}
            for workers in (1, 2):
                load = os.getloadavg()[0]
                _, m = study.run_study(path, directory / f"runs{workers}-{repeat}.parquet",
                                       study_dask.Cluster(workers=workers), progress=False)
                throughput[workers] = args.runs * args.samples / m["seconds"]
                run_s[workers] = m["runs_s"] / args.runs
                cpu[workers] = m["tasks_cpu_s"] / args.runs
                client[workers] = m["client_cpu_s"] / m["seconds"]
                if workers == 2:
                    overheads.append(m["per_run_overhead"])
                print(f"load {load:.2f}, {workers} worker(s): {args.runs} runs of {args.samples} samples in "
                      f"{m['seconds']:.2f} s wall ({m['startup_s']:.1f} s start-up before), "
                      f"{throughput[workers] / 1e6:.2f} M samples/s, {run_s[workers] * 1e3:.1f} ms a run "
                      f"({cpu[workers] * 1e3:.1f} ms CPU); "
                      f"{m['tasks']} tasks; per-run overhead {100 * m['per_run_overhead']:.2f} % "
                      f"(in tasks {m['in_tasks_s'] * 1e3:.0f} ms, between {m['between_s'] * 1e3:.0f} ms); "
                      f"first task after {m['first_s'] * 1e3:.0f} ms, tail {m['tail_s'] * 1e3:.0f} ms; "
                      f"the client {100 * client[workers]:.1f} % of a core; whole overhead {100 * m['overhead']:.1f} %")
            ratios.append(throughput[2] / throughput[1])
            estimates.append((2 - client[2]) * cpu[1] / cpu[2])
            print(f"  2 workers / 1 worker: {ratios[-1]:.2f}x throughput; a run took {run_s[2] / run_s[1]:.2f}x as "
                  f"long beside another ({cpu[2] / cpu[1]:.2f}x the CPU time); on two free cores about "
                  f"{estimates[-1]:.2f}x (the two cores less the client's share, times a run's CPU time with 1 worker "
                  "over that with 2)")
        print(f"ratio over {len(ratios)} repeats: min {min(ratios):.2f}x, median {statistics.median(ratios):.2f}x, "
              f"max {max(ratios):.2f}x; per-run overhead with 2 workers: {100 * min(overheads):.2f} to "
              f"{100 * max(overheads):.2f} %; the CPU-time estimate {min(estimates):.2f}x to "
              f"{max(estimates):.2f}x; load average now {os.getloadavg()[0]:.2f}")
        if args.lot_rows:
            lot_capture(directory, args.lot_rows)


def plain_processes(path: pathlib.Path, runs: int, samples: int, repeat: int) -> None:
    """The runs in 1 and 2 plain processes, one run a call (the machine's ceiling)."""
    resolved, _ = study.read_spec(path)
    ratios = []
    for _ in range(repeat):
        throughput = {}
        for processes in (1, 2):
            with concurrent.futures.ProcessPoolExecutor(processes) as pool:
                list(pool.map(study.study_task, [resolved] * processes, [[r] for r in range(processes)]))
                start = time.perf_counter()
                list(pool.map(study.study_task, [resolved] * runs, [[r] for r in range(runs)]))
                throughput[processes] = runs * samples / (time.perf_counter() - start)
        ratios.append(throughput[2] / throughput[1])
        print(f"plain processes: 1 gives {throughput[1] / 1e6:.2f} M samples/s, 2 give {throughput[2] / 1e6:.2f} "
              f"M samples/s: {ratios[-1]:.2f}x (load average {os.getloadavg()[0]:.2f})")
    print(f"plain processes' ratio over {repeat} repeats: min {min(ratios):.2f}x, median "
          f"{statistics.median(ratios):.2f}x, max {max(ratios):.2f}x")


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
