"""The wheel a user installs: built from the repository, installed into a fresh virtual
environment and used from another directory, it makes ``PlaceNav-v0`` and runs
``placeclust tour``, ``placeclust cluster`` and the closed loop: ``placeclust errands`` with the
learned agent, and ``placeclust leaderboard`` (the planner) of a recognizer of the user's own
against the true rooms, then ``placeclust compare`` (``docs/design.md``, "Packaging")."""

import json
import shutil
import subprocess
import sys
import sysconfig
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


_BUILT = shutil.ignore_patterns(".git", ".venv", "build", "dist", "*.egg-info", "__pycache__",
                                ".*_cache")


def _not_source(folder: str, names: list[str]) -> set[str]:
    """What a copy of the clone leaves out: built files, and the runs at its top (not the
    package ``envs/runs``)."""
    return set(_BUILT(folder, names)) | ({"runs"} & set(names) if Path(folder) == ROOT else set())


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    # built from a copy, so setuptools' build/ and egg-info never land in the clone
    src = tmp_path_factory.mktemp("src") / "placeclust"
    shutil.copytree(ROOT, src, ignore=_not_source)
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps",
                    "--no-build-isolation", "--wheel-dir", str(out), str(src)], check=True)
    (path,) = out.glob("placeclust-*.whl")
    return path


def test_the_wheel_holds_two_packages_and_the_assets(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    tops = {n.split("/")[0] for n in names if not n.split("/")[0].endswith(".dist-info")}
    assert tops == {"placeclust", "placeclust_envs"}  # no top-level envs or train to shadow
    assert {"placeclust_envs/assets/robot.xml", "placeclust_envs/assets/room_styles.json",
            "placeclust_envs/assets/policies/errands/ppo_errands.zip",
            "placeclust/py.typed", "placeclust_envs/py.typed"} <= set(names)
    for sub in ("world", "tasks", "agents", "runs", "commands"):
        assert f"placeclust_envs/{sub}/__init__.py" in names
    # the docs' tooling is the repository's, not the library's
    assert not [n for n in names if "freshness" in n or n.startswith("docs/")]
    # the closed loop's errand policy is installed; training's maps and policies stay in the clone
    assert [n for n in names if "policies" in n] == [
        "placeclust_envs/assets/policies/errands/ppo_errands.zip"]
    entry = zipfile.ZipFile(wheel).read(next(n for n in names if n.endswith("entry_points.txt")))
    assert b"placeclust = placeclust_envs.commands.cli:main" in entry


def test_the_installed_wheel_works_outside_the_repository(wheel, tmp_path):
    env = tmp_path / "venv"
    venv.create(env, with_pip=True)
    python = env / "bin" / "python"
    # the dependencies come from this interpreter's site-packages (a plain path, so its
    # editable-install hooks stay off); placeclust itself only from the wheel
    purelib = subprocess.run([str(python), "-c", "import sysconfig; "
                              "print(sysconfig.get_paths()['purelib'])"],
                             check=True, capture_output=True, text=True).stdout.strip()
    Path(purelib, "deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-deps", str(wheel)],
                   check=True)
    work = tmp_path / "elsewhere"
    work.mkdir()

    def run(*args: str) -> str:
        return subprocess.run(args, cwd=work, check=True, capture_output=True, text=True).stdout

    code = ("import gymnasium as gym, placeclust, placeclust_envs\n"
            "env = gym.make('PlaceNav-v0', panorama_width=64, panorama_height=16)\n"
            "obs, info = env.reset(seed=0)\n"
            "print(obs['panorama'].shape, placeclust.__file__, placeclust_envs.__file__)")
    out = run(str(python), "-c", code)
    assert out.startswith("(16, 64, 3)")
    assert str(ROOT) not in out and str(env) in out  # the installed copy, not the clone
    placeclust = str(env / "bin" / "placeclust")
    run(placeclust, "tour", "--rooms", "2", "--steps", "30", "--width", "128", "--height", "32",
        "--out", "t", "--quiet")
    assert (work / "t" / "tour.npz").is_file() and (work / "t" / "floorplan.png").is_file()
    table = run(placeclust, "cluster", "--features", "orb", "--tour", "t/tour.npz", "--out", "c",
                "--quiet")
    assert "online/orb" in table and (work / "c" / "metrics.json").is_file()
    # the closed loop: a guided tour and errands in one building with the shipped learned
    # agent (its policy file is package data), on the true rooms (the recognizers' own
    # checks are placeclust's tests)
    scores = run(placeclust, "errands", "--scene-seeds", "0", "--rooms", "3",
                 "--recognizer", "oracle", "--agent", "ppo", "--errands", "1",
                 "--tour-steps-per-room", "40", "--json", "ppo.json")
    assert "success_rate=" in scores and (work / "ppo.json").is_file()
    # a leaderboard of a recognizer of the user's own, from a module in the folder they work
    # in, against the true rooms, and the paired comparison of the two
    shutil.copy(ROOT / "examples" / "tiny_recognizer.py", work / "mine.py")
    table = run(placeclust, "leaderboard", "--scene-seeds", "0", "1", "--rooms", "3",
                "--recognizers", "oracle", "mine:HaarPlaces", "--param", "threshold=0.8",
                "--errands", "1", "--tour-steps-per-room", "40", "--workers", "1",
                "--out", "board")
    assert "| oracle | 1.00 [1.00, 1.00] |" in table
    results = str(work / "board" / "results.json")
    mine = [row for row in json.loads(Path(results).read_text())["buildings"]
            if row["recognizer"] == "mine:HaarPlaces"]
    assert [row["recognizer_params"] for row in mine] == [{"threshold": 0.8}] * 2
    paired = run(placeclust, "compare", results, results, "--a", "mine:HaarPlaces",
                 "--b", "oracle")
    assert "| success_rate |" in paired and "Paired on 2 buildings" in paired


def test_the_oldest_versions_tested_are_the_floors_declared():
    """``make test-oldest`` installs tests/oldest.txt: each pin must be a dependency's floor."""
    import re

    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    floors = {}
    for dep in tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]:
        name, floor = re.fullmatch(r"([A-Za-z0-9_.-]+)>=([0-9.]+)", dep.split(";")[0]).groups()
        floors[name.lower()] = floor
    pins = dict(line.split("==") for line in (ROOT / "tests" / "oldest.txt").read_text().split()
                if "==" in line)
    assert set(pins) == set(floors)
    for name, pin in pins.items():
        assert pin.startswith(floors[name]), f"{name}: floor {floors[name]}, tested {pin}"
