"""``angletrack study`` and ``angletrack lot``: many runs on Dask, results to Parquet.

Both need the optional extra ``angletrack[study]`` (Dask, pyarrow, tqdm); without it they
say how to install it, in one line, before anything else.
"""

from __future__ import annotations

import argparse
import pathlib

from angletrack import capture as capture_io
from angletrack.cli_args import add_reader_arguments, non_negative_number, positive_number, subcommand


def _add_cluster_arguments(p: argparse.ArgumentParser) -> None:
    where = p.add_argument_group("where the runs go (default: a local cluster, one process per core)")
    one = where.add_mutually_exclusive_group()
    one.add_argument("--workers", type=_count, metavar="N", help="local worker processes (default: one per core)")
    one.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, such as tcp://host:8786")
    one.add_argument("--scheduler-file", type=pathlib.Path, metavar="FILE",
                     help="an existing Dask scheduler's file (dask scheduler --scheduler-file FILE)")
    p.add_argument("--output", "-o", type=pathlib.Path, required=True, metavar="RESULTS.parquet",
                   help="the results: a Parquet dataset (a directory of part files, read as one table by pandas "
                   "or pyarrow), each part written as its runs complete")
    p.add_argument("--resume", action="store_true",
                   help="continue the results in --output: the runs already there are skipped")
    p.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected at least 1, got {text}")
    return value


def _cluster(args: argparse.Namespace):
    from angletrack import study_dask

    study_dask.require_extra()
    return study_dask.Cluster(workers=args.workers, scheduler=args.scheduler, scheduler_file=args.scheduler_file)


def _cmd_study(args: argparse.Namespace) -> int:
    """run a tolerance study on Dask: simulated sensors through motion profiles and setups

    Runs every sensor of SPEC (TOML or JSON: the spreads of the sensors' parameters, the motion
    profiles, the setups as tracker files, the number of sensors and a seed;
    docs/guide/studies.md) through every profile and every setup, one row of results per run
    (its parameters, RMS and largest angle error after the start-up, faults, what an online
    calibration learned, the time taken), on a local Dask cluster or an existing one. Each
    run's seeds come from the spec's seed and the run id, so the results do not depend on
    the workers.
    """
    from angletrack import study

    cluster = _cluster(args)
    summary, _ = study.run_study(args.spec, args.output, cluster, resume=args.resume, progress=not args.no_progress)
    print(summary)
    return 0


def add_study_parser(sub) -> None:
    """The ``study`` subcommand."""
    p = subcommand(sub, _cmd_study)
    p.add_argument("spec", type=pathlib.Path, metavar="SPEC", help="the study's specification (.toml or .json)")
    _add_cluster_arguments(p)


def _limit(text: str) -> tuple:
    name, sep, bounds = text.partition("=")
    low, comma, high = bounds.partition(",")
    try:
        values = tuple(None if v.strip() == "" else float(v) for v in (low, high))
    except ValueError:
        values = ()
    if not sep or not comma or not name or values in ((), (None, None)):
        raise argparse.ArgumentTypeError(f"expected COLUMN=LOW,HIGH (either bound may be empty), got {text!r}")
    return name, values


def _cmd_lot(args: argparse.Namespace) -> int:
    """calibrate and track every capture of a production lot on Dask, and report its outliers

    Calibrates each capture of CAPTURES (files or quoted globs, such as 'captures/*.csv') as
    `angletrack calibrate --tracker` does and tracks it with what was learned as `angletrack
    track --tracker` does; one row per capture (file, status, the learned calibration with
    each harmonic's uncertainty, the residual error, faults); a capture that fails is a row
    with its error. Then prints the outliers: units beyond --limit, or further than
    --spread-factor scaled MADs from the lot's median, and the failed captures.
    """
    from angletrack import lot, study_dask

    cluster = _cluster(args)
    lot.check_limits(dict(args.limit or []))
    files = lot.captures(args.captures)
    tracker_text = capture_io.read_text_file(args.tracker, "--tracker")
    from angletrack.tracker import Tracker

    # Refused here, not once per capture.
    if Tracker.from_json(tracker_text, str(args.tracker)).dtype == "fixed":
        raise ValueError(f'--tracker: {args.tracker}: number_type "fixed": a lot tracks float trackers ("f32", '
                         '"f64"); track the fixed-point chain with `angletrack track --tracker`')
    layout = lot.Layout(columns=args.columns, delimiter=args.delimiter, decimal=args.decimal,
                        skip_rows=args.skip_rows, time_unit=args.time_unit, sample_rate_hz=args.sample_rate)
    source = "\n".join([tracker_text, repr(layout), str(args.skip)])
    study_dask.prepare_output(args.output, args.resume)
    done = study_dask.done_keys(args.output, "file", source) if args.resume else set()
    todo = [f for f in files if f not in done]
    writer = study_dask.PartWriter(args.output, source)
    if todo:
        def arguments(batch: list) -> tuple:
            return batch, tracker_text, str(args.tracker), layout, args.skip

        # At most 4 captures a task: each may take seconds, and a lot's tasks are few.
        study_dask.run_tasks(cluster, lot.lot_task, arguments, study_dask.Batches(todo, len(todo), largest=4), writer,
                             progress=not args.no_progress, unit="capture")
    report, _ = lot.outlier_report(args.output, dict(args.limit or []), args.spread_factor)
    print(report)
    return 0


def add_lot_parser(sub) -> None:
    """The ``lot`` subcommand."""
    p = subcommand(sub, _cmd_lot)
    p.add_argument("captures", nargs="+", metavar="CAPTURES", help="capture files or quoted globs (.csv, .npy, .npz)")
    p.add_argument("--tracker", type=pathlib.Path, required=True, metavar="FILE.json",
                   help="the tracker file of the lot's setup (its calibration is replaced by each unit's)")
    p.add_argument("--columns", metavar="ROLE=COLUMN,...", help="as for `angletrack track`")
    p.add_argument("--delimiter", metavar="CHAR", help="as for `angletrack track`")
    p.add_argument("--time-unit", choices=["s", "ms", "us", "ns"], default="s", help="unit of the time column")
    p.add_argument("--sample-rate", type=positive_number, metavar="HZ", help="as for `angletrack track`")
    add_reader_arguments(p)
    p.add_argument("--skip", type=non_negative_number, default=0.0, metavar="S",
                   help="with a reference column: leave the first S seconds out of the tracked error")
    p.add_argument("--limit", type=_limit, action="append", metavar="COLUMN=LOW,HIGH",
                   help="a unit outside LOW to HIGH in COLUMN (such as residual_rms_rad=,0.002) is an outlier; "
                   "repeatable")
    p.add_argument("--spread-factor", type=positive_number, default=5.0, metavar="X",
                   help="a unit further than X scaled MADs (about standard deviations) from the lot's median is "
                   "an outlier (default 5)")
    _add_cluster_arguments(p)

