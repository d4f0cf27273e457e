"""Where the time of a study or a lot on Dask went: the runs' own time (each row's
``seconds``, measured inside the run), the tasks' time around them on the workers, the
workers' idle time between their tasks (the scheduling), at the start and at the end.

The per-run overhead of the scheduling is what a worker spends on each task beside its runs
(the call, the rows made into Python objects) plus its wait between two tasks, over the
runs' time: it does not depend on how busy the machine is in the way the wall time does
(another process taking a core makes the runs slower too, not only the scheduling).
"""

from __future__ import annotations

import collections
from typing import Sequence


class Timeline:
    """The tasks' times as they complete: for each worker thread, when each task started and
    ended (the wall clock of its machine), and the seconds of the runs it held."""

    def __init__(self, submitted_at: float):
        self.submitted_at = submitted_at
        self.tasks: dict = collections.defaultdict(list)
        self.runs_s = 0.0
        self.cpu_s = 0.0

    def add(self, rows: Sequence[dict], times: tuple) -> None:
        """One task's ``rows`` and its ``(worker thread, start, end, CPU seconds)``."""
        worker, start, end, cpu = times
        self.tasks[worker].append((start, end))
        self.cpu_s += cpu
        self.runs_s += sum(row.get("seconds", 0.0) for row in rows)

    def account(self, wall_s: float, threads: int, client_cpu_s: float) -> dict:
        """The times (s) and shares summed over the worker threads, for a run of ``wall_s``
        seconds on ``threads`` threads whose client (and local scheduler) took
        ``client_cpu_s`` of CPU time:

        ``runs_s`` the runs' own time; ``tasks_cpu_s`` the CPU time of the threads running
        the tasks (their runs' and the rest: what the load of the machine does not inflate);
        ``in_tasks_s`` the tasks' time beside their runs;
        ``between_s`` the workers' waits between two of their tasks; ``first_s`` from the
        first submission to each worker's first task; ``tail_s`` from each worker's last
        task to the last one's end; ``per_run_overhead`` (in_tasks + between) / runs;
        ``overhead`` the whole wall time x threads less the runs, over the runs (start and
        tail included); ``client_cpu_s`` the client's CPU time."""
        runs = self.runs_s
        in_tasks = between = first = tail = 0.0
        last_end = max((end for spans in self.tasks.values() for _, end in spans), default=self.submitted_at)
        for spans in self.tasks.values():
            spans.sort()
            in_tasks += sum(end - start for start, end in spans)
            between += sum(max(0.0, start - end) for (_, end), (start, _) in zip(spans, spans[1:]))
            first += max(0.0, spans[0][0] - self.submitted_at)
            tail += last_end - max(end for _, end in spans)
        in_tasks -= runs
        share = (lambda t: t / runs) if runs > 0 else (lambda t: float("nan"))
        return {"runs_s": runs, "in_tasks_s": in_tasks, "between_s": between, "first_s": first, "tail_s": tail,
                "per_run_overhead": share(in_tasks + between), "overhead": share(wall_s * threads - runs),
                "client_cpu_s": client_cpu_s, "tasks_cpu_s": self.cpu_s,
                "tasks": sum(len(s) for s in self.tasks.values())}
