"""Frozen benchmark suites and tracks: which buildings, tours and errands a result is measured on.

A suite is named and versioned (``placenav-v1``) and never changes once published: a new
choice is a new version. Every results file records the suite it ran (or none), the package
version, the versions of the libraries that render and match, and a *render fingerprint*, a
hash of a few reference frames: Mesa, MuJoCo or a texture change that moves one pixel changes
it; and a *physics fingerprint*, a hash of one fixed drive: a MuJoCo version that moves the
robot otherwise changes it, though it may draw the same pixels. So a result from another
machine says whether it is comparable (:func:`provenance`, checked by ``placeclust compare``).

Examples:
    >>> from envs.runs.suite import SUITES
    >>> suite = SUITES["placenav-v1"]
    >>> suite.split, suite.n_rooms, suite.n_errands
    ('test', 6, 5)
    >>> suite.scene_seeds("quick") == list(range(2000, 2000 + suite.n_quick))
    True
    >>> v2 = SUITES["placenav-v2"]  # every track, each on its own buildings
    >>> v2.agent, len(v2.scene_seeds("full", "long")), v2.scene_seeds("quick", "carried")
    ('relocalizer', 4, [2000])
    >>> SUITES["placenav-v3"].task("full", "carried").goal_kind  # errands to pictures
    'image'
    >>> SUITES["placenav-v4"].n_errands  # v3 with three times the errands
    15
    >>> track_task("changed-night")
    {'local_light': True, 'errand_condition': 'night'}
    >>> track_task("carried", errand_learn=False)
    {'local_light': True, 'errand_start': 'carried', 'errand_learn': False}
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import inspect
import platform
from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from placeclust import __version__

from ..world.splits import SPLITS
from .suite_v5 import V5, V5_TRACKS
from .task_spec import ErrandTask

#: the sizes a suite runs at: ``full`` (what the docs report), ``quick`` (a check in minutes),
#: ``long`` (the long-tour track: fewer buildings, tours of ``long_tour_steps_per_room``)
SIZES = ("full", "quick", "long")


@dataclass(frozen=True)
class Suite:
    """A benchmark's definition: its buildings, tours, errands, seed and metrics.

    Attributes:
        name: ``<family>-v<N>``.
        env_id: the task every building runs.
        split: where its buildings come from (``test``: report only).
        n_buildings, n_quick, n_long: buildings of the full, quick and long-tour sizes (the
            first ones of ``split``).
        n_rooms: rooms per building.
        n_errands: errands per building after the tour.
        seed: the episode seed (the tour's route, the errands' goals).
        tour_steps_per_room, long_tour_steps_per_room: the tour's length per room.
        metrics: what its tables report, each a mean with its interval over buildings.
        agent: the errand agent it is run with unless told another (``--agent``).
        tracks: ``(track, buildings)`` pairs: the :data:`TRACKS` it runs, each on the first
            ``buildings`` of ``split`` at full size and ``n_quick`` at the quick size (``long``
            is then a track, not a size); none: one set of errands on ``n_buildings`` (v1).
        errands: ``(argument, value)`` pairs every track's errands add (v3: image goals,
            ``goal_kind`` and ``success_radius``); none: errands to named rooms.
        quick_tracks, quick_errands: what the quick size runs, where it is less than the full
            size's tracks and errands (v5: its quick check fits in 10 minutes); empty, 0: the
            same.
    """

    name: str
    env_id: str
    split: str
    n_buildings: int
    n_quick: int
    n_long: int
    n_rooms: int
    n_errands: int
    seed: int
    tour_steps_per_room: int
    long_tour_steps_per_room: int
    metrics: tuple[str, ...] = ("success_rate", "spl", "precision", "nmi", "places_per_room")
    agent: str = "planner"
    tracks: tuple[tuple[str, int], ...] = ()
    errands: tuple[tuple[str, Any], ...] = ()
    quick_tracks: tuple[str, ...] = ()
    quick_errands: int = 0

    @property
    def sizes(self) -> tuple[str, ...]:
        """The sizes it runs at: :data:`SIZES`, less ``long`` where that is a track."""
        return ("full", "quick") if self.tracks else SIZES

    @property
    def track_names(self) -> list[str]:
        """Its tracks, in order (empty for a suite of one set of errands)."""
        return [name for name, _ in self.tracks]

    def tracks_at(self, size: str = "full") -> list[str]:
        """The tracks it runs at ``size``: :attr:`track_names`, or the quick size's own."""
        return list(self.quick_tracks) if size == "quick" and self.quick_tracks else \
            self.track_names

    def scene_seeds(self, size: str = "full", track: str | None = None) -> list[int]:
        """The buildings of one of :attr:`sizes`: ``track``'s, or those of every track."""
        if size not in self.sizes:
            raise ValueError(f"unknown size {size!r} of {self.name}; choose one of {self.sizes}")
        if track is not None and track not in self.track_names:
            raise ValueError(f"{self.name} has no track {track!r}; its tracks: "
                             f"{self.track_names or 'none'}")
        if size == "quick":
            n = self.n_quick
        elif self.tracks:
            n = dict(self.tracks)[track] if track else max(dict(self.tracks).values())
        else:
            n = self.n_long if size == "long" else self.n_buildings
        return list(SPLITS[self.split][:n])

    def task(self, size: str = "full", track: str | None = None) -> ErrandTask:
        """What a building's errands are (:class:`~envs.runs.task_spec.ErrandTask`): the
        suite's errands and tour, and ``track``'s own (:func:`track_task`), which a suite of
        tracks needs."""
        if self.tracks:
            if track not in self.track_names:
                raise ValueError(f"{self.name} runs its tracks one by one: name one of "
                                 f"{self.track_names}")
            errands = self.quick_errands if size == "quick" and self.quick_errands else \
                self.n_errands
            return ErrandTask.from_kwargs({"n_errands": errands,
                                           "tour_steps_per_room": self.tour_steps_per_room,
                                           **track_task(track), **dict(self.errands)})
        steps = self.long_tour_steps_per_room if size == "long" else self.tour_steps_per_room
        return ErrandTask(n_errands=self.n_errands, tour_steps_per_room=steps)


