"""``angletrack study``: a tolerance study on Dask, one row of results per run.

The specification (TOML or JSON; ``docs/guide/studies.md``) is checked and resolved by the
Rust crate (``angletrack::study``: its tracker files read and put inline), which also
computes each run from the specification and the run id alone. This module plans the runs
still to do, schedules them (:mod:`angletrack.study_dask`) and streams their rows to a
Parquet dataset.
"""

from __future__ import annotations

import json
import pathlib
from typing import Optional

from angletrack import _angletrack
from angletrack import capture as capture_io
from angletrack import study_dask


def read_spec(path: pathlib.Path) -> tuple[str, int]:
    """The specification at ``path`` (``.toml``, else JSON) resolved by the crate: its JSON
    text with the tracker files (relative to its directory) inline, and its number of runs."""
    text = capture_io.read_text_file(path, "SPEC")
    if path.suffix.lower() == ".toml":
        try:
            import tomllib
        except ImportError:  # Python < 3.11: the extra's backport
            import tomli as tomllib
        try:
            text = json.dumps(tomllib.loads(text))
        except tomllib.TOMLDecodeError as e:
            raise ValueError(f"{path}: not TOML ({e})") from None
    return _angletrack.study_resolve(text, str(path), path.parent)


def study_task(resolved: str, runs: list) -> list:
    """The rows of ``runs`` (run ids) of the resolved specification: one Dask task."""
    return _angletrack.study_runs(resolved, list(runs))


def run_study(spec: pathlib.Path, output: pathlib.Path, cluster: study_dask.Cluster, *, resume: bool = False,
              progress: bool = True, first_runs: Optional[int] = None) -> tuple[str, dict]:
    """Runs the study ``spec`` into the dataset ``output`` (``resume``: the runs already
    there skipped; ``first_runs``: only runs 0 to N-1); returns the summary to print and what
    :func:`angletrack.study_dask.run_tasks` measured (empty when nothing was left to run)."""
    resolved, runs = read_spec(spec)
    if first_runs is not None:
        runs = min(runs, first_runs)
    study_dask.prepare_output(output, resume)
    done = study_dask.done_keys(output, "run", resolved) if resume else set()
    count = runs - sum(1 for r in done if r < runs)
    writer = study_dask.PartWriter(output, resolved)
    if count == 0:
        return f"study {spec}: all {runs} runs already in {output}", {}
    todo = study_dask.Batches((r for r in range(runs) if r not in done), count)
    measured = study_dask.run_tasks(cluster, study_task, lambda batch: (resolved, batch), todo, writer,
                                    progress=progress)
    return (f"study {spec}: {measured['rows']} runs in {measured['seconds']:.1f} s on {measured['workers']} "
            f"workers ({len(done)} already done) -> {output}"), measured
