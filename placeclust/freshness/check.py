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
    python -m placeclust.freshness record NAME ...  # after regenerating NAME

A stale section is one whose recorded fingerprint differs from today's; it passes ``check``
only when the docs say so (``--write`` lists it, with the command that would regenerate it,
in the section ``freshness``), so a table the code has moved under is either regenerated or
marked, never silently wrong. ``record`` fingerprints a section at the commit that wrote it
as the docs hold it today, or at the working tree if no commit holds it yet.

What the trace cannot see: code that runs only at full size (a branch the tiny run never
takes) and inputs no section produces (files under ``runs/`` that a ``make`` target made):
those are stood in by a tiny closed-loop run, so the check covers the code that reads them,
not whatever made them.

Examples:
    >>> code = "def f(x):\\n    '''Doc.'''\\n    return x + 1  # why\\n"
    >>> same = "def f(x):\\n    '''Other words.'''\\n    return x + 1\\n"
    >>> source_digest(code, ["f"]) == source_digest(same, ["f"])
    True
    >>> source_digest(code, ["f"]) == source_digest(code.replace("+ 1", "+ 2"), ["f"])
    False
"""

from __future__ import annotations

import argparse
import ast
import copy
import functools
import hashlib
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

MANIFEST = ROOT / "docs" / "generated.json"
DOCS = ROOT / "docs" / "benchmarks.md"
#: this module's own section: the stale ones, listed
SECTION = "freshness"
#: fingerprints are of syntax as this minor version of Python prints it
PYTHON = f"{sys.version_info.major}.{sys.version_info.minor}"


# -- fingerprints --------------------------------------------------------------------------

def _strip_docstrings(tree: ast.AST) -> None:
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if (isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
                and body and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)):
            node.body = body[1:] or [ast.Pass()]


def _strip_help(tree: ast.AST) -> None:
    """Drop ``help=`` texts of calls (argparse's): words, not behaviour."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            node.keywords = [k for k in node.keywords if k.arg != "help"]


def _definitions(tree: ast.Module) -> dict[str, ast.AST]:
    """Every function of a module by its ``__qualname__`` (``Cls.method``, ``f.<locals>.g``)."""
    found: dict[str, ast.AST] = {}

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                found[prefix + child.name] = child
                visit(child, f"{prefix}{child.name}.<locals>.")
            elif isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.")
            else:
                visit(child, prefix)

    visit(tree, "")
    return found


def _names(node: ast.AST) -> set[str]:
    """The identifiers a piece of code mentions (names and attributes)."""
    return {n.id if isinstance(n, ast.Name) else n.attr for n in ast.walk(node)
            if isinstance(n, ast.Name | ast.Attribute)}


def _binds(stmt: ast.stmt) -> set[str]:
    """The module-level names a statement defines."""
    if isinstance(stmt, ast.Import | ast.ImportFrom):
        return {(a.asname or a.name).split(".")[0] for a in stmt.names}
    if isinstance(stmt, ast.ClassDef):
        return {stmt.name}
    targets = stmt.targets if isinstance(stmt, ast.Assign) else \
        [stmt.target] if isinstance(stmt, ast.AnnAssign | ast.AugAssign) else []
    return {n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)}


_FUNCTION = (ast.FunctionDef, ast.AsyncFunctionDef)


def _without_methods(stmt: ast.stmt) -> ast.stmt:
    """A class statement without its functions (a copy: parsed trees are shared)."""
    if not isinstance(stmt, ast.ClassDef):
        return stmt
    bare = copy.copy(stmt)
    bare.body = [_without_methods(b) for b in stmt.body if not isinstance(b, _FUNCTION)] \
        or [ast.Pass()]
    return bare


@functools.lru_cache(maxsize=1024)
def _statements(tree: ast.Module) -> tuple[tuple[ast.stmt, frozenset[str], frozenset[str]], ...]:
    """A module's statements other than functions, each with the names it binds and mentions."""
    bare = [_without_methods(s) for s in tree.body if not isinstance(s, _FUNCTION)]
    return tuple((s, frozenset(_binds(s)), frozenset(_names(s))) for s in bare)