# v2's tracks with errands to pictures of spots (PlaceNav-ImageGoal-v0, the spot agent):
# a map that knows the spot is worth more than one that knows the room. Success within
# 1 m, Habitat ImageNav's radius, chosen on the val pilot (docs/design.md, "placenav-v3")
_V3 = Suite(name="placenav-v3", env_id="PlaceNav-ImageGoal-v0", split="test",
            n_buildings=12, n_quick=1, n_long=4, n_rooms=6, n_errands=5, seed=0,
            tour_steps_per_room=150, long_tour_steps_per_room=500,
            agent="spot", metrics=("success_rate", "spl", "final_distance",
                                   "precision", "nmi", "places_per_room"),
            tracks=(("continued", 12), ("changed-night", 12), ("changed-cloudy", 12),
                    ("changed-moved", 12), ("carried", 12), ("corridor", 12),
                    ("corridor-carried", 12), ("long", 4)),
            errands=(("goal_kind", "image"), ("success_radius", 1.0)))

#: the published suites; never edit one, add the next version
SUITES: Mapping[str, Suite] = MappingProxyType({
    # sized by the pilot on val (docs/benchmarks.md, "How many buildings"): 60 buildings give
    # every recognizer piloted a half-width <= 0.05 on success and SPL and <= 0.01 on the tour
    # map's precision; 5 errands a building, as 10 let one lost robot fail a building's rest
    "placenav-v1": Suite(name="placenav-v1", env_id="PlaceNav-GuidedTour-v1", split="test",
                         n_buildings=60, n_quick=4, n_long=4, n_rooms=6, n_errands=5, seed=0,
                         tour_steps_per_room=150, long_tour_steps_per_room=500),
    # each track sized by its pilot on val within the 3 hours a full run may take on 2 cores
    # (docs/design.md, "placenav-v2"): 12 buildings give PANORAMA and PANORAMA_ORB a
    # success half-width near 0.05 on the lit tracks (11-19 needed) and resolve 5% aliasing
    # on every track calibrated (6 buildings did); long tours cost 3x, so 4 as in v1
    "placenav-v2": Suite(name="placenav-v2", env_id="PlaceNav-GuidedTour-v1", split="test",
                         n_buildings=12, n_quick=1, n_long=4, n_rooms=6, n_errands=5, seed=0,
                         tour_steps_per_room=150, long_tour_steps_per_room=500,
                         agent="relocalizer",
                         tracks=(("continued", 12), ("changed-night", 12),
                                 ("changed-cloudy", 12), ("changed-moved", 12),
                                 ("carried", 12), ("corridor", 12), ("corridor-carried", 12),
                                 ("long", 4))),
    "placenav-v3": _V3,
    # v3 with 15 errands a building: v3's five do not resolve one place a room on three tracks
    # (2 of 8), and errands are the lever, not buildings: on the val pilot (8 buildings,
    # 1000-1007) the buildings' true differences spread 0.00-0.09 against 0.63-0.70 for one
    # errand, and 15 give six of seven tracks a chance of 0.87 or more at 12 buildings
    # (docs/design.md, "Errands decide the resolution, not buildings"). A building's first
    # five errands are its v3 errands, goal for goal
    "placenav-v4": replace(_V3, name="placenav-v4", n_errands=15),
    # v4's question with the verdict the recognizer's: the same goals for all, no stop by
    # rule, a compass that drifts, goals off the route, the changed tracks on a fixed map too
    # (envs.runs.suite_v5)
    "placenav-v5": Suite(**V5),
})


