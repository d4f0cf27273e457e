"""Running many independent tasks on Dask and streaming their rows to Parquet: what
``angletrack study`` and ``angletrack lot`` share.

Python only plans, schedules and collects here; each task is one call into the Rust crates
(which release the GIL) for a batch of runs, sized to last about :data:`TASK_SECONDS` so
that the scheduling's cost per task is spread over many runs (:class:`Batches`). The tasks
run on a local cluster of processes (one per core, or ``workers``, each one thread; Dask's
nanny starts them with ``OMP_NUM_THREADS=1`` and its kin, so nothing numerical in them
starts threads of its own), or on an existing cluster (``scheduler`` address or
``scheduler_file``). At most a few tasks per worker are in flight, and every row is written
as its task completes, so memory stays bounded whatever the number of tasks. The output is
a Parquet dataset: a directory of part files, each complete when it appears (written
beside and renamed), so an interrupted run leaves every part written readable and
``resume`` skips the rows already there. A worker lost mid-task has its tasks redone by
Dask; nothing finished is lost.

Dask, pyarrow and tqdm are the optional extra ``angletrack[study]``.
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
import math
import os
import pathlib
import socket
import threading
import time
import uuid
from typing import Any, Callable, Iterable, Optional, Sequence

#: The line the commands print when the extra is missing.
INSTALL_HINT = "install the study extra: pip install 'angletrack[study]' (Dask, pyarrow, tqdm)"
#: Rows gathered before a part file is written, and the longest wait (s) before one is.
PART_ROWS = 512
PART_SECONDS = 10.0
#: Tasks in flight per worker thread: enough to keep each busy while results come back.
TASKS_PER_WORKER = 3
#: The time (s) a task is sized for, once a task's time is known: the cost of scheduling one
#: (a few milliseconds) spread over the runs it holds.
TASK_SECONDS = 1.0
#: The tasks per worker thread the keys left are at least split into: the last tasks short,
#: so no worker waits long for another's at the end.
TAIL_SHARE = 3
#: Times Dask retries a task whose worker raised (a lost worker's tasks are redone anyway).
RETRIES = 2
#: Dask's settings for a local cluster, whose scheduler, client and workers share the
#: machine's cores with the runs: the periodic work of each process made rarer, since what
#: it serves does not help independent tasks sent a few at a time (the event loop's check
#: for a blocked loop, the dashboard's system monitor, work stealing: the scheduler's queue
#: gives each free worker the next task; the memory monitor ten times a second), and the
#: workers' statistical profiler off: it samples the task's thread a hundred times a second
#: for the dashboard, and with it a run beside another took 1.14x to 1.18x as long as alone
#: (1.04x without; python/scripts/study_scale.py). The script prints the client's share of a
#: core.
LOCAL_CONFIG = {
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.scheduler.work-stealing": False,
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.worker.profile.enabled": False,
}
#: The key of the Parquet schema's metadata holding what the rows were computed from.
SOURCE_KEY = b"angletrack-source"


def require_extra() -> None:
    """Refuses, in one line naming the extra, when Dask, pyarrow or tqdm is missing."""
    for module in ("dask.distributed", "pyarrow.parquet", "tqdm"):
        try:
            __import__(module)
        except ImportError:
            raise RuntimeError(f"{module.split('.')[0]} is missing: {INSTALL_HINT}") from None


@dataclasses.dataclass
class Cluster:
    """Where the tasks run: a local cluster of ``workers`` processes (default: one per
    core), or the scheduler at ``scheduler`` (``tcp://host:8786``) or in ``scheduler_file``."""

    workers: Optional[int] = None
    scheduler: Optional[str] = None
    scheduler_file: Optional[pathlib.Path] = None

    def client(self):
        """A connected ``dask.distributed.Client`` (and the local cluster it owns, if any)."""
        from dask.distributed import Client, LocalCluster

        if self.scheduler is not None:
            return Client(self.scheduler, timeout="30s"), None
        if self.scheduler_file is not None:
            return Client(scheduler_file=str(self.scheduler_file), timeout="30s"), None
        import dask

        workers = self.workers or os.cpu_count() or 1
        # Any free port for its HTTP server (8787 may be taken), errors only in the log: the progress bar
        # and the summary are what the user reads.
        with dask.config.set(LOCAL_CONFIG):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", silence_logs=logging.ERROR)
            return Client(cluster), cluster


class PartWriter:
    """Rows to a Parquet dataset directory, a part file per batch, each renamed into place
    when complete; the schema's metadata records ``source`` (what the rows were computed
    from), checked on resume."""

    def __init__(self, directory: pathlib.Path, source: str):
        self.directory, self.source = directory, source
        self.rows: list = []
        self.written = 0
        self.last = time.monotonic()
        self.session = uuid.uuid4().hex[:8]
        self.parts = 0

    def add(self, rows: Sequence[dict]) -> None:
        """Gathers ``rows``; writes a part once :data:`PART_ROWS` are gathered or
        :data:`PART_SECONDS` have passed since the last."""
        self.rows.extend(rows)
        if len(self.rows) >= PART_ROWS or time.monotonic() - self.last > PART_SECONDS:
            self.flush()

    def flush(self) -> None:
        """Writes the rows gathered as one part file (none without rows)."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        self.last = time.monotonic()
        if not self.rows:
            return
        table = pa.Table.from_pylist(self.rows).replace_schema_metadata({SOURCE_KEY: self.source.encode()})
        name = f"part-{self.session}-{self.parts:05d}.parquet"
        temporary = self.directory / f".{name}.tmp"
        pq.write_table(table, temporary)
        temporary.rename(self.directory / name)
        self.written += len(self.rows)
        self.parts += 1
        self.rows = []


def done_keys(directory: pathlib.Path, key: str, source: str, flag: str = "--output") -> set:
    """The values of column ``key`` in the dataset ``directory`` (the rows already written),
    refusing one computed from another ``source``."""
    import pyarrow.parquet as pq

    parts = sorted(directory.glob("part-*.parquet"))
    done: set = set()
    for part in parts:
        file = pq.ParquetFile(part)
        written = (file.schema_arrow.metadata or {}).get(SOURCE_KEY, b"").decode()
        if written != source:
            raise ValueError(f"{flag}: {directory} holds results of another specification or lot ({part.name}): "
                             "--resume continues the same one; give another --output")
        done.update(file.read(columns=[key]).column(key).to_pylist())
    return done


def prepare_output(directory: pathlib.Path, resume: bool, flag: str = "--output") -> None:
    """Makes the dataset directory; one already holding parts is refused unless ``resume``."""
    if directory.exists() and not directory.is_dir():
        raise ValueError(f"{flag}: {directory} is a file: the results are a Parquet dataset (a directory of parts)")
    if directory.is_dir() and any(directory.glob("part-*.parquet")) and not resume:
        raise ValueError(f"{flag}: {directory} already holds results: give --resume to continue them, or another "
                         "--output")
    directory.mkdir(parents=True, exist_ok=True)
    for stale in directory.glob(".part-*.tmp"):
        stale.unlink()


def run_tasks(cluster: Cluster, task: Callable[..., list], arguments: Callable[[list], tuple], batches: "Batches",
              writer: PartWriter, *, progress: bool = True, unit: str = "run") -> dict:
    """Runs ``task(*arguments(batch))`` for each batch of keys of ``batches`` on ``cluster``
    (each returns a list of row dicts, one per key), writing the rows as tasks complete;
    returns what :func:`angletrack.study_timing.account` makes of the tasks' times, with
    ``rows``, ``seconds`` (wall time from the first submission, the workers up) and
    ``startup_s`` (connecting, or starting the local cluster, and importing the package on
    every worker)."""
    # pyarrow imported here, and the package on every worker below, before the clock starts:
    # the first part's write and each worker's first task would otherwise pay for them.
    import pyarrow.parquet  # noqa: F401
    from dask.distributed import as_completed
    from tqdm import tqdm

    from angletrack import study_timing

    begun = time.monotonic()
    client, local = cluster.client()
    try:
        client.run(_warm_up)
        threads = max(sum(client.nthreads().values()), 1)
        batches.threads = threads
        started, started_at, cpu = time.monotonic(), time.time(), time.process_time()
        in_flight = as_completed()
        timeline = study_timing.Timeline(started_at)

        def submit(count: int) -> None:
            for batch in itertools.islice(batches, count):
                in_flight.add(client.submit(_timed, task, *arguments(batch), pure=False, retries=RETRIES))

        submit(threads * TASKS_PER_WORKER)
        with tqdm(total=batches.count, unit=unit, disable=not progress, dynamic_ncols=True) as bar:
            for future in in_flight:
                rows, times = future.result()
                future.release()
                timeline.add(rows, times)
                batches.observe(len(rows), times[2] - times[1])
                writer.add(rows)
                bar.update(len(rows))
                submit(1)
        writer.flush()
        seconds = time.monotonic() - started
        measured = timeline.account(seconds, threads, time.process_time() - cpu)
        measured.update(rows=writer.written, seconds=seconds, workers=threads, startup_s=started - begun)
        return measured
    finally:
        writer.flush()
        client.close()
        if local is not None:
            local.close()


def _warm_up() -> None:
    """Imports the package and its extension on a worker."""
    import angletrack  # noqa: F401


def _timed(task: Callable[..., list], *args) -> tuple:
    """``task(*args)`` on a worker: its rows, and ``(worker thread, start, end, CPU seconds)``
    (wall clock; the CPU time of the thread, which runs the Rust code too)."""
    start, cpu = time.time(), time.thread_time()
    rows = task(*args)
    worker = f"{socket.gethostname()}:{os.getpid()}:{threading.get_ident()}"
    return rows, (worker, start, time.time(), time.thread_time() - cpu)


class Batches:
    """``count`` keys in batches, one task each, sized as they are submitted: a single key
    until a task's time is known, then keys for about :data:`TASK_SECONDS` (the scheduling's
    cost spread over many runs), but at most a ``1 / TAIL_SHARE`` share of the keys left per
    worker thread, so that the last tasks are short and the workers finish together; at most
    ``largest`` keys (the rows a task holds). The results do not depend on the batching: each
    key's row is computed from the key alone."""

    def __init__(self, keys: Iterable[Any], count: int, largest: int = 1024):
        self.keys, self.count, self.largest = iter(keys), count, largest
        self.threads = 1
        self.submitted = 0
        self.observed_keys, self.observed_s = 0, 0.0

    def observe(self, keys: int, seconds: float) -> None:
        """A task of ``keys`` keys took ``seconds`` on its worker."""
        self.observed_keys += keys
        self.observed_s += seconds

    def size(self) -> int:
        """The keys of the next batch."""
        if self.observed_keys == 0:
            return 1
        per_key = self.observed_s / self.observed_keys
        wanted = TASK_SECONDS / per_key if per_key > 0 else self.largest
        tail = (self.count - self.submitted) / (TAIL_SHARE * self.threads)
        return max(1, min(self.largest, int(wanted), math.ceil(tail)))

    def __iter__(self) -> "Batches":
        return self

    def __next__(self) -> list:
        batch = list(itertools.islice(self.keys, self.size()))
        if not batch:
            raise StopIteration
        self.submitted += len(batch)
        return batch
