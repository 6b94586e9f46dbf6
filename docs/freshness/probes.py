"""Tiny runs of the commands that write ``docs/benchmarks.md``, traced for
:mod:`docs.freshness`.

A section's *probe* is its own command line at a tiny size: the same subcommand, recognizers,
features, conditions, doors and parameters, on one building of two rooms with a few frames (two
for the closed loop, whose intervals need two; the options that set the size are replaced,
``--docs`` and ``--out`` dropped), run in a process of its own under a tracer that sees which
functions of the repository produce that section's figures (:func:`traced`). A command
that reads results (``compare``, ``score``, ``train.report``, ``stats``) first runs the probe
of the section that wrote them (the one whose ``--out`` holds them), or, for inputs no section
writes, a stand-in: a tiny closed-loop run (with any recognizer the command names that the
stand-in lacks, :func:`named`), or tiny tours.

Commands are found by name (the ``placeclust`` console script, ``python -m train.X``): this
library imports nothing of the simulator.

Examples:
    >>> probe_argv("placeclust demo --out runs/demo --docs docs/benchmarks.md".split())
    ['placeclust', 'demo', '--rooms', '2', '--steps', '60']
"""

from __future__ import annotations

import builtins
import hashlib
import inspect
import io
import json
import os
import runpy
import shlex
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
#: the packages whose functions are traced (a user's recognizer in ``examples`` too)
TRACED = ("placeclust", "envs", "train", "examples")
_SKIP_FILES = ("docs/", "runs/", ".git/", ".venv")

#: options that only say where a result goes, or how many processes compute it
_DROP = {"--docs", "--section", "--out", "--json", "--executor", "--ray-address", "--workers",
         "--quiet"}
#: options naming a file the command writes beside its section (``score --calibration``'s
#: figure): a probe writes it beside its own ``out`` instead, never over the docs' figure
_WRITES = {"--calibration"}
#: options that set a run's size, replaced by each subcommand's tiny values
_SIZE = {"--scenes", "--scene-seeds", "--n-scenes", "--split", "--rooms", "--tour-seeds",
         "--steps-per-room", "--steps", "--goals-per-scene", "--tour-steps-per-room",
         "--suite", "--sizes", "--repeats", "--rounds", "--errands",
         "--latency-sizes"}
# a probe runs with a section's recorded code too: the leaderboard's errand count keeps the
# spelling every version reads (--goals-per-scene, --errands since 0.19.0)
_TINY = {
    "demo": "--rooms 2 --steps 60",
    "tour": "--rooms 2 --steps 40",
    "bench": "--scenes 0 --rooms 2 --tour-seeds 0 --steps-per-room 15 --latency-sizes "
             "--workers 1 --quiet",
    "seed001": "--split val --n-scenes 1 --rooms 2 --steps-per-room 20",
    "latency": "--sizes 4 8 --repeats 1",
    "speed": "--steps 10 --rounds 1 --workers 1",
    "like": "--scenes 1000 --rooms 2 --steps-per-room 10",
    "leaderboard": "--split val --n-scenes 2 --rooms 2 --goals-per-scene 1 "
                   "--tour-steps-per-room 25 --workers 1",
    "train.drift": "--n-scenes 1 --rooms 2 --errands 1",
}
#: the stand-ins for closed-loop results no section writes: two val buildings, with the tracks
#: the files' folders name (``STAND_IN`` is followed by them; a calibration recognizer among
#: them for ``score --calibration``) or without tracks
STAND_IN = ("placeclust leaderboard --recognizers oracle none panorama panorama-orb "
            "oracle-noise:0.05 --agent relocalizer --track")
#: three rooms and errands a building, so that ``none`` falls below ``oracle`` on every track and
#: ``placeclust score`` can normalize between them
STAND_IN_SIZE = ("--split val --n-scenes 2 --rooms 3 --goals-per-scene 3 "
                 "--tour-steps-per-room 25 --workers 1")