def get_suite(name: str) -> Suite:
    """The suite called ``name``; a ``ValueError`` naming the suites there are."""
    if name not in SUITES:
        raise ValueError(f"unknown suite {name!r}; choose one of {sorted(SUITES)}")
    return SUITES[name]


# -- tracks ----------------------------------------------------------------------------------
#
# v1's errands run under the tour's own light and furniture, each from where the last ended, in
# rooms of random sizes: a recognizer that works and one that works better succeed alike there.
# Each track changes one of those, as Habitat's challenge tracks each stress one thing, so that
# what the recognizer's map is worth decides the errand (docs/design.md, "Tracks").

@dataclass(frozen=True)
class Track:
    """A named closed-loop track: the guided tour's arguments and what it tests.

    ``placeclust leaderboard --track NAME`` and ``placeclust errands --track NAME`` run one;
    ``placeclust score`` puts several tracks' results into one suite score
    (:mod:`envs.commands.compare`).

    | track | the errands | what it asks of the map |
    |---|---|---|
    | ``continued`` | from where the last one ended, as in v1 | to name the places on the way |
    | ``changed-night`` | under night light (the tour by day) | to serve after the light changed |
    | ``changed-cloudy`` | under cloudy light | the same, a milder change |
    | ``changed-moved`` | furniture moved and removed, posters swapped | to serve after moves |
    | ``carried`` | each from where the robot is put down | to say where it is from a look |
    | ``corridor`` | identical offices along a corridor | to tell apart what only a camera can |
    | ``corridor-carried`` | put down in one of the identical offices | to say which, from a look |
    | ``long`` | after a tour of 500 steps a room | to stay compact and right on a long tour |

    The first five run in buildings with windows and lamps (``local_light``,
    :mod:`envs.world.local_light`) and share one tour a building: by night the lamps light
    other places than the sun did, and the windows go dark. ``corridor`` and ``long`` keep
    v1's light: their tours are their own (``corridor-carried`` shares ``corridor``'s).

    Under a changed condition the map is the tour's; by default the recognizer keeps learning
    during the errands, as a deployed robot would; ``errand_learn=False``
    (``--localize-only``) fixes the map, and a recognizer without ``localize_one`` is then
    skipped, not scored zero.
    """

    name: str
    task: Mapping[str, Any]
    tests: str


#: the tracks that share a building's tour: windows and lamps, so that night is a real night
LIT = {"local_light": True}

