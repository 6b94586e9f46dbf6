"""Whether a code change changes what a section's command computes: its probe, run twice.

A section whose fingerprint moved (:func:`docs.freshness.check.status`) ran code that has
changed since it was measured, which says nothing yet about its figures: most edits (a clearer
message, a renamed helper, a new option) leave them as they were. :func:`verify` decides by
measurement instead of by trace: it runs the section's probe (its own command line at a tiny
size, with the runs that make its inputs, :func:`docs.freshness.probes.probe_runs`) once with
the code that measured it (the newest commit that still has its recorded fingerprint,
:func:`docs.freshness.check.measured_commit`) and once with today's, each writing its tables
into a scratch copy of the docs, and compares the two texts with their timings masked
(:func:`comparable_text`). The same text: the section is current again, today's fingerprint
recorded with the verdict. Another text: it is stale, and listed as such with the first line
that differs.

    python -m docs.freshness verify            # every section whose code moved
    python -m docs.freshness verify NAME ...   # these

A probe is one building of two rooms and a few frames, so it sees what that size reaches: a
change that moves only a full-size figure (a branch a tiny run never takes) passes unseen,
as it does the trace.

Examples:
    >>> comparable_text("_`placeclust demo` · 2026-11-29 · placeclust 0.16.0_\\n"
    ...                 "| precision | ms per frame |\\n|---|---|\\n| 0.97 | 41.2 |\\n"
    ...                 "12 minutes of one core in all.")
    '| precision | ms per frame |\\n|---|---|\\n| 0.97 | ~ |\\n~ of one core in all.'
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from docs.freshness import probes
from docs.freshness.probes import ROOT

#: a stamp line: command, date, versions, machine (never the same twice)
_STAMP = re.compile(r"^_`.*` · .*_$", re.M)
#: a duration or a rate in prose: a number and its unit
_DURATION = re.compile(r"\d+(?:\.\d+)?(?:\s*[-–]\s*\d+(?:\.\d+)?)?\s*(?:core-seconds?|core-hours?"
                       r"|minutes?|seconds?|hours?|min|ms|s|h)\b(?!-)")
#: a package's version, which the code that measured a table and today's may print otherwise
_VERSION = re.compile(r"\b(placeclust|MuJoCo|mujoco) \d+\.\d+(?:\.\d+)?")
#: a table column of timings, by its header
_TIMED = re.compile(r"second|minute|hour|\bms\b|ms_per|time|speed|per s\b|fps|cost|×|ratio"
                    r"|latency|core", re.I)


def comparable_text(text: str) -> str:
    """A section's text as two runs of the same code print it alike: without its stamp line,
    versions or timings (a table column whose header, the row above ``|---|``, names one, and
    a duration in prose) as ``~``."""
    text = _VERSION.sub(r"\1 ~", _STAMP.sub("", text))  # a figure is not its version
    lines = text.strip("\n").split("\n")
    separator = [bool(re.fullmatch(r"\|[-:| ]+\|?", line.strip())) for line in lines]
    timed: set[int] = set()
    out = []
    for i, line in enumerate(lines):
        if not line.startswith("|"):
            timed = set()
            out.append(_DURATION.sub("~", line))
            continue
        cells = line.strip().strip("|").split("|")
        if i + 1 < len(lines) and separator[i + 1]:  # a header: which of its columns are timed
            timed = {k for k, c in enumerate(cells) if _TIMED.search(c)}
        elif not separator[i]:
            cells = [" ~ " if k in timed else c for k, c in enumerate(cells)]
        out.append("|" + "|".join(cells) + "|")
    return "\n".join(out)


def _absolute(argv: list[str]) -> list[str]:
    """Arguments naming a file of the repository (``../shared/data/...``, ``assets/...``) as
    absolute paths, so the command runs from another checkout."""
    out = []
    for token in argv:
        head, eq, tail = token.rpartition("=") if token.startswith("--") else ("", "", token)
        if tail and not tail.startswith("-") and not Path(tail).is_absolute() \
                and (ROOT / tail).exists():
            tail = str((ROOT / tail).resolve())
        out.append(head + eq + tail)
    return out


def _command(argv: list[str]) -> list[str]:
    """A probe's command line as a process of the checkout on ``PYTHONPATH``."""
    if argv[:2] == ["python", "-m"]:
        return [sys.executable, "-m", *argv[2:]]
    return [sys.executable, "-m", "envs.commands.cli", *argv[1:]]