STAND_IN_PLAIN = "placeclust leaderboard --recognizers oracle none panorama panorama-orb"
#: the options by which a reading command names recognizers (``compare --a``, ``score --pair``):
#: one the stand-in lacks, a user's ``module:Class``, joins it with its constructor's defaults
NAMING = ("--a", "--b", "--pair", "--floor", "--ceiling")
#: the closed loop's tracks (``envs.runs.suite.TRACKS``, which this library cannot import;
#: a test keeps the two alike)
TRACK_NAMES = ("continued", "changed-night", "changed-cloudy", "changed-moved", "carried",
               "corridor", "corridor-carried", "long", "changed-night-fixed",
               "changed-cloudy-fixed", "changed-moved-fixed")
#: the tracks before placenav-v5 added the changed ones on a fixed map
_V2_TRACKS = TRACK_NAMES[:8]
#: what a suite fixes beyond its buildings and size (``envs.runs.suite.SUITES``; a test
#: keeps the two alike): its agent and its tracks, less ``long``, the same code as the others
#: after a longer tour (which traced would take minutes)
SUITE_OPTIONS = {"placenav-v1": "--agent planner",
                 "placenav-v2": "--agent relocalizer --track " + " ".join(
                     t for t in _V2_TRACKS if t != "long"),
                 "placenav-v3": "--agent spot --goal-kind image --track " + " ".join(
                     t for t in _V2_TRACKS if t != "long")}
SUITE_OPTIONS["placenav-v4"] = SUITE_OPTIONS["placenav-v3"]  # v3 with more errands
# v5's agent and tracks; its task (PlaceNav-ImageGoal-v1, the gyro, goals off the route) reaches
# a probe only once the leaderboard runs a suite's protocol on other buildings (issue 88)
SUITE_OPTIONS["placenav-v5"] = "--agent spot-memory --goal-kind image --track " + " ".join(
    t for t in TRACK_NAMES if t != "long")
#: options that take no value (``--latency-sizes`` may take none, and is replaced anyway)
_FLAGS = {"--quick", "--quiet", "--localize-only", "--force", "--alone"}


def _options(argv: list[str]) -> list[tuple[str | None, list[str]]]:
    """``argv`` as (option, values) pairs; positional arguments under None."""
    out: list[tuple[str | None, list[str]]] = []
    for token in argv:
        if token.startswith("--"):
            out.append((token.split("=", 1)[0],
                        token.split("=", 1)[1:] if "=" in token else []))
        elif out and out[-1][0] is not None and out[-1][0] not in _FLAGS:
            out[-1][1].append(token)
        else:
            out.append((None, [token]))
    return out


def subcommand(argv: list[str]) -> str:
    """``bench`` for ``placeclust bench ...``, ``train.report`` for ``python -m train.report``."""
    return argv[2] if argv[:2] == ["python", "-m"] else argv[1]


def probe_argv(argv: list[str], out: str | None = None, size: str | None = None) -> list[str]:
    """A section's command line at its tiny size (``size``: other options than the
    subcommand's tiny ones), writing under ``out`` (None: nowhere); a file it writes besides
    (:data:`_WRITES`) goes to ``OUT-NAME``, beside ``out``, so a probe leaves ``docs/`` alone."""
    name = subcommand(argv)
    head = argv[:3] if name.startswith("train.") else argv[:2]
    options = _options(argv[len(head):])
    kept = [(o, v) for o, v in options if o not in _DROP and o not in _SIZE
            and not (name == "leaderboard" and o == "--size")  # a suite's size, dropped
            and not (o in _WRITES and out is None)]
    kept = [(o, [f"{out}-{Path(v[0]).name}"] if o in _WRITES and v else v) for o, v in kept]
    suite = next((v[0] for o, v in options if o == "--suite" and v), None)
    fixed = _options(shlex.split(SUITE_OPTIONS.get(suite or "", "")))
    given = {o for o, _ in kept}
    kept = [(o, v) for o, v in fixed if o not in given] + kept  # the section's own win
    tokens = [t for o, v in kept for t in ([o] if o else []) + v]
    tiny = shlex.split(_TINY.get(name, "") if size is None else size)
    # commands that keep and resume runs write into the probe's own folder: a kept run in the
    # default one would be reused, and the trace would miss the code that made it
    if out is not None and name in ("bench", "leaderboard", "demo", "tour", "like"):
        tiny += ["--out", out]
    return head + tokens + tiny


