"""Throughput of the observers called from Python, the call included (argument checks,
output allocation, the GIL released around the Rust loop); best of 3 runs per case;
measured, not asserted.

1. One channel: samples per second over one call on N_SAMPLES samples.
2. Many channels, float32, the Kalman ATO: ``track_batch`` on 64, 256 and 1024 channels
   (N_SAMPLES channel-samples in all), with every output and with ``outputs=("angle",
   "speed")``, against a Python loop of ``track()`` over the channels (what a caller writes
   without the batch), in M channel-samples/s and as the ratio to the loop. Each figure is
   given in wall-clock time and in the CPU time of the calling thread (``time.thread_time``,
   which leaves out the time other processes take on a shared machine).

    python python/benchmarks/throughput.py [N_SAMPLES]
"""

import sys
import time

import numpy as np

import angletrack as at

N = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000_000
SECOND_ORDER, _, KALMAN = at.paper_benchmark_gains()
GAINS = {2: SECOND_ORDER, 3: KALMAN}
CHANNELS = (64, 256, 1024)


def single_channel() -> None:
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


def best_seconds(run) -> tuple[float, float]:
    """The shortest wall-clock and thread CPU times (s) of 3 calls of ``run``."""
    wall, cpu = float("inf"), float("inf")
    for _ in range(3):
        start_wall, start_cpu = time.perf_counter(), time.thread_time()
        result = run()
        wall = min(wall, time.perf_counter() - start_wall)
        cpu = min(cpu, time.thread_time() - start_cpu)
        del result
    return wall, cpu


def many_channels() -> None:
    print(
        f"\n{N} channel-samples per call (float32, Kalman ATO, fast sin/cos), best of 3: "
        "M channel-samples/s and the ratio to a Python loop of track(), wall clock | thread CPU"
    )
    for channels in CHANNELS:
        samples = N // channels
        k = np.arange(samples)
        speed = 50.0 + 2.0 * np.arange(channels)[:, None]  # rad/s, one per channel
        theta = 0.1 * np.arange(channels)[:, None] + speed * 1e-4 * k
        y_c, y_s = np.cos(theta).astype(np.float32), np.sin(theta).astype(np.float32)
        del theta
        cases = {
            "loop of track()": lambda: [at.track(KALMAN, y_c[c], y_s[c]) for c in range(channels)],
            "track_batch, all outputs": lambda: at.track_batch(KALMAN, y_c, y_s),
            "track_batch, angle + speed": lambda: at.track_batch(
                KALMAN, y_c, y_s, outputs=("angle", "speed")
            ),
        }
        times = {name: best_seconds(run) for name, run in cases.items()}
        loop_wall, loop_cpu = times["loop of track()"]
        print(f"  {channels} channels x {samples} samples")
        for name, (wall, cpu) in times.items():
            rate_wall, rate_cpu = channels * samples / wall / 1e6, channels * samples / cpu / 1e6
            print(
                f"    {name:28s} {rate_wall:7.1f} M/s  x{loop_wall / wall:4.1f}  | "
                f"{rate_cpu:7.1f} M/s  x{loop_cpu / cpu:4.1f}"
            )


if __name__ == "__main__":
    single_channel()
    many_channels()
