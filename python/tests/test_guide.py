"""The examples of the README and the user guide (docs/guide/*.md), found from this file's
place in the repository (the suite runs against the installed wheel, from elsewhere):

- every ```python block runs, in a fresh namespace (a failing assert, an exception: fail);
- every ```sh block runs, a page's blocks in order in one scratch directory holding the
  files they name (capture.csv, raw.csv), unless the line before it is
  ``<!-- not run: REASON -->``;
- every page with a ```rust block is a doctest module of tests/lib.rs (cargo test runs it)
  and every fenced block names a language this harness or another one handles.
"""

import math
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import angletrack
from angletrack import capture

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
# The languages of fenced blocks, and who runs them: python and sh here, rust by the doctests
# of tests/lib.rs, c by scripts/test.d/16-c-api.sh; toml and text are not code.
LANGUAGES = {"python", "sh", "rust", "c", "toml", "text"}
NOT_RUN = re.compile(r"^<!-- not run: \S.* -->$")


def blocks(page):
    """The fenced blocks of `page`: (language, first line number, code, line before the fence)."""
    found, lines = [], page.read_text(encoding="utf-8").splitlines()
    k = 0
    while k < len(lines):
        fence = re.match(r"^```(\S*)", lines[k])
        if fence:
            end = next((j for j in range(k + 1, len(lines)) if lines[j].startswith("```")), None)
            assert end is not None, f"{page}:{k + 1}: unclosed code block"
            before = lines[k - 1] if k > 0 else ""
            found.append((fence.group(1), k + 1, "\n".join(lines[k + 1:end]) + "\n", before))
            k = end
        k += 1
    return found


def relative(page):
    return page.relative_to(ROOT).as_posix()


PYTHON_BLOCKS = [(page, line, code) for page in PAGES for language, line, code, _ in blocks(page)
                 if language == "python"]
SH_PAGES = [page for page in PAGES if any(b[0] == "sh" and not NOT_RUN.match(b[3]) for b in blocks(page))]


def test_the_guide_is_found_and_has_examples():
    assert (ROOT / "docs" / "guide" / "index.md").is_file(), ROOT
    assert len(PYTHON_BLOCKS) >= 5 and len(SH_PAGES) >= 1, (len(PYTHON_BLOCKS), SH_PAGES)


@pytest.mark.parametrize("page, line, code", PYTHON_BLOCKS,
                         ids=[f"{relative(p)}:{n}" for p, n, _ in PYTHON_BLOCKS])
def test_python_example_runs(page, line, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"{relative(page)}:{line}", "exec"), {"__name__": "__guide__"})


def test_every_block_is_run_by_a_harness():
    lib = (ROOT / "tests" / "lib.rs").read_text(encoding="utf-8")
    problems = []
    for page in PAGES:
        found = blocks(page)
        for language, line, _, before in found:
            if language not in LANGUAGES:
                problems.append(f"{relative(page)}:{line}: block language {language!r} is not one of {sorted(LANGUAGES)}")
        rust = any(language == "rust" for language, *_ in found)
        included = f'include_str!("../{relative(page)}")' in lib
        if rust and not included:
            problems.append(f"{relative(page)} has rust blocks but tests/lib.rs does not include it")
    assert not problems, "\n".join(problems)


def write_capture(path):
    """A sensor with offsets, unequal amplitudes and 4 mrad of 3rd harmonic, turning at
    200 Hz electrical, sampled at 20 kHz for 0.5 s, noise 0.001."""
    rng = np.random.default_rng(7)
    t = np.arange(10_000) / 20e3
    theta = 0.3 + 2 * math.pi * 200.0 * t
    seen = theta + 0.004 * np.sin(3 * theta)
    y_c = 0.02 + 0.9 * np.cos(seen) + 1e-3 * rng.standard_normal(t.size)
    y_s = -0.01 + 0.93 * np.sin(seen) + 1e-3 * rng.standard_normal(t.size)
    capture.write_capture(path, {"time": t, "y_c": y_c, "y_s": y_s, "reference": theta})


def write_raw(path):
    """A resolver's windings at 50 rev/s: 10 kHz carrier, 160 kHz, 12-bit, 305 degrees."""
    speed = 2 * math.pi * 50
    profile = angletrack.MotionProfile(0.3, speed).constant_speed(speed, 0.03)
    scenario = angletrack.resolver_windings(
        profile, angletrack.ResolverModel(carrier_delay_rad=math.radians(305)), seed=1)
    capture.write_capture(path, {"time": scenario.time_s, "y_c": scenario.y_c, "y_s": scenario.y_s,
                                 "reference": scenario.angle_rad})


@pytest.mark.parametrize("page", SH_PAGES, ids=[relative(p) for p in SH_PAGES])
def test_shell_examples_run(page, tmp_path):
    write_capture(tmp_path / "capture.csv")
    write_raw(tmp_path / "raw.csv")
    # The installed command first (the virtual environment this interpreter belongs to).
    env = dict(os.environ, PATH=f"{pathlib.Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
               MPLBACKEND="Agg")
    for language, line, code, before in blocks(page):
        if language != "sh" or NOT_RUN.match(before):
            continue
        result = subprocess.run(["bash", "-euo", "pipefail", "-c", code], cwd=tmp_path, env=env,
                                capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, (f"{relative(page)}:{line}: exit {result.returncode}\n"
                                        f"{result.stdout[-2000:]}\n{result.stderr[-2000:]}")


@pytest.mark.parametrize("header, extra", [("motor_gains.h", []), ("motor_fixed.h", ["--dtype", "fixed"])])
def test_the_c_blocks_headers_are_what_design_writes(header, extra, tmp_path):
    """scripts/test.d/16-c-api.sh compiles the guide's C blocks with these headers, which
    stand for the command's output: they must be it."""
    from angletrack import cli

    out = tmp_path / header
    status = cli.main(["design", "kalman", "--sample-rate", "20000", "--jerk-std", "1e5", "--noise-std", "0.01",
                       *extra, "--format", "c", "--name", "motor", "--output", str(out)])
    assert status == 0
    fixture = ROOT / "crates" / "angletrack-c" / "tests" / "c" / "guide" / header
    assert fixture.read_text(encoding="utf-8") == out.read_text(encoding="utf-8"), (
        f"{fixture.relative_to(ROOT)} differs from `angletrack design kalman --sample-rate 20000 --jerk-std 1e5 "
        f"--noise-std 0.01 {' '.join(extra)} --format c --name motor`: regenerate it")
