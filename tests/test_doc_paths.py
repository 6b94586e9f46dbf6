"""Every file path the docs and docstrings name exists: a reader sent to a file finds it."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: a repository path: one of the top-level folders, then a file with an extension
PATH = re.compile(r"(?<![\w/.-])((?:tests|envs|placeclust|train|docs|assets|examples)/"
                  r"[\w./-]+\.(?:py|md|json|yml|yaml|zip|png|xml|npz))\b")


#: files docs/design.md's "Adding a task" tells a reader to write
TO_WRITE = {"envs/tasks/posters.py", "tests/envs/tasks/test_posters.py"}


def _sources():
    yield from (ROOT / "README.md", ROOT / "CHANGELOG.md")
    yield from (ROOT / "docs").glob("*.md")
    for folder in ("placeclust", "envs", "train", "tests", "examples"):
        yield from (ROOT / folder).rglob("*.py")


def test_every_path_named_exists():
    missing = []
    for source in _sources():
        if source.name == "CHANGELOG.md":  # history may name files since moved
            continue
        for path in set(PATH.findall(source.read_text())):
            if "NAME" in path or path in TO_WRITE:
                continue
            if not (ROOT / path).exists():
                missing.append(f"{source.relative_to(ROOT)} names {path}")
    assert not missing, "\n".join(sorted(missing))
