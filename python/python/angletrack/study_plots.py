"""``angletrack plot RESULTS.parquet``: the figures of a study's or a lot's results.

A study's: the yield curve (for each setup, the fraction of sensors whose largest angle
error over every profile is within an error, against that error) and the largest error
against each sensor parameter that was spread (the angle error harmonics' amplitudes too). A lot's: the histogram of each
calibration parameter with its outliers marked (:func:`angletrack.lot.outlier_report`).
"""

from __future__ import annotations

import argparse
import pathlib

import numpy as np

from angletrack import lot
from angletrack.study_dask import require_extra

def is_results(path: pathlib.Path) -> bool:
    """Whether ``path`` names results (a ``.parquet`` file or dataset directory)."""
    return path.suffix.lower() == ".parquet"


def plot_command(args: argparse.Namespace) -> int:
    """``angletrack plot RESULTS.parquet [-o FILE.png]``."""
    from angletrack.plots import pyplot

    require_extra()
    if not args.capture.exists():
        raise ValueError(f"capture: {args.capture}: no such results")
    png = args.output or (args.out / f"{args.capture.stem}_plot.png" if args.out else
                          args.capture.with_name(f"{args.capture.stem}_plot.png"))
    png.parent.mkdir(parents=True, exist_ok=True)
    plt = pyplot()
    import pyarrow.parquet as pq

    table = pq.read_table(args.capture)
    if "run" in table.column_names:
        text = _study_figure(plt, table, png)
    elif "file" in table.column_names:
        text = _lot_figure(plt, args.capture, png)
    else:
        raise ValueError(f"capture: {args.capture} holds neither a study's nor a lot's results")
    print(text)
    return 0


def worst_per_sensor(table) -> dict:
    """For each setup, the largest angle error (rad) of each sensor over every profile
    (runs in error left out): ``{setup: array}``."""
    ok = table.filter(np.asarray(table.column("error").to_pylist(), dtype=object) == "")
    grouped = ok.group_by(["setup", "sensor"]).aggregate([("max_error_rad", "max")])
    setups = np.asarray(grouped.column("setup").to_pylist(), dtype=object)
    worst = grouped.column("max_error_rad_max").to_numpy()
    return {s: np.sort(worst[setups == s]) for s in sorted(set(setups))}


def sensor_parameters(table) -> list:
    """The sensor's drawn parameters of a study's rows, as the crate orders its columns
    (``StudyRow::columns``: between ``number_type`` and ``samples``), the angle error
    harmonics' phases left out."""
    names = table.column_names
    drawn = names[names.index("number_type") + 1:names.index("samples")]
    return [name for name in drawn if not name.endswith("_phase_rad")]


def _study_figure(plt, table, png: pathlib.Path) -> str:
    worst = worst_per_sensor(table)
    varied = [p for p in sensor_parameters(table) if np.ptp(table.column(p).to_numpy()) > 0]
    columns = 1 + len(varied)
    fig, axes = plt.subplots(1, columns, figsize=(5.0 * columns, 4.2), squeeze=False)
    yield_axes = axes[0][0]
    lines = [f"study results: {table.num_rows} runs"]
    for setup, errors in worst.items():
        fraction = np.arange(1, len(errors) + 1) / len(errors)
        yield_axes.step(errors * 1e3, fraction, where="post", label=setup)
        lines.append(f"  {setup}: {len(errors)} sensors, largest error over the profiles: median "
                     f"{np.median(errors) * 1e3:.4g} mrad, worst {errors[-1] * 1e3:.4g} mrad")
    yield_axes.set(xlabel="largest angle error over every profile (mrad)", ylabel="fraction of sensors within",
                   title="yield", xscale="log")
    yield_axes.grid(True, which="both", alpha=0.3)
    yield_axes.legend()
    setups = np.asarray(table.column("setup").to_pylist(), dtype=object)
    errors = table.column("max_error_rad").to_numpy()
    for ax, parameter in zip(axes[0][1:], varied):
        values = table.column(parameter).to_numpy()
        for setup in worst:
            mine = setups == setup
            ax.scatter(values[mine], errors[mine] * 1e3, s=6, label=setup)
        ax.set(xlabel=parameter, ylabel="largest angle error (mrad)", yscale="log")
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return "\n".join(lines + [f"wrote {png}"])


def _lot_figure(plt, results: pathlib.Path, png: pathlib.Path) -> str:
    import pyarrow.parquet as pq

    report, found = lot.outlier_report(results, {})
    table = pq.read_table(results)
    files = table.column("file").to_pylist()
    columns = len(lot.SCREENED)
    fig, axes = plt.subplots(1, columns, figsize=(4.0 * columns, 3.8), squeeze=False)
    for ax, column in zip(axes[0], lot.SCREENED):
        values = np.asarray(table.column(column).to_numpy(zero_copy_only=False), dtype=np.float64)
        finite = values[np.isfinite(values)]
        ax.hist(finite, bins=max(5, min(50, len(finite) // 3 or 1)), color="tab:blue", alpha=0.7)
        outliers = [files.index(f) for f, c, _, _ in found if c == column]
        for k in outliers:
            ax.axvline(values[k], color="tab:red", linestyle="--")
        ax.set(xlabel=column, ylabel="units", title=f"{column}: {len(outliers)} outliers")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return f"{report}\nwrote {png}"
