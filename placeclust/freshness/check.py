"""Which generated sections of ``docs/benchmarks.md`` the current code would change.

Every table of ``docs/benchmarks.md`` is written by the command that measures it
(:mod:`placeclust.docs_section`). ``docs/generated.json`` records, for each section, what its
figures depend on: the functions of this repository its command runs and the repository files
it reads, found by running the command at a tiny size under a tracer (``record``), and a
*fingerprint* of them: their source as syntax, without docstrings and comments, so rewording
a docstring changes nothing, while changing a line of a function the command runs, a default,
a module constant or a shipped policy does. ``check`` recomputes every fingerprint from
today's sources (cheap: no command runs) and lists the sections the code has moved under::

    python -m placeclust.freshness check            # exit 1 if a change went unnoticed
    python -m placeclust.freshness check --write    # list the stale ones in the docs
    python -m placeclust.freshness record --now NAME  # after measuring NAME again

A stale section is one whose recorded fingerprint differs from today's; it passes ``check``
only when the docs say so (``--write`` lists it, with the command that would regenerate it,
in the section ``freshness``), so a table the code has moved under is either regenerated or
marked, never silently wrong. ``record`` fingerprints a section at the commit that wrote it
as the docs hold it today, or at the working tree if no commit holds it yet.

What the trace cannot see: code that runs only at full size (a branch the tiny run never
takes) and inputs no section produces (files under ``runs/`` that a ``make`` target made):
those are stood in by a tiny closed-loop run, so the check covers the code that reads them,
not whatever made them.
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from placeclust.docs_section import markers, write_section
from placeclust.freshness import probes
from placeclust.freshness.probes import ROOT
from placeclust.freshness.syntax import at_commit, fingerprint, working_tree

MANIFEST = ROOT / "docs" / "generated.json"
DOCS = ROOT / "docs" / "benchmarks.md"
#: this module's own section: the stale ones, listed
SECTION = "freshness"
#: fingerprints are of syntax as this minor version of Python prints it
PYTHON = f"{sys.version_info.major}.{sys.version_info.minor}"


# -- the docs and the manifest -------------------------------------------------------------

_SECTION = re.compile(r"<!-- BEGIN GENERATED ([a-z0-9-]+) -->\n(_`(.+?)` · [^\n]*_)")


def sections(docs: Path = DOCS) -> dict[str, tuple[str, str]]:
    """Every generated section of ``docs``: ``{name: (stamp line, command line)}``."""
    return {m[1]: (m[2], m[3]) for m in _SECTION.finditer(docs.read_text()) if m[1] != SECTION}


def load(manifest: Path = MANIFEST) -> dict[str, Any]:
    if not manifest.exists():
        return {"sections": {}, "acknowledged": {}}
    return json.loads(manifest.read_text())


def save(data: dict[str, Any], manifest: Path = MANIFEST) -> None:
    data["python"] = PYTHON
    manifest.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


def comparable(manifest: Path = MANIFEST) -> bool:
    """Whether this Python prints syntax as the one that recorded the fingerprints did
    (``ast.unparse`` may differ between minor versions)."""
    return load(manifest).get("python", PYTHON) == PYTHON


def _section_text(text: str, name: str) -> str | None:
    begin, end = markers(name)
    if begin not in text:
        return None
    return text.split(begin, 1)[1].split(end, 1)[0]


def section_commit(name: str, docs: Path = DOCS) -> str | None:
    """The commit that wrote section ``name`` as the docs hold it today (the oldest of the
    newest run of commits holding that text), or None if no commit holds it yet (or the docs
    are outside the repository)."""
    docs = docs.resolve()
    if not docs.is_relative_to(ROOT):
        return None
    rel = str(docs.relative_to(ROOT))
    today = _section_text(docs.read_text(), name)
    log = subprocess.run(["git", "log", "--format=%H", "--", rel], cwd=ROOT,
                         capture_output=True, text=True).stdout.split()
    found = None
    for commit in log:  # newest first
        old = at_commit(commit)(rel)
        if old is None or _section_text(old.decode(), name) != today:
            break
        found = commit
    return found


def status(docs: Path = DOCS, manifest: Path = MANIFEST) -> dict[str, list[str]]:
    """Sections by state: ``current``; ``stale`` (the code moved since; ``acknowledged`` if
    the docs say so); ``unrecorded`` (written since the last ``record``, or never). A section
    the docs' list calls stale while the manifest does not (or the other way) counts as
    ``stale`` too, until ``check --write`` lists what is."""
    data = load(manifest)
    out: dict[str, list[str]] = {"current": [], "stale": [], "acknowledged": [], "unrecorded": []}
    for name, (stamp, _) in sections(docs).items():
        entry = data["sections"].get(name)
        if entry is None or entry["stamp"] != stamp:
            out["unrecorded"].append(name)
            continue
        now = fingerprint(entry["trace"])
        if now == entry["fingerprint"]:
            out["current"].append(name)
        elif data["acknowledged"].get(name) == now:
            out["acknowledged"].append(name)
        else:
            out["stale"].append(name)
    listed = set(re.findall(r"^\| ([a-z0-9-]+) \| `", _section_text(docs.read_text(), SECTION)
                            or "", flags=re.M))
    if listed != set(out["acknowledged"]):  # the docs' list must say what the manifest says
        out["stale"] += sorted(listed.symmetric_difference(out["acknowledged"]) - set(out["stale"])
                               - set(out["unrecorded"]))
    return out


def write_stale_list(docs: Path = DOCS, manifest: Path = MANIFEST) -> dict[str, list[str]]:
    """Mark every stale section as such: in the manifest and in the docs' ``freshness``
    section, with the command that regenerates it."""
    data, state = load(manifest), status(docs, manifest)
    now = {n: fingerprint(data["sections"][n]["trace"])
           for n in state["stale"] + state["acknowledged"]}
    stale = sorted(n for n, value in now.items() if value != data["sections"][n]["fingerprint"])
    data["acknowledged"] = {n: now[n] for n in stale}
    save(data, manifest)
    commands = sections(docs)
    if stale:
        body = ("The code has changed under these tables since they were measured (the "
                "functions their commands run, as `python -m placeclust.freshness check` "
                "compares them): their figures may differ today. Each command regenerates "
                "its table; one that reads `runs/` needs what `make benchmarks` runs before "
                "it.\n\n| section | command |\n|---|---|\n"
                + "\n".join(f"| {n} | `{commands[n][1]}` |" for n in stale))
    else:
        body = "Every table below is what today's code measures."
    write_section(docs, SECTION, body, "python -m placeclust.freshness check --write")
    return status(docs, manifest)


# -- recording -----------------------------------------------------------------------------

def record(names: list[str], docs: Path = DOCS, manifest: Path = MANIFEST,
           scratch: Path | None = None, log: Callable[[str], None] = print,
           now: bool = False) -> None:
    """Trace each named section's probe and store what it depends on, fingerprinted at the
    commit that wrote the section as it stands (the working tree if no commit holds it), or,
    with ``now``, at the working tree: the caller says today's code just measured it (a
    table measured again may come out the same, text and stamp, on the same day)."""
    import tempfile

    scratch = Path(scratch or tempfile.mkdtemp(prefix="freshness-"))
    found = sections(docs)
    commands = {n: shlex.split(c) for n, (_, c) in found.items()}
    unknown = sorted(set(names) - set(found))
    if unknown:
        raise ValueError(f"no generated section named {unknown} in {docs}")
    for i, name in enumerate(names, 1):
        stamp, command = found[name]
        runs = probes.probe_runs(name, commands, scratch)
        log(f"[{i}/{len(names)}] {name}: tracing {len(runs)} tiny run(s)")
        trace = probes.union([probes.trace_command(r, scratch, read_by_none=r is runs[-1])
                              for r in runs])
        tracked = set(subprocess.run(["git", "ls-files", *trace["files"]], cwd=ROOT,
                                     capture_output=True, text=True).stdout.split())
        trace["files"] = [f for f in trace["files"] if f in tracked]
        commit = None if now else section_commit(name, docs)
        read = at_commit(commit) if commit else working_tree
        data = load(manifest)
        data["sections"][name] = {"stamp": stamp, "command": command, "commit": commit,
                                  "probes": [" ".join(r) for r in runs], "trace": trace,
                                  "fingerprint": fingerprint(trace, read)}
        data["acknowledged"].pop(name, None)
        save(data, manifest)
        today = fingerprint(trace)
        log(f"    {sum(map(len, trace['functions'].values()))} functions in "
            f"{len(trace['functions'])} files, {len(trace['files'])} data files; "
            + ("current" if today == data["sections"][name]["fingerprint"]
               else f"stale: the code moved since {commit[:10] if commit else 'now'}"))


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    p = argparse.ArgumentParser(prog="python -m placeclust.freshness", description=__doc__
                                .split("\n\n")[0])
    sub = p.add_subparsers(dest="what", required=True)
    check = sub.add_parser("check", help="list the sections the code has moved under")
    check.add_argument("--write", action="store_true",
                       help="mark the stale ones in the docs (section 'freshness')")
    rec = sub.add_parser("record", help="trace sections' tiny runs and store what they use")
    rec.add_argument("names", nargs="*", help="sections (default: the unrecorded ones)")
    rec.add_argument("--scratch", type=Path, help="a folder for the tiny runs (kept)")
    rec.add_argument("--now", action="store_true",
                     help="the sections were just measured by the code as it stands")
    for q in (check, rec):
        q.add_argument("--docs", type=Path, default=DOCS)
        q.add_argument("--manifest", type=Path, default=MANIFEST)
    args = p.parse_args(argv)
    if not args.docs.is_file():
        p.error(f"no such file: {args.docs}")
    if args.manifest.exists() and not comparable(args.manifest):
        p.error(f"{args.manifest} was recorded with Python {load(args.manifest)['python']}; "
                f"this is {PYTHON}, whose syntax trees may print otherwise: run it with that one")
    if args.what == "record":
        names = args.names or status(args.docs, args.manifest)["unrecorded"]
        try:
            record(names, args.docs, args.manifest, args.scratch, now=args.now)
        except (ValueError, RuntimeError) as e:
            print(f"error: {e}", file=sys.stderr)
            return 2
        return 0
    state = write_stale_list(args.docs, args.manifest) if args.write else \
        status(args.docs, args.manifest)
    for key in ("current", "acknowledged", "stale", "unrecorded"):
        if state[key]:
            print(f"{key} ({len(state[key])}): {' '.join(state[key])}")
    if state["stale"] or state["unrecorded"]:
        print("the code has moved under the sections above, unnoticed: regenerate them, then "
              "`python -m placeclust.freshness record --now NAME`, or mark them stale with "
              "`python -m placeclust.freshness check --write`", file=sys.stderr)
        return 1
    return 0