def out_dir(argv: list[str]) -> str | None:
    """Where a command writes (its ``--out``), or None."""
    return next((v[0] for o, v in _options(argv) if o == "--out" and v), None)


def run(argv: list[str]) -> None:
    """Run a command line in this process (``placeclust ...`` or ``python -m train.X ...``).

    Raises:
        RuntimeError: it exited with a non-zero status.
    """
    saved = sys.argv
    try:
        if argv[:2] == ["python", "-m"]:
            sys.argv = argv[2:]
            runpy.run_module(argv[2], run_name="__main__", alter_sys=True)
        else:
            (script,) = entry_points(group="console_scripts", name=argv[0])
            script.load()(argv[1:])
    except SystemExit as e:
        if e.code not in (0, None):
            raise RuntimeError(f"{shlex.join(argv)} exited with {e.code}") from None
    finally:
        sys.argv = saved


def inputs(argv: list[str], produced: dict[str, str]) -> list[tuple[str, str | None]]:
    """The files under ``runs/`` that a command reads, each with the output folder of the
    section that writes it (``produced``: ``{out folder: section}``), or None."""
    found = []
    for token in (t for o, v in _options(argv) if o not in _DROP for t in v):
        for path in token.split("=", 1)[-1].split(","):
            path = path.split("@", 1)[0]
            if path.startswith("runs/"):  # a file under a run's folder, or the folder
                owner = next((d for d in produced if path == d.rstrip("/")
                              or path.startswith(d.rstrip("/") + "/")), None)
                found.append((path, owner))
    return found


def _tour_name(path: str) -> str:
    return ("panorama" if "panorama" in path else "forward") + ("-doors" if "doors" in path
                                                                else "")


def _track(path: str) -> str | None:
    parts = Path(path).parts
    return parts[-2] if len(parts) > 2 and parts[-2] in TRACK_NAMES else None


def named(argv: list[str]) -> tuple[str, ...]:
    """The recognizers a reading command names that the stand-ins do not run (a user's
    ``module:Class``, a calibration recognizer), in order: the stand-in runs them too."""
    known = {r for c in (STAND_IN, STAND_IN_PLAIN)
             for r in _recognizers(shlex.split(c))[1]}
    names = [n for o, v in _options(argv) if o in NAMING for n in v]
    return tuple(dict.fromkeys(n for n in names if n not in known))


def _folder(scratch: Path, base: str, extra: tuple[str, ...]) -> Path:
    # stand-ins with other recognizers each get a folder of their own: a cached trace skips
    # its run, so a shared folder could hold another stand-in's files
    tag = hashlib.sha256(" ".join(extra).encode()).hexdigest()[:8]
    return scratch / (f"{base}-{tag}" if extra else base)


def stand_in(path: str, scratch: Path, extra: tuple[str, ...] = ()) -> str:
    """Where the stand-in run holds a file like ``path``: a track's results if the folder
    above it names a track, else a run's without tracks; or a tiny tour for a ``tour.npz`` (a
    panorama one if its path says so, with doors if it says so). ``extra``: the recognizers
    it runs beside its own (:func:`named`)."""
    if path.endswith("tour.npz"):
        return str(scratch / f"tour-{_tour_name(path)}" / "tour.npz")
    track = _track(path)
    return str(_folder(scratch, "stand-in", extra) / track / "results.json" if track
               else _folder(scratch, "stand-in-plain", extra) / "results.json")


def _recognizers(argv: list[str]) -> tuple[int, list[str]]:
    """Where a stand-in's ``--recognizers`` list ends in ``argv``, and the list."""
    start = end = argv.index("--recognizers") + 1
    while end < len(argv) and not argv[end].startswith("--"):
        end += 1
    return end, argv[start:end]


def _with(command: str, extra: tuple[str, ...]) -> list[str]:
    """``command`` (a stand-in's) with ``extra`` after its own recognizers."""
    argv = shlex.split(command)
    end, _ = _recognizers(argv)
    return argv[:end] + list(extra) + argv[end:]