TRACKS: Mapping[str, Track] = MappingProxyType({t.name: t for t in (
    Track("continued", LIT, "errands from where the last ended, in the tour's world"),
    Track("changed-night", {**LIT, "errand_condition": "night"},
          "errands by night, lamps on and windows dark, on a day map"),
    Track("changed-cloudy", {**LIT, "errand_condition": "cloudy"},
          "errands under cloud, no sun patches, on a day map"),
    Track("changed-moved", {**LIT, "errand_condition": "moved"},
          "errands after furniture moved and posters were swapped"),
    Track("carried", {**LIT, "errand_start": "carried"},
          "each errand from where the robot is put down"),
    Track("corridor", {"layout": "corridor"}, "identical offices along a corridor"),
    Track("corridor-carried", {"layout": "corridor", "errand_start": "carried"},
          "each errand from where the robot is put down among identical offices"),
    Track("long", {"tour_steps_per_room": 500}, "errands after a tour of 500 steps a room"),
    *(Track(name, task, tests) for name, task, tests in V5_TRACKS),
)})


def get_track(name: str) -> Track:
    """The track called ``name``; a ``ValueError`` naming the tracks there are."""
    if name not in TRACKS:
        raise ValueError(f"unknown track {name!r}; choose one of {list(TRACKS)}")
    return TRACKS[name]


def track_task(name: str, errand_learn: bool = True) -> dict[str, Any]:
    """The ``PlaceNav-GuidedTour-v1`` arguments of track ``name``; with ``errand_learn=False``
    the map is fixed during the errands (the default leaves the argument out: jobs of the
    default keep their plain names)."""
    task = dict(get_track(name).task)
    if not errand_learn:
        task["errand_learn"] = False
    return task


def library_versions() -> dict[str, str]:
    """The versions of placeclust, Python and the libraries that render, match and learn."""
    out = {"placeclust": __version__, "python": platform.python_version(),
           "machine": platform.machine()}
    for pkg in ("numpy", "opencv-contrib-python-headless", "scikit-learn", "scipy", "mujoco",
                "mahotas"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = ""
    return out


@functools.cache
def render_fingerprint() -> str:
    """A hash of reference frames: three panoramas and a forward view of one fixed building.

    Two machines with the same fingerprint render the benchmark's worlds pixel for pixel
    alike; results with different ones may differ for that reason alone.
    """
    from ..tasks.place_nav import PlaceNavEnv  # its package sets MUJOCO_GL first

    digest = hashlib.sha256()
    for camera, seeds in (("panorama", (0, 1, 2)), ("forward", (0,))):
        env = PlaceNavEnv(scene_seed=0, n_rooms=4, camera=camera)
        try:
            for seed in seeds:
                obs, _ = env.reset(seed=seed)
                digest.update(np.ascontiguousarray(obs[env.image_key]).tobytes())
        finally:
            env.close()
    return digest.hexdigest()[:16]


#: the fixed drive of :func:`physics_fingerprint`: control steps straight ahead, then turning
PHYSICS_DRIVE = (120, 80)


@functools.cache
def physics_fingerprint() -> str:
    """A hash of one fixed drive in one fixed building: the robot's state and rangefinders
    after each control step, as it drives straight into building 0's furniture and walls for
    :data:`PHYSICS_DRIVE` ``[0]`` steps, then turns at random for ``[1]``.

    Two machines with the same fingerprint simulate the benchmark's robot bit for bit alike.
    The render fingerprint cannot tell: MuJoCo 3.17 and 4.0 draw the same pixels, but the same
    drive ends 3 cm and 0.10 rad apart, and the same errands end otherwise
    (``tests/envs/world/physics_reference.json`` holds it for the versions it was driven with).
    """
    import mujoco

    from ..tasks.place_nav import PlaceNavEnv  # its package sets MUJOCO_GL first

    ahead, turning = PHYSICS_DRIVE
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, size=(ahead + turning, 2))
    actions[:ahead] = (1.0, 0.0)
    env = PlaceNavEnv(scene_seed=0, n_rooms=4)
    try:
        env.reset(seed=0)
        digest = hashlib.sha256()
        for action in actions.astype(np.float32):
            env.robot.command(env.data, action)
            mujoco.mj_step(env.model, env.data, nstep=env.n_substeps)
            for values in (env.data.qpos, env.data.qvel, env.data.sensordata):
                digest.update(np.ascontiguousarray(values).tobytes())
    finally:
        env.close()
    return digest.hexdigest()[:16]


