"""The layout a newcomer reads in ``docs/design.md`` is the layout on disk: the module map
names every module, the layers and "no import circles" hold (import-linter's contracts in
``pyproject.toml``), no folder of ``envs/`` is crowded and no two modules share a name."""

import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("placeclust", "envs", "train", "docs")


def _modules() -> set[str]:
    return {p.relative_to(ROOT).as_posix() for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")
            if p.name != "__init__.py"}


def test_the_module_map_names_every_module_and_only_those():
    design = (ROOT / "docs" / "design.md").read_text()
    table = design.split("<!-- module-map", 1)[1].split("\n\n", 1)[0]
    mapped = re.findall(r"^\| `([\w/]+\.py)` \|", table, flags=re.M)
    assert len(mapped) == len(set(mapped)), "a module is in the map twice"
    modules = _modules()
    missing, extra = sorted(modules - set(mapped)), sorted(set(mapped) - modules)
    assert not missing, f"modules missing from the map: {missing}"
    assert not extra, f"the map names modules that do not exist: {extra}"


def test_the_import_contracts_hold():
    """Layers (train > commands > runs > agents > tasks > world > placeclust), a library free of the
    simulator, and no import circle among the modules of any package (imports inside
    functions included)."""
    lint = Path(sys.executable).with_name("lint-imports")
    done = subprocess.run([str(lint), "--no-cache"], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "BROKEN" not in done.stdout and "3 kept, 0 broken" in done.stdout


def test_no_folder_is_crowded_and_no_two_modules_share_a_name():
    folders = Counter(p.parent for p in (ROOT / "envs").rglob("*.py") if p.name != "__init__.py")
    assert max(folders.values()) <= 15, folders
    names = Counter(Path(m).name for m in _modules())
    assert [n for n, k in names.items() if k > 1] == []
