"""Which generated sections of ``docs/benchmarks.md`` the current code would change.

Every table of ``docs/benchmarks.md`` is written by the command that measures it
(:mod:`placeclust.docs_section`). ``docs/generated.json`` records, for each section, what its
figures depend on: the functions of this repository its command runs and the repository files
it reads, found by running the command at a tiny size under a tracer (``record``), and a
*fingerprint* of them: their source as syntax, without docstrings and comments. A section
whose fingerprint is today's is *current*. One whose code changed since is *moved*: that it
ran changed code says nothing yet about its figures, and ``verify``
(:mod:`docs.freshness.verify`) decides by running its probe with the code that measured it
and with today's: the same tables, and it is current again; others, and it *differs*, and the
docs list it as stale, with its command.

The docs policy: the sections that a claim of the README or ``docs/design.md`` cites
(:data:`docs.freshness.cited.CITED`) stay current, so ``check`` fails on one that moved or
differs; every other section is a *dated record* (its stamp line gives the command, date,
version and machine) that a code change does not mark stale unless its probe shows that the
change moves its figures::

    python -m docs.freshness check            # exit 1: a cited table moved, or the list is old
    python -m docs.freshness verify [NAME...] # probe the moved sections, then list what differs
    python -m docs.freshness record --now NAME  # after measuring NAME again

``record`` fingerprints a section at the commit that wrote it as the docs hold it today, or
at the working tree if no commit holds it yet.

What the trace cannot see: code that runs only at full size (a branch the tiny run never
takes) and inputs no section produces (files under ``runs/`` that a ``make`` target made):
those are stood in by a tiny closed-loop run, so the check covers the code that reads them,
not whatever made them.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import re
import shlex
import subprocess
import sys
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

from docs.freshness import probes, verify
from docs.freshness.cited import CITED
from docs.freshness.probes import ROOT
from docs.freshness.syntax import at_commit, fingerprint, working_tree
from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import markers, write_section

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
        return {"sections": {}, "differs": {}}
    data = json.loads(manifest.read_text())
    data.setdefault("differs", {})
    data.pop("acknowledged", None)  # before 0.17.0: marked by hand, never probed: moved
    return data


def save(data: dict[str, Any], manifest: Path = MANIFEST) -> None:
    data["python"] = PYTHON
    manifest.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


@contextlib.contextmanager
def _locked(manifest: Path) -> Iterator[None]:
    """Hold an exclusive lock beside ``manifest``: verify processes run side by side each
    read, change and write it whole."""
    with open(manifest.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


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


def measured_commit(name: str, entry: dict[str, Any], docs: Path = DOCS) -> str | None:
    """The newest commit whose code still has section ``name``'s recorded fingerprint, back to
    :func:`section_commit` (which measured it), that one if none has; None if no commit holds
    the section.

    The code of any such commit computes the section as the code that measured it did, by the
    fingerprint's own premise, and probing the newest one lets the sections a change moved
    share one checkout of the code before it (their probes' runs are made once a checkout)."""
    oldest = section_commit(name, docs)
    if oldest is None:
        return None
    log = subprocess.run(["git", "log", "--format=%H", "--ancestry-path", f"{oldest}..HEAD"],
                         cwd=ROOT, capture_output=True, text=True).stdout.split()
    for commit in log + [oldest]:  # newest first
        if fingerprint(entry["trace"], at_commit(commit)) == entry["fingerprint"]:
            return commit
    return oldest


def status(docs: Path = DOCS, manifest: Path = MANIFEST) -> dict[str, list[str]]:
    """Sections by state: ``current``; ``moved`` (the code it ran changed since, and no probe
    has said whether its figures do); ``differs`` (a probe showed they would:
    :mod:`docs.freshness.verify`); ``unrecorded`` (written since the last ``record``, or
    never); and ``unlisted``, the sections whose entry in the docs' list of stale tables is
    not what the manifest says (``check --write`` lists what differs)."""
    data = load(manifest)
    out: dict[str, list[str]] = {"current": [], "moved": [], "differs": [], "unrecorded": []}
    for name, (stamp, _) in sections(docs).items():
        entry = data["sections"].get(name)
        if entry is None or entry["stamp"] != stamp:
            out["unrecorded"].append(name)
            continue
        now = fingerprint(entry["trace"])
        if now == entry["fingerprint"]:
            out["current"].append(name)
        elif data["differs"].get(name) == now:
            out["differs"].append(name)
        else:
            out["moved"].append(name)
    listed = set(re.findall(r"^\| ([a-z0-9-]+) \| ", _section_text(docs.read_text(), SECTION)
                            or "", flags=re.M)) - {"section"}
    out["unlisted"] = sorted(listed.symmetric_difference(out["differs"]))
    return out


def failing(state: dict[str, list[str]], cited: Mapping[str, str] | None = None
            ) -> dict[str, list[str]]:
    """What makes ``check`` fail: sections never recorded, cited sections (``cited``, default
    :data:`~docs.freshness.cited.CITED`) that moved or differ, and a list of stale tables
    that is not the manifest's."""
    cited = CITED if cited is None else cited
    return {"unrecorded": state["unrecorded"],
            "cited and not current": [n for n in state["moved"] + state["differs"]
                                      if n in cited],
            "listed otherwise in the docs": state["unlisted"]}


def write_stale_list(docs: Path = DOCS, manifest: Path = MANIFEST) -> dict[str, list[str]]:
    """List the sections whose probe differs in the docs' ``freshness`` section, with the
    command that regenerates each and the first line that differs."""
    data, state = load(manifest), status(docs, manifest)
    commands = sections(docs)
    differs = sorted(state["differs"])
    if differs:
        body = ("Today's code writes these tables otherwise than the code that measured them "
                "(`python -m docs.freshness verify` ran each one's probe, a tiny run of its "
                "command, with both): their figures may differ today. Each command "
                "regenerates its table; one that reads `runs/` needs what `make benchmarks` "
                "runs before it. Every other table is current, or a dated record whose code "
                "has changed in ways its probe does not see.\n\n"
                "| section | first difference (then → now) | command |\n|---|---|---|\n"
                + "\n".join(f"| {n} | "
                             + data["sections"][n].get("difference", "").replace("|", "\\|")
                             + f" | `{commands[n][1]}` |" for n in differs))
    else:
        body = ("No table is known to differ from what today's code measures: each is current, "
                "or a dated record whose code has changed in ways its probe does not see "
                "(`python -m docs.freshness verify`).")
    accepted = sorted(n for n in state["current"] if "accepted" in data["sections"][n])
    if accepted:  # current in figures; their words are the older code's until measured again
        body += ("\n\nThese tables' probes differ in words printed beside the figures, not in "
                 "a figure (read and accepted, `python -m docs.freshness accept`); the text "
                 "above each is the older code's until it is measured again:\n\n"
                 + "\n".join(f"- `{n}`: {data['sections'][n]['accepted']['difference']} "
                              f"({data['sections'][n]['accepted']['because']})"
                              for n in accepted))
    write_section(docs, SECTION, body, "python -m docs.freshness check --write")
    return status(docs, manifest)


def accept(names: list[str], because: str, docs: Path = DOCS, manifest: Path = MANIFEST
           ) -> None:
    """Take sections whose probe differs (:func:`run_verify`) as current where a person read
    both probes' tables and found that no figure differs, only words the table prints beside
    them (a setting renamed in a flag line): today's fingerprint is recorded with the
    difference and ``because``, and the docs' ``freshness`` section lists them until the
    section is measured again (:func:`record`).

    Raises:
        ValueError: no reason given, or a section that does not differ.
    """
    import datetime

    if not because.strip():
        raise ValueError("say why the difference is not a figure (--because)")
    with _locked(manifest):
        data = load(manifest)
        same = sorted(set(names) - set(data["differs"]))
        if same:
            raise ValueError(f"{same} do not differ: accept only what verify found different")
        for name in names:
            entry = data["sections"][name]
            entry["accepted"] = {"difference": entry.pop("difference", ""), "because": because,
                                 "date": str(datetime.date.today())}
            entry["fingerprint"] = fingerprint(entry["trace"])
            data["differs"].pop(name)
        save(data, manifest)
    write_stale_list(docs, manifest)


def run_verify(names: list[str], docs: Path = DOCS, manifest: Path = MANIFEST,
               scratch: Path | None = None, log: Callable[[str], None] = print) -> None:
    """Probe each named section with the code that measured it and with today's
    (:func:`docs.freshness.verify.verdict`) and record the verdict: the same tables, today's
    fingerprint is the section's; others, it differs (and the docs list it).

    Raises:
        RuntimeError: after every section, naming those whose probe failed (no verdict).
    """
    import datetime
    import tempfile

    scratch = Path(scratch or tempfile.mkdtemp(prefix="freshness-verify-"))
    commands = {n: shlex.split(c) for n, (_, c) in sections(docs).items()}
    failed: list[str] = []
    try:
        for i, name in enumerate(names, 1):
            data = load(manifest)
            entry = data["sections"][name]
            # recorded --now: measured by the code that committed the section's text with it
            then = entry.get("commit") or measured_commit(name, entry, docs)
            log(f"[{i}/{len(names)}] {name}: its probe with the code of {(then or '?')[:10]} "
                "and with today's")
            try:
                same, what = verify.verdict(name, {**entry, "commit": then}, commands, scratch)
            except (ValueError, RuntimeError) as e:  # the next sections can still be judged
                failed.append(name)
                log(f"    not judged: {e}")
                continue
            now = fingerprint(entry["trace"])
            with _locked(manifest):  # another verify may have saved while this probe ran
                data = load(manifest)
                entry = data["sections"][name]
                if same:
                    entry.update(fingerprint=now, verified=str(datetime.date.today()))
                    entry.pop("difference", None)
                    data["differs"].pop(name, None)
                else:
                    entry["difference"] = what
                    data["differs"][name] = now
                save(data, manifest)
            log(f"    {'the same: current' if same else 'differs: ' + what}")
    finally:
        verify.remove_checkouts(scratch)
    write_stale_list(docs, manifest)
    if failed:
        raise RuntimeError(f"no verdict for {' '.join(failed)}: their probes failed (above)")


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
        data["differs"].pop(name, None)
        save(data, manifest)
        today = fingerprint(trace)
        log(f"    {sum(map(len, trace['functions'].values()))} functions in "
            f"{len(trace['functions'])} files, {len(trace['files'])} data files; "
            + ("current" if today == data["sections"][name]["fingerprint"]
               else f"stale: the code moved since {commit[:10] if commit else 'now'}"))


def _parser() -> ArgumentParser:
    p = ArgumentParser(prog="python -m docs.freshness", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="what", required=True)
    check = sub.add_parser("check", help="the sections' states; fails on a cited one that is "
                           "not current")
    check.add_argument("--write", action="store_true",
                       help="list the sections whose probe differs in the docs (section "
                       "'freshness')")
    ver = sub.add_parser("verify", help="run moved sections' probes with the code that "
                         "measured them and with today's, and record the verdict")
    ver.add_argument("names", nargs="*", help="sections (default: every moved one, cited first)")
    rec = sub.add_parser("record", help="trace sections' tiny runs and store what they use")
    rec.add_argument("names", nargs="*", help="sections (default: the unrecorded ones)")
    rec.add_argument("--now", action="store_true",
                     help="the sections were just measured by the code as it stands")
    acc = sub.add_parser("accept", help="take sections whose probe differs only in words "
                         "beside the figures as current, saying why (listed in the docs)")
    acc.add_argument("names", nargs="+", help="sections verify found to differ")
    acc.add_argument("--because", required=True, help="what differs and why it is no figure")
    for q in (ver, rec):
        q.add_argument("--scratch", type=Path, help="a folder for the tiny runs (kept)")
    for q in (check, ver, rec, acc):
        q.add_argument("--docs", type=Path, default=DOCS)
        q.add_argument("--manifest", type=Path, default=MANIFEST)
    return p


def _act(args: Any) -> None:
    """``record``, ``verify`` or ``accept`` (``check`` only reports)."""
    if args.what == "accept":
        accept(args.names, args.because, args.docs, args.manifest)
    elif args.what == "record":
        names = args.names or status(args.docs, args.manifest)["unrecorded"]
        record(names, args.docs, args.manifest, args.scratch, now=args.now)
    elif args.what == "verify":
        moved = status(args.docs, args.manifest)["moved"]
        names = args.names or sorted(moved, key=lambda n: n not in CITED)
        unknown = sorted(set(names) - set(sections(args.docs)))
        if unknown:
            raise ValueError(f"no generated section named {unknown} in {args.docs}")
        run_verify(names, args.docs, args.manifest, args.scratch)


def main(argv: list[str] | None = None) -> int:
    p = _parser()
    args = p.parse_args(sys.argv[1:] if argv is None else argv)
    if not args.docs.is_file():
        p.error(f"no such file: {args.docs}")
    if args.manifest.exists() and not comparable(args.manifest):
        p.error(f"{args.manifest} was recorded with Python {load(args.manifest)['python']}; "
                f"this is {PYTHON}, whose syntax trees may print otherwise: run it with that one")
    try:
        _act(args)
    except (ValueError, RuntimeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if args.what == "record":
        return 0
    state = write_stale_list(args.docs, args.manifest) if getattr(args, "write", False) else \
        status(args.docs, args.manifest)
    for key in ("current", "moved", "differs", "unrecorded", "unlisted"):
        if state[key]:
            print(f"{key} ({len(state[key])}): {' '.join(state[key])}")
    failed = {k: v for k, v in failing(state).items() if v}
    for what, names in failed.items():
        print(f"{what}: {' '.join(names)}", file=sys.stderr)
    if failed:
        print("cited tables must be current: measure them again (then `python -m "
              "docs.freshness record --now NAME`) or `python -m docs.freshness verify NAME`; "
              "`check --write` lists what differs", file=sys.stderr)
        return 1
    return 0