def _reach(tree: ast.Module, used: set[str]) -> tuple[list[ast.stmt], set[str]]:
    """The module-level statements the code naming ``used`` can reach: the constants, imports
    and classes (attributes, decorators, bases; not their methods) it names, what those name
    in turn, and every statement that defines nothing (a registration call). A constant or an
    import that the traced code never names may change freely. Returns them, and every name
    mentioned by them or by ``used``'s code."""
    statements = _statements(tree)
    kept: set[int] = set()
    used = set(used)
    grew = True
    while grew:
        grew = False
        for i, (_, binds, names) in enumerate(statements):
            if i not in kept and (not binds or binds & used):
                kept.add(i)
                used |= names
                grew = True
    return [statements[i][0] for i in sorted(kept)], used


@functools.lru_cache(maxsize=1024)
def _parse(source: str) -> ast.Module:
    """A module's syntax without docstrings and help texts (cached: callers must not edit it)."""
    tree = ast.parse(source)
    _strip_docstrings(tree)
    _strip_help(tree)
    return tree


def _module_file(importer: str, module: str | None, level: int, files: set[str]) -> str | None:
    """The repository file an import in ``importer`` names, if it is one of ``files``."""
    if level:
        base = Path(importer).parent.parts[:len(Path(importer).parent.parts) - level + 1]
        parts = [*base, *(module.split(".") if module else [])]
    else:
        parts = (module or "").split(".")
        parts[0] = {"placeclust_envs": "envs"}.get(parts[0], parts[0])
    stem = "/".join(parts)
    return next((c for c in (f"{stem}.py", f"{stem}/__init__.py") if c in files), None)


def _imported(path: str, stmt: ast.stmt, mentioned: set[str], files: set[str]
              ) -> list[tuple[str, set[str]]]:
    """What an import statement of ``path`` uses of other modules of ``files``: the names it
    imports from one, or, for a module it imports whole, every name ``path`` mentions."""
    pairs: list[tuple[str | None, set[str]]] = []
    if isinstance(stmt, ast.ImportFrom):
        for alias in stmt.names:
            sub = f"{stmt.module}.{alias.name}" if stmt.module else alias.name
            pairs += [(_module_file(path, stmt.module, stmt.level, files), {alias.name}),
                      (_module_file(path, sub, stmt.level, files), mentioned)]
    elif isinstance(stmt, ast.Import):
        pairs += [(_module_file(path, a.name, 0, files), mentioned) for a in stmt.names]
    return [(t, n) for t, n in pairs if t]


def _digests(trees: dict[str, ast.Module | None], functions: dict[str, list[str]]
             ) -> dict[str, str]:
    """Each module's digest: its traced functions and the module-level statements reachable
    from them, across modules (a constant imported from another module counts there). A
    module that is missing (``None``) counts as empty: one the traced code only imported,
    using nothing of it, may come and go."""
    files = set(trees)
    used: dict[str, set[str]] = {p: set() for p in files}
    found = {p: _definitions(t) if t else {} for p, t in trees.items()}
    for path, names in functions.items():
        used[path] |= {q.split(".")[0] for q in names}  # a method's class
        for q in names:
            used[path] |= _names(found[path][q]) if q in found[path] else set()
    reached: dict[str, list[ast.stmt]] = {}
    grew = True
    while grew:
        grew = False
        for path, tree in trees.items():
            reached[path], mentioned = _reach(tree, used[path]) if tree else ([], set())
            for stmt in reached[path]:
                for target, imported in _imported(path, stmt, mentioned, files):
                    if not imported <= used[target]:
                        used[target] |= imported
                        grew = True
    out = {}
    for path in trees:  # a missing module is an empty one: its functions are missing
        parts = [ast.unparse(found[path][q]) if q in found[path] else f"missing {q}"
                 for q in sorted(functions.get(path, []))]
        parts += [ast.unparse(s) for s in reached[path]]
        out[path] = hashlib.sha256("\n\0".join(parts).encode()).hexdigest()[:16]
    return out