def stand_in_commands(paths: list[str], scratch: Path, extra: tuple[str, ...] = ()
                      ) -> list[list[str]]:
    """The runs that make the stand-ins of ``paths``, with recognizers ``extra`` beside
    their own."""
    runs = []
    results = [p for p in paths if not p.endswith("tour.npz")]
    tracks = sorted({t for t in map(_track, results) if t}, key=TRACK_NAMES.index)
    tracked = _folder(scratch, "stand-in", extra)
    if "long" in tracks:
        # the long track is the plain errands after a longer tour: the same code at a tiny
        # tour (its own 500 steps a room, traced, would take minutes)
        tracks.remove("long")
        runs.append(probe_argv(_with(STAND_IN_PLAIN, extra) + ["--agent", "relocalizer"],
                               str(tracked / "long"), STAND_IN_SIZE))
    if tracks:
        # the leaderboard writes one track's results into --out itself, several into a folder
        # each: a lone track runs into its own folder, where stand_in() looks for it
        out = tracked / tracks[0] if len(tracks) == 1 else tracked
        runs.append(probe_argv(_with(STAND_IN, extra) + tracks, str(out), STAND_IN_SIZE))
    if any(not _track(p) for p in results):
        runs.append(probe_argv(_with(STAND_IN_PLAIN, extra),
                               str(_folder(scratch, "stand-in-plain", extra))))
    for name in sorted({_tour_name(p) for p in paths if p.endswith("tour.npz")}):
        tour = ("placeclust tour --camera " + name.split("-")[0]
                + (" --doors 1.0" if name.endswith("doors") else ""))
        runs.append(probe_argv(shlex.split(tour), str(scratch / f"tour-{name}")))
    return runs


def substitute(argv: list[str], swap: dict[str, str]) -> list[str]:
    """``argv`` with each input path replaced by its tiny counterpart."""
    out = []
    for token in argv:
        head, _, spec = token.rpartition("=") if "=" in token and not token.startswith("--") \
            else ("", "", token)
        files = []
        for item in spec.split(","):
            path, at, recognizer = item.partition("@")
            new = swap.get(path) or next((path.replace(d, t, 1) for d, t in swap.items()
                                          if path.startswith(d.rstrip("/") + "/")), path)
            if head and new != path and new.endswith("results.json") and not at:
                at, recognizer = "@", "oracle"  # an agent's errands: the stand-in's oracle
            files.append(new + at + recognizer)
        out.append((head + "=" if head else "") + ",".join(files))
    return out


# -- tracing -------------------------------------------------------------------------------

@contextmanager
def traced() -> Iterator[dict[str, Any]]:
    """Record the repository's functions that run, and the repository files opened, in this
    process while the block runs: ``{"functions": {path: set(qualname)}, "files": set(path)}``.
    """
    roots = tuple(str(ROOT / p) + os.sep for p in TRACED)
    own = str(Path(__file__).resolve().parent) + os.sep  # this package: the tool itself
    calls: set[tuple[str, str]] = set()
    files: set[str] = set()

    def tracer(frame: Any, event: str, arg: Any) -> None:
        code = frame.f_code
        if code.co_filename.startswith(roots) and not code.co_filename.startswith(own):
            # a module's or a class's body runs as code that is not a function's: its module's
            # skeleton covers it
            function = code.co_flags & inspect.CO_NEWLOCALS
            calls.add((code.co_filename, getattr(code, "co_qualname", code.co_name)
                       if function else "<module>"))

    real_open, real_io_open = builtins.open, io.open

    def opening(file: Any, *args: Any, **kwargs: Any) -> Any:
        if isinstance(file, str | os.PathLike):
            path = Path(file).resolve()
            if path.is_relative_to(ROOT) and path.is_file():
                rel = path.relative_to(ROOT).as_posix()
                if not rel.startswith(_SKIP_FILES) and not rel.endswith(".py"):
                    files.add(rel)
        return real_open(file, *args, **kwargs)

    result: dict[str, Any] = {"functions": {}, "files": set()}
    sys.settrace(tracer)
    threading.settrace(tracer)
    builtins.open = io.open = opening
    try:
        yield result
    finally:
        sys.settrace(None)
        threading.settrace(None)  # type: ignore[arg-type,unused-ignore]
        builtins.open, io.open = real_open, real_io_open
        for filename, qualname in calls:
            if "<" in qualname.rsplit(".", 1)[-1]:  # module, class body, lambda, comprehension:
                qualname = "<module>"  # their module's skeleton or their function covers them
            path = Path(filename).resolve().relative_to(ROOT).as_posix()
            names = result["functions"].setdefault(path, set())
            if qualname != "<module>":
                names.add(qualname.split(".<locals>.<")[0] if "<locals>.<" in qualname
                          else qualname)
        result["files"] = files


