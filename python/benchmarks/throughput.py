"""Throughput of the observers called from Python: samples per second over one call on
10^7 samples (one channel), the call included (argument checks, output allocation, the GIL
released around the Rust loop). Best of 3 runs per case; measured, not asserted.

    python python/benchmarks/throughput.py [N_SAMPLES]
"""

import sys
import time

import numpy as np

import angletrack as at

N = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000_000
SECOND_ORDER, _, KALMAN = at.paper_benchmark_gains()
GAINS = {2: SECOND_ORDER, 3: KALMAN}


def main() -> None:
    theta = np.cumsum(np.full(N, 1e-3))
    print(f"{N} samples per call, best of 3 (M samples/s, call included)")
    for dtype in (np.float32, np.float64):
        y_c, y_s = np.cos(theta).astype(dtype), np.sin(theta).astype(dtype)
        for order, gains in GAINS.items():
            for sin_cos in ("fast", "exact"):
                best = 0.0
                for _ in range(3):
                    obs = at.Observer(gains, dtype=dtype, sin_cos=sin_cos)
                    start = time.perf_counter()
                    est = obs.update(y_c, y_s)
                    best = max(best, N / (time.perf_counter() - start))
                    del est
                print(f"  {np.dtype(dtype).name:8s} order {order}  {sin_cos:5s}  {best / 1e6:6.1f}")


if __name__ == "__main__":
    main()
