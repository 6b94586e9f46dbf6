"""The figures the README says `make demo` prints come out of this install: the demo at full
size, compared with the README's row for the render fingerprint this machine draws."""

import re
from pathlib import Path

import pytest

from envs.commands.demo import run_demo
from envs.runs.suite import render_fingerprint

README = Path(__file__).resolve().parent.parent / "README.md"
#: the README's columns, in order: the demo's table rows they show
ROWS = ("online (seed 000)", "online, PANORAMA settings", "nested (seed 001)",
        "nested (seed 001), forward camera", "online (seed 000), forward camera")


def readme_figures() -> dict[str, list[tuple[float, float, int]]]:
    """render fingerprint -> (precision, NMI, places) per demo row, from the README's table."""
    table = {}
    for render, cells in re.findall(r"^\| `([0-9a-f]{16})` \|(.*)\|$", README.read_text(),
                                    flags=re.M):
        figures = [c.strip().split(" / ") for c in cells.split("|")]
        table[render] = [(float(p), float(n), int(k)) for p, n, k in figures]
    return table


def test_the_readme_has_a_demo_row_for_each_column():
    figures = readme_figures()
    assert figures and all(len(row) == len(ROWS) for row in figures.values())


def test_make_demo_prints_the_readmes_figures(tmp_path):
    figures, here = readme_figures(), render_fingerprint()
    if here not in figures:
        pytest.skip(f"the README lists the demo's figures for the renders {sorted(figures)}; "
                    f"this machine draws {here}")
    table = run_demo(str(tmp_path))
    printed = [(round(table[r]["precision"], 3), round(table[r]["nmi"], 3),
                table[r]["n_places"]) for r in ROWS]
    assert printed == figures[here]
