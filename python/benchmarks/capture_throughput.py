"""End-to-end throughput and peak memory of ``angletrack track`` on large ``t;sin;cos``
captures (issue targets: a 4e6-row capture in under 300 MB peak RSS at 1e6 samples/s or
more on one core; the peak RSS flat with the capture's size).

Run with the package installed (``bash scripts/test.sh python`` builds it into
python/.venv):

    python/.venv/bin/python python/benchmarks/capture_throughput.py --rows 4e6 1e7 --output csv npy

Each capture is generated in a temporary directory (``--dir``, default /tmp) and deleted
afterwards, with its estimates. Peak RSS and wall time come from GNU ``/usr/bin/time -v``
(Debian package ``time``) around the ``angletrack`` console script.
"""

from __future__ import annotations

import argparse
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

import angletrack
from angletrack import export

SAMPLE_PERIOD_S = 1e-4
CHUNK = 1_000_000


def write_capture(path: pathlib.Path, rows: int) -> None:
    """A ``t;sin;cos`` capture of ``rows`` samples: an accelerating rotor with noise."""
    rng = np.random.default_rng(0)
    with open(path, "w") as f:
        f.write("t;sin;cos\n")
        for start in range(0, rows, CHUNK):
            k = np.arange(start, min(rows, start + CHUNK), dtype=np.float64)
            t = k * SAMPLE_PERIOD_S
            theta = 100.0 * t + 5.0 * np.sin(0.5 * t)
            noise = rng.normal(0.0, 0.005, (2, k.size))
            block = np.column_stack([t, np.sin(theta) + noise[0], np.cos(theta) + noise[1]])
            np.savetxt(f, block, fmt=["%.10g", "%.6f", "%.6f"], delimiter=";")


def measure(capture: pathlib.Path, gains: pathlib.Path, output: pathlib.Path) -> tuple[float, float]:
    """(wall seconds, peak RSS in MB) of ``angletrack track`` on ``capture``."""
    script = pathlib.Path(sys.executable).parent / "angletrack"
    command = ["/usr/bin/time", "-v", str(script), "track", str(capture), "--columns", "time=t,y_s=sin,y_c=cos",
               "--gains-file", str(gains), "--output", str(output)]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        raise SystemExit(f"angletrack track failed:\n{run.stderr}")
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", run.stderr)
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr)
    hours, minutes, seconds = (float(g) if g else 0.0 for g in wall.groups())
    return 3600 * hours + 60 * minutes + seconds, int(rss.group(1)) / 1024


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", type=float, nargs="+", default=[4e6], help="capture sizes (rows)")
    parser.add_argument("--output", nargs="+", default=["csv"], choices=["csv", "npy"], help="estimates formats")
    parser.add_argument("--dir", type=pathlib.Path, default=pathlib.Path("/tmp"), help="where the files go")
    args = parser.parse_args()
    if not shutil.which("/usr/bin/time"):
        raise SystemExit("needs GNU time: apt-get install time")
    work = pathlib.Path(tempfile.mkdtemp(prefix="angletrack_bench_", dir=args.dir))
    try:
        gains = work / "gains.json"
        gains.write_text(export.to_json(angletrack.Gains([0.1, 0.005, 1e-4], SAMPLE_PERIOD_S)))
        print("| rows | capture (MB) | output | wall (s) | samples/s | peak RSS (MB) |")
        print("| ---: | ---: | :--- | ---: | ---: | ---: |")
        for rows in map(int, args.rows):
            capture = work / "capture.csv"
            write_capture(capture, rows)
            size_mb = capture.stat().st_size / 1e6
            for ext in args.output:
                output = work / f"estimates.{ext}"
                wall, rss = measure(capture, gains, output)
                output.unlink()
                print(f"| {rows:.0e} | {size_mb:.0f} | {ext} | {wall:.2f} | {rows / wall:.3g} | {rss:.0f} |", flush=True)
            capture.unlink()
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