def probe_text(name: str, commands: dict[str, list[str]], tree: Path, scratch: Path) -> str:
    """The tables section ``name``'s probe writes with the code of checkout ``tree``,
    :func:`comparable_text` of them (every section the probe's own run writes, in order),
    kept in ``scratch`` for the other sections of the same command line.

    Raises:
        RuntimeError: a run failed; its last line of error says why.
    """
    scratch.mkdir(parents=True, exist_ok=True)
    runs = probes.probe_runs(name, commands, scratch)
    # the sections of one command line (a suite's tracks) run one probe: its own run's output
    # folder is named for the command, not the section
    own = str(scratch / f"own-{_digest(commands[name])}")
    runs[-1] = [own if t == str(scratch / name) else t for t in runs[-1]]
    section = [t for o, v in probes._options(commands[name]) if o == "--section"
               for t in ["--section", *v]]
    # sections of one command line (a suite's tracks) share one probe: run it once a checkout
    key = _digest([str(tree), runs, section])
    docs = scratch / f"probe-{key}.md"
    finished = scratch / f"probe-{key}.done"
    if finished.exists():
        return _in_place(docs.read_text(), scratch)
    docs.unlink(missing_ok=True)
    env = {**os.environ, "PYTHONPATH": str(tree), "MUJOCO_GL": os.environ.get("MUJOCO_GL",
                                                                            "egl")}
    for i, run in enumerate(runs):
        last = i == len(runs) - 1
        argv = _absolute(run) + (["--docs", str(docs), *section] if last else [])
        # a run that makes an input is the same for every section that reads it (a suite's
        # tracks feed its score): once a checkout
        made = scratch / f"run-{_digest([str(tree), argv])}.done"
        if made.exists() and not last:
            continue
        jobs = None if last else _out_runs(argv)
        if jobs is not None:
            _share_jobs(scratch / "jobs", jobs)
        done = subprocess.run(_command(argv), cwd=tree, env=env, capture_output=True, text=True)
        if done.returncode != 0:
            why = (done.stderr.strip().splitlines() or ["no message"])[-1]
            raise RuntimeError(f"`{shlex.join(run)}` failed in {tree}: {why}")
        if jobs is not None:
            _share_jobs(jobs, scratch / "jobs")
        made.touch()
    if not docs.exists():
        raise RuntimeError(f"the probe of {name} wrote no section")
    finished.touch()
    return _in_place(docs.read_text(), scratch)


def _out_runs(argv: list[str]) -> Path | None:
    """The job store of a closed-loop run that makes an input (``--out OUT``: ``OUT/runs``)."""
    out = probes.out_dir(argv) if argv[1:2] == ["leaderboard"] else None
    return None if out is None else Path(out) / "runs"


def _share_jobs(source: Path, target: Path) -> None:
    """Copy the job results of ``source`` that ``target`` lacks: the stand-ins of one
    checkout share their recognizers' jobs (a row is used again only if its stamp, the code
    that made it, is the run's: :func:`envs.runs.jobs.run_jobs`), so each stand-in runs only
    the recognizers it adds. One folder per checkout: today's jobs never answer for the old
    code's."""
    target.mkdir(parents=True, exist_ok=True)
    for row in source.glob("*.json"):
        if not (target / row.name).exists():
            shutil.copyfile(row, target / row.name)


def _digest(what: object) -> str:
    return hashlib.sha256(json.dumps(what).encode()).hexdigest()[:12]


def _in_place(text: str, scratch: Path) -> str:
    """:func:`comparable_text` of a probe's tables, its own scratch folder (in a figure's
    path: each checkout writes under its own) named alike."""
    return comparable_text(text.replace(str(scratch), "<scratch>"))


def checkout(commit: str, scratch: Path) -> Path:
    """A detached worktree of ``commit`` under ``scratch`` (made once, kept)."""
    tree = scratch / f"tree-{commit[:12]}"
    if not tree.exists():
        subprocess.run(["git", "worktree", "add", "--detach", "--force", str(tree), commit],
                       cwd=ROOT, check=True, capture_output=True)
    return tree


def first_difference(a: str, b: str) -> str:
    """Where ``a`` and ``b`` first differ, as ``then → now``: that line, from a little
    before the first character that differs.

    >>> first_difference("| x | 0.90 | 12 |", "| x | 0.93 | 12 |")
    "'| x | 0.90 | 12 |' → '| x | 0.93 | 12 |'"
    """
    for old, new in zip(a.split("\n") + [""], b.split("\n") + [""]):
        if old != new:
            at = next((i for i, (x, y) in enumerate(zip(old, new)) if x != y),
                      min(len(old), len(new)))
            start = max(0, at - 40)  # the lines from a little before where they part
            return f"{old[start:at + 60].strip()!r} → {new[start:at + 60].strip()!r}"
    return "none"


def verdict(name: str, entry: dict[str, Any], commands: dict[str, list[str]], scratch: Path
            ) -> tuple[bool, str]:
    """``(same, what)``: whether today's code writes the probe of ``name`` as the code of the
    commit that measured it did, and the first difference if not.

    Raises:
        ValueError: the section was recorded from a tree no commit holds (nothing to run).
        RuntimeError: a probe failed.
    """
    commit = entry.get("commit")
    if not commit:
        raise ValueError(f"{name} was measured by code no commit holds; measure it again")
    then = probe_text(name, commands, checkout(commit, scratch), scratch / "then" / commit[:12])
    now = probe_text(name, commands, ROOT, scratch / "now")
    return then == now, first_difference(then, now)


def remove_checkouts(scratch: Path) -> None:
    """Drop the worktrees :func:`checkout` made under ``scratch``."""
    for tree in scratch.glob("tree-*"):
        subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT,
                       capture_output=True)


Log = Callable[[str], None]