#: the CPU flags recorded beside a render fingerprint: two machines alike in Mesa, LLVM and
#: MuJoCo drew different pixels of the same building at the same commit, so what the GL
#: strings leave out, the likeliest (the CPU that runs llvmpipe, MuJoCo and the texture
#: maths) is recorded; the cause is not pinned down
CPU_FLAGS = ("sse4_2", "avx", "avx2", "fma", "avx512f", "avx512vl", "avx512bw")


def cpu_info() -> str:
    """The CPU's model name and which of :data:`CPU_FLAGS` it has (``/proc/cpuinfo``), or
    :func:`platform.processor` where that file is absent.

    >>> isinstance(cpu_info(), str)
    True
    """
    cpuinfo = Path("/proc/cpuinfo")
    if not cpuinfo.is_file():
        return platform.processor() or platform.machine()
    fields: dict[str, str] = {}
    for line in cpuinfo.read_text().splitlines():  # the first CPU's lines hold for all
        key, _, value = line.partition(":")
        fields.setdefault(key.strip(), value.strip())
    flags = set(fields.get("flags", "").split())
    return f"{fields.get('model name', '')}; " + " ".join(f for f in CPU_FLAGS if f in flags)


def renderer_info() -> dict[str, str]:
    """What draws the pixels here: OpenGL's version and renderer strings (Mesa's version and
    llvmpipe on a CPU machine), MuJoCo's version and the CPU (:func:`cpu_info`). A stored
    render fingerprint holds for these (``tests/envs/world/render_reference.json``)."""
    import mujoco
    from OpenGL import GL

    from ..tasks import place_nav  # noqa: F401  (its package sets MUJOCO_GL first)

    context = mujoco.GLContext(16, 16)
    try:
        context.make_current()
        return {"gl_version": GL.glGetString(GL.GL_VERSION).decode(),
                "gl_renderer": GL.glGetString(GL.GL_RENDERER).decode(),
                "mujoco": mujoco.__version__, "cpu": cpu_info()}
    finally:
        context.free()


#: the code every benchmark result comes from: the library and the simulator's world, tasks
#: and agents (relative to this package: ``envs``, or ``placeclust_envs`` in a wheel)
CODE_PACKAGES = ("placeclust", "..world", "..tasks", "..agents")


@functools.cache
def code_fingerprint() -> str:
    """A hash of the source of :data:`CODE_PACKAGES`, every file in a fixed order: an edit
    anywhere a result could come from changes it, within one version of placeclust too."""
    digest = hashlib.sha256()
    for package in CODE_PACKAGES:
        root = Path(inspect.getfile(importlib.import_module(package, __package__))).parent
        for path in sorted(root.glob("*.py")):
            digest.update(f"{package}/{path.name}".encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def sources_fingerprint(*sources: str | Path) -> str:
    """:func:`code_fingerprint` extended by the source files a result also depends on (the
    command's own module, a user's recognizer module, a policy file), in the order given."""
    digest = hashlib.sha256(code_fingerprint().encode())
    for source in sources:
        digest.update(Path(source).read_bytes())
    return digest.hexdigest()[:16]


def provenance(suite: Suite | None, size: str = "full", named_buildings: bool = False
               ) -> dict[str, Any]:
    """What a results file records so another can be told comparable or not: the suite (its
    definition too) and size, or none, whose ``buildings`` they are (``"named"``: the
    suite's settings on buildings a command named, so not the suite's figures), the library
    versions, and the render and physics fingerprints."""
    return {"suite": None if suite is None else suite.name, "size": size if suite else None,
            "buildings": None if suite is None else ("named" if named_buildings else "suite"),
            "definition": None if suite is None else asdict(suite),
            "versions": library_versions(), "render_fingerprint": render_fingerprint(),
            "physics_fingerprint": physics_fingerprint()}
