"""Issue 23: `angletrack calibrate` streams its capture, so its memory does not grow with the
capture's length: 4e6 rows stay far under the issue's 300 MB (measured 40 MB of peak resident
memory, of which about 29 MB are the interpreter, numpy and the extension; held within 2x,
below the 96 MB the capture's file alone would take in memory)."""

import math
import subprocess
import sys

import numpy as np

import angletrack
from angletrack import export, harmonics

ROWS = 4_000_000
SAMPLE_PERIOD_S = 5e-5


def write_capture(path):
    """A sensor read at 200 Hz electrical on the 20 kHz clock with 5 mrad at orders 3 and 4
    and 1e-3 of noise, and its reference angle, synthesised here with numpy: (y_c, y_s,
    reference) as a 2-D float64 `.npy` of 96 MB."""
    k = np.arange(ROWS)
    theta = 2 * math.pi * 200.0 * SAMPLE_PERIOD_S * k
    seen = theta + 5e-3 * np.sin(3 * theta + 0.3) + 5e-3 * np.sin(4 * theta + 1.1)
    rng = np.random.default_rng(3)
    y_c = np.cos(seen) + 1e-3 * rng.standard_normal(ROWS)
    y_s = np.sin(seen) + 1e-3 * rng.standard_normal(ROWS)
    reference = np.remainder(theta + math.pi, 2 * math.pi) - math.pi
    np.save(path, np.column_stack([y_c, y_s, reference]))


def test_calibrate_streams_four_million_rows_in_under_300_mb(tmp_path):
    capture, gains_file, out = tmp_path / "capture.npy", tmp_path / "g.json", tmp_path / "cal.json"
    write_capture(capture)
    gains_file.write_text(export.to_json(angletrack.third_order_butterworth(2e-3, SAMPLE_PERIOD_S).gains))
    arguments = ["calibrate", str(capture), "--gains-file", str(gains_file), "--columns", "y_c=0,y_s=1,reference=2",
                 "--sample-rate", "20000", "-o", str(out)]
    # A process of its own, which reports its peak resident memory since it started
    # (/proc's VmHWM: the rusage of a child also counts the forking process's pages).
    child = subprocess.run(
        [sys.executable, "-c", "import atexit, sys\n"
         "atexit.register(lambda: sys.stderr.write(next(line for line in open('/proc/self/status') "
         "if line.startswith('VmHWM'))))\n"
         "from angletrack import cli\n"
         "sys.exit(cli.main(sys.argv[1:]))", *arguments],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    assert child.returncode == 0, child.stderr
    peak_kb = int(child.stderr.strip().splitlines()[-1].split()[1])
    peak_mb = peak_kb / 1024
    print(f"calibrate on {ROWS} rows: peak resident memory {peak_mb:.1f} MB")
    assert peak_mb < 80
    # All of it was read: orders 3 and 4 learned at their 5 mrad.
    learned = harmonics.Calibration.from_json(out.read_text())
    amplitudes = {o["order"]: o["amplitude_rad"] for o in learned.orders}
    assert abs(amplitudes[3] - 5e-3) < 1e-4 and abs(amplitudes[4] - 5e-3) < 1e-4