def source_digest(source: str | None, qualnames: list[str]) -> str:
    """A digest of the named functions of one module and of the module-level statements they
    can reach, as syntax: docstrings, comments, layout and argparse's ``help=`` texts do not
    count. A missing module or function counts as a change.

    Args:
        source: the module's text, or None when the file does not exist.
        qualnames: functions' ``__qualname__`` in that module.
    """
    return _digests({"m.py": None if source is None else _parse(source)},
                    {"m.py": qualnames})["m.py"]


Reader = Callable[[str], "bytes | None"]


def working_tree(path: str) -> bytes | None:
    """A repository file's bytes today, or None."""
    file = ROOT / path
    return file.read_bytes() if file.is_file() else None


def at_commit(commit: str) -> Reader:
    """A reader of repository files as they were at ``commit``."""
    def read(path: str) -> bytes | None:
        done = subprocess.run(["git", "show", f"{commit}:{path}"], cwd=ROOT, capture_output=True)
        return done.stdout if done.returncode == 0 else None
    return read


def fingerprint(trace: dict[str, Any], read: Reader = working_tree) -> str:
    """The fingerprint of a trace (``{"functions": {path: [qualname]}, "files": [path]}``)
    over sources read by ``read``: what a section's figures depend on."""
    texts = {p: read(p) for p in trace["functions"]}
    trees = {p: None if t is None else _parse(t.decode()) for p, t in texts.items()}
    digest = hashlib.sha256()
    for path, value in sorted(_digests(trees, trace["functions"]).items()):
        digest.update(f"{path}:{value}\n".encode())
    for path in sorted(trace["files"]):
        data = read(path)
        digest.update(f"{path}:{'missing' if data is None else hashlib.sha256(data).hexdigest()}\n"
                      .encode())
    return digest.hexdigest()[:16]


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
                "its table.\n\n| section | command |\n|---|---|\n"
                + "\n".join(f"| {n} | `{commands[n][1]}` |" for n in stale))
    else:
        body = "Every table below is what today's code measures."
    write_section(docs, SECTION, body, "python -m placeclust.freshness check --write")
    return status(docs, manifest)


# -- recording -----------------------------------------------------------------------------

def record(names: list[str], docs: Path = DOCS, manifest: Path = MANIFEST,
           scratch: Path | None = None, log: Callable[[str], None] = print) -> None:
    """Trace each named section's probe and store what it depends on, fingerprinted at the
    commit that wrote the section as it stands (the working tree if no commit holds it)."""
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
        trace = probes.union([probes.trace_command(r, scratch) for r in runs])
        tracked = set(subprocess.run(["git", "ls-files", *trace["files"]], cwd=ROOT,
                                     capture_output=True, text=True).stdout.split())
        trace["files"] = [f for f in trace["files"] if f in tracked]
        commit = section_commit(name, docs)
        read = at_commit(commit) if commit else working_tree
        data = load(manifest)
        data["sections"][name] = {"stamp": stamp, "command": command, "commit": commit,
                                  "probes": [" ".join(r) for r in runs], "trace": trace,
                                  "fingerprint": fingerprint(trace, read)}
        data["acknowledged"].pop(name, None)
        save(data, manifest)
        now = fingerprint(trace)
        log(f"    {sum(map(len, trace['functions'].values()))} functions in "
            f"{len(trace['functions'])} files, {len(trace['files'])} data files; "
            + ("current" if now == data["sections"][name]["fingerprint"]
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
            record(names, args.docs, args.manifest, args.scratch)
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
              "`python -m placeclust.freshness record NAME`, or mark them stale with "
              "`python -m placeclust.freshness check --write`", file=sys.stderr)
        return 1
    return 0
