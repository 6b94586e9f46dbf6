"""Benchmark tables written into the docs by the command that measures them.

``docs/benchmarks.md`` holds only tables that a command reproduces. Each lives between two
markers that name it; the command that measures it replaces what lies between them (and says
which command it was, when, and with which version), leaving the rest of the file as it is::

    <!-- BEGIN GENERATED demo -->
    ...
    <!-- END GENERATED demo -->

What each section depends on is recorded apart (:mod:`docs.freshness`): after a command
rewrites a section, ``python -m docs.freshness record --now NAME`` traces it anew, and
``python -m docs.freshness check`` tells which sections today's code would change.
"""

from __future__ import annotations

import datetime
import os
import platform
import re
from pathlib import Path

from placeclust import __version__
from placeclust.atomic import write_atomic

_NAME = re.compile(r"[a-z0-9][a-z0-9-]*")


def markers(name: str) -> tuple[str, str]:
    """The ``BEGIN`` and ``END`` comment lines around the section ``name``."""
    if not _NAME.fullmatch(name):
        raise ValueError(f"section name must be lowercase letters, digits and '-', got {name!r}")
    return f"<!-- BEGIN GENERATED {name} -->", f"<!-- END GENERATED {name} -->"


def write_section(path: str | os.PathLike, name: str, body: str, command: str) -> Path:
    """Put ``body`` between the markers of section ``name`` of the markdown file ``path``.

    A file or a section that does not exist yet is created (a new section goes at the end,
    under a ``## name`` heading). The file is replaced atomically, so an interrupted write
    leaves the old one.

    Args:
        path: the markdown file, e.g. ``docs/benchmarks.md``.
        name: the section (lowercase letters, digits, ``-``).
        body: the markdown to put there: a table, a few lines of context.
        command: the command line that produced ``body``, recorded above it.

    Returns:
        The path written.

    Raises:
        ValueError: the name is malformed, or the file has a ``BEGIN`` marker of this section
            without its ``END`` (or twice): the file is left untouched.

    Examples:
        >>> import tempfile, pathlib
        >>> doc = pathlib.Path(tempfile.mkdtemp()) / "benchmarks.md"
        >>> _ = doc.write_text("# Benchmarks\\n\\nHand-written text stays.\\n")
        >>> _ = write_section(doc, "demo", "| a |\\n|---|\\n| 1 |", "make demo")
        >>> _ = write_section(doc, "demo", "| a |\\n|---|\\n| 2 |", "make demo")
        >>> text = doc.read_text()
        >>> "Hand-written text stays." in text, "| 1 |" in text, text.count("| 2 |")
        (True, False, 1)
    """
    begin, end = markers(name)
    path = Path(path)
    text = path.read_text() if path.exists() else ""
    n_begin, n_end = text.count(begin), text.count(end)
    if (n_begin, n_end) not in ((0, 0), (1, 1)) or text.find(begin) > text.find(end):
        raise ValueError(f"{path}: section {name!r} needs exactly one {begin!r} followed by one "
                         f"{end!r}; found {n_begin} and {n_end}. Left the file as it is.")
    stamp = (f"_`{command}` · {datetime.date.today().isoformat()} · placeclust {__version__} · "
             f"Python {platform.python_version()}, {os.cpu_count()} CPUs_")
    block = f"{begin}\n{stamp}\n\n{body.strip()}\n{end}"
    if n_begin:
        head, rest = text.split(begin, 1)
        text = head + block + rest.split(end, 1)[1]
    else:
        text = (text.rstrip() + "\n\n" if text.strip() else "") + f"## {name}\n\n{block}\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_atomic(path, lambda f: f.write(text.encode()))
