"""Every module, command and flag the README and the docs name exists: a reader who types what
the docs say gets the thing, not an import error or "unrecognized arguments"."""

import contextlib
import importlib
import io
import re
from pathlib import Path

import pytest

from envs.commands.cli import COMMANDS, build_parser

ROOT = Path(__file__).resolve().parent.parent
#: a dotted name in backticks under one of the repository's packages
DOTTED = re.compile(r"`((?:placeclust|envs|train|docs)(?:\.\w+)+)")
#: a ``placeclust`` command line in backticks or a code block, up to the line's end
COMMAND = re.compile(r"(?<![\w.-])placeclust ([a-z]\w*)([^`\n]*)")
#: the flags of one command line
FLAG = re.compile(r"(?<![\w-])(--[a-z][\w-]*)")


#: a generated section's body: a command's output on its date (a dated record, or current by
#: docs.freshness), not prose to keep in step by hand
GENERATED = re.compile(r"<!-- BEGIN GENERATED [\w-]+ -->.*?<!-- END GENERATED [\w-]+ -->", re.S)


def _docs() -> list[Path]:
    """The README and the docs' pages, less the retired tables (history, as the changelog)."""
    return [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").glob("*.md")
                                        if p.name != "retired.md")]


def _prose(doc: Path) -> str:
    return GENERATED.sub("", doc.read_text())


def _resolves(name: str) -> bool:
    """Whether ``name`` is a module, or an attribute of the longest module it starts with."""
    parts = name.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for part in parts[cut:]:
            if not hasattr(obj, part):
                return False
            obj = getattr(obj, part)
        return True
    return False


def _flags(command: str) -> set[str]:
    """The options ``placeclust COMMAND`` accepts, read from its help."""
    if command in COMMANDS:
        path, _, function = COMMANDS[command][0].partition(":")
        module = importlib.import_module(path, "envs.commands")
        main = getattr(module, function or "main")
        out = io.StringIO()
        with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
            main(["-h"])
        return set(FLAG.findall(out.getvalue()))
    parser = build_parser()
    sub = next(a for a in parser._actions if a.choices and command in a.choices)
    return {o for a in sub.choices[command]._actions for o in a.option_strings}


def test_every_module_the_docs_name_imports():
    missing = sorted({f"{doc.name}: {name}" for doc in _docs()
                      for name in DOTTED.findall(_prose(doc)) if not _resolves(name)})
    assert not missing, "\n".join(missing)


def test_every_command_and_flag_the_docs_name_exists():
    known = set(COMMANDS) | {a for act in build_parser()._actions if act.choices
                             for a in act.choices}
    flags: dict[str, set[str]] = {}
    missing = set()
    for doc in _docs():
        for command, rest in COMMAND.findall(_prose(doc)):
            if command == "import":  # "from placeclust import ..."
                continue
            if command not in known:
                missing.add(f"{doc.name}: placeclust {command}")
                continue
            accepted = flags.setdefault(command, _flags(command))
            missing |= {f"{doc.name}: placeclust {command} {flag}"
                        for flag in FLAG.findall(rest) if flag not in accepted}
    assert not missing, "\n".join(sorted(missing))