def as_json(trace: dict[str, Any]) -> dict[str, Any]:
    return {"functions": {p: sorted(n) for p, n in sorted(trace["functions"].items())},
            "files": sorted(trace["files"])}


def trace_command(argv: list[str], scratch: Path, read_by_none: bool = False
                  ) -> dict[str, Any]:
    """Trace one command line in a fresh process (so imports and caches start cold), or reuse
    its trace from ``scratch``. A run whose output nothing reads (``read_by_none``: a section's
    own, the last of :func:`probe_runs`) shares the trace of the same run written elsewhere, as
    sections with one command line do (the eight of a suite of tracks)."""
    scratch.mkdir(parents=True, exist_ok=True)
    key = [t for t, o in zip(argv, ["", *argv]) if not read_by_none or "--out" not in (t, o)]
    target = scratch / f"trace-{hashlib.sha256(' '.join(key).encode()).hexdigest()[:12]}.json"
    if not target.exists():
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(
            [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
        done = subprocess.run([sys.executable, "-m", "docs.freshness", "_trace",
                               str(target), "--", *argv], cwd=ROOT, env=env,
                              capture_output=True, text=True)
        if done.returncode != 0:
            last = (done.stderr.strip().splitlines() or ["no message"])[-1]
            raise RuntimeError(f"the tiny run `{shlex.join(argv)}` failed: {last}")
    return json.loads(target.read_text())


def union(traces: list[dict[str, Any]]) -> dict[str, Any]:
    functions: dict[str, set[str]] = {}
    for t in traces:
        for path, names in t["functions"].items():
            functions.setdefault(path, set()).update(names)
    return as_json({"functions": functions, "files": {f for t in traces for f in t["files"]}})


def probe_runs(name: str, commands: dict[str, list[str]], scratch: Path) -> list[list[str]]:
    """The tiny command lines whose traces make up section ``name``'s (``commands``: every
    section's command line): the runs that make its inputs, then its own."""
    produced = {d: n for n, c in commands.items() if (d := out_dir(c))}
    argv = commands[name]
    runs, swap = [], {}
    found = inputs(argv, produced)
    # a suite's tiny run leaves the long track out (SUITE_OPTIONS): its file gets a stand-in
    alone = [p for p, o in found if o is None or (_track(p) == "long" and "--suite" in
                                                  commands[produced[o]])]
    for owner in sorted({o for p, o in found if o and p not in alone}):
        folder = str(scratch / produced[owner])
        runs.append(probe_argv(commands[produced[owner]], folder))
        swap[owner] = folder
    extra = named(argv)
    runs += stand_in_commands(alone, scratch, extra)
    swap.update({p: stand_in(p, scratch, extra) for p in alone})
    runs.append(probe_argv(substitute(argv, swap), str(scratch / name)))
    return runs


def trace_main(argv: list[str]) -> int:
    """``python -m docs.freshness _trace OUT -- COMMAND...``: run one command traced,
    write what it ran to OUT (a JSON file); :func:`trace_command` calls it in a process of its
    own."""
    if len(argv) < 3 or argv[1] != "--":
        print("usage: python -m docs.freshness _trace OUT -- COMMAND ...", file=sys.stderr)
        return 2
    try:
        with traced() as found:
            run(argv[2:])
    except RuntimeError:  # the command has said why on stderr: its last line is the reason
        return 2
    Path(argv[0]).write_text(json.dumps(as_json(found)))
    return 0
