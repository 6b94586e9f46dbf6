"""Fingerprints of code as syntax: what a traced run of a command depends on.

A traced run (:mod:`docs.freshness.probes`) names the functions of the repository that
ran. Their fingerprint is their ``ast.unparse`` without docstrings or argparse ``help=`` texts,
with the module-level statements that code can reach (constants, imports, class attributes,
registration calls), followed across imports to where a name is defined: so rewording a
docstring, a comment or an option's help, or adding a function or a constant the run never
names, changes nothing, while a changed line, default or constant it reaches does.

Examples:
    >>> code = "def f(x):\\n    '''Doc.'''\\n    return x + 1  # why\\n"
    >>> same = "def f(x):\\n    '''Other words.'''\\n    return x + 1\\n"
    >>> source_digest(code, ["f"]) == source_digest(same, ["f"])
    True
    >>> source_digest(code, ["f"]) == source_digest(code.replace("+ 1", "+ 2"), ["f"])
    False
"""

from __future__ import annotations

import ast
import copy
import functools
import hashlib
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

from docs.freshness.probes import ROOT


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


@functools.lru_cache(maxsize=1024)
def _definitions(tree: ast.Module) -> dict[str, ast.AST]:
    """Every function of a module by its ``__qualname__`` (``Cls.method``, ``f.<locals>.g``);
    cached like :func:`_parse`, whose trees it is given (callers must not edit the result)."""
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
        parts = [_unparse(found[path][q]) if q in found[path] else f"missing {q}"
                 for q in sorted(functions.get(path, []))]
        parts += [_unparse(s) for s in reached[path]]
        out[path] = hashlib.sha256("\n\0".join(parts).encode()).hexdigest()[:16]
    return out


@functools.lru_cache(maxsize=4096)
def _digests_of(trees: tuple[tuple[str, ast.Module | None], ...],
                functions: tuple[tuple[str, tuple[str, ...]], ...]) -> dict[str, str]:
    """:func:`_digests` of hashable arguments, cached: the same sources (the same cached trees)
    traced for the same functions digest alike at every commit that did not change them."""
    return _digests(dict(trees), {p: list(q) for p, q in functions})


@functools.lru_cache(maxsize=65536)
def _unparse(node: ast.AST) -> str:
    """``ast.unparse``, cached by node: the cached trees' nodes are the same objects each
    time the same source is read, at any commit."""
    return ast.unparse(node)


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
    """A reader of repository files as they were at ``commit`` (a hash or any ref, resolved
    once: a branch that moves later does not change what this reader reads)."""
    done = subprocess.run(["git", "rev-parse", "--verify", "--quiet", f"{commit}^{{commit}}"],
                          cwd=ROOT, capture_output=True, text=True)
    resolved = done.stdout.strip() if done.returncode == 0 else commit
    return functools.partial(_show, resolved)


@functools.lru_cache(maxsize=8192)
def _show(commit: str, path: str) -> bytes | None:
    """``path`` at ``commit``, or None where it did not exist. Cached, because a commit's
    files never change and probing which commit measured a section reads the same files at
    the same commits for every section."""
    done = subprocess.run(["git", "show", f"{commit}:{path}"], cwd=ROOT, capture_output=True)
    return done.stdout if done.returncode == 0 else None


def fingerprint(trace: dict[str, Any], read: Reader = working_tree) -> str:
    """The fingerprint of a trace (``{"functions": {path: [qualname]}, "files": [path]}``)
    over sources read by ``read``: what a section's figures depend on."""
    texts = {p: read(p) for p in trace["functions"]}
    trees = {p: None if t is None else _parse(t.decode()) for p, t in texts.items()}
    digest = hashlib.sha256()
    digests = _digests_of(tuple(sorted(trees.items())),
                          tuple((p, tuple(q)) for p, q in sorted(trace["functions"].items())))
    for path, value in sorted(digests.items()):
        digest.update(f"{path}:{value}\n".encode())
    for path in sorted(trace["files"]):
        data = read(path)
        digest.update(f"{path}:{'missing' if data is None else hashlib.sha256(data).hexdigest()}\n"
                      .encode())
    return digest.hexdigest()[:16]
