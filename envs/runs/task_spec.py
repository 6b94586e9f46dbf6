"""One closed-loop run's errands as one typed value, from the command line to the env.

:class:`ErrandTask` says which task a building runs (``env_id``), how many errands follow the
tour (``n_errands``, the env's own name for it), the tour (its length, layout, doors, light)
and the errands (where they start, under which condition, whether the map learns, what the
goal is). ``placeclust errands`` and ``placeclust leaderboard`` build one from their options
(:func:`envs.commands.errands.task_from_args`), a suite builds one per track
(:meth:`envs.runs.suite.Suite.task`), and a job carries its :meth:`ErrandTask.kwargs`, the env's
keyword arguments, to :func:`~envs.runs.tour_errands.run_scene`, which builds it again. Every
value is checked once, here, with one line that names it.

Examples:
    >>> task = ErrandTask(n_errands=15, goal_kind="image", local_light=True)
    >>> task.images, task.kwargs()
    (True, {'n_errands': 15, 'local_light': True, 'goal_kind': 'image'})
    >>> ErrandTask.from_kwargs(task.kwargs()) == task
    True
    >>> task.tour_kwargs(), task.errand_kwargs()
    ({'local_light': True}, {'goal_kind': 'image'})
    >>> ErrandTask(goal_kind="door")
    Traceback (most recent call last):
    ...
    ValueError: goal_kind must be one of ('room', 'image'), got 'door'
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

#: the tasks a closed-loop run may name: room or image goals (v0's, by ``goal_kind``), and
#: placenav-v5's image goals (:mod:`envs.tasks.image_goal`)
ENV_IDS = ("PlaceNav-GuidedTour-v1", "PlaceNav-ImageGoal-v1")
#: the kinds of goal an errand can have (:data:`envs.tasks.errand_goals.GOAL_KINDS`)
GOAL_KINDS = ("room", "image")
#: the arguments that make a building's tour: tasks that agree on them share one tour
TOUR_KEYS = frozenset({"env_id", "tour_steps_per_room", "layout", "doors", "local_light",
                       "compass"})


@dataclass(frozen=True)
class ErrandTask:
    """The task one closed-loop run measures, beyond the building and the recognizer.

    Attributes:
        env_id: one of :data:`ENV_IDS`.
        n_errands: errands after the tour.
        tour_steps_per_room: the guided tour's length per room.
        layout, doors, local_light: the building (:mod:`envs.world.scene`).
        errand_start: ``"continue"`` from where the last errand ended, or ``"carried"``.
        errand_condition: the world during the errands (None: the tour's; ``"night"``...).
        errand_learn: whether the map keeps learning during the errands (False: it only
            localizes, ``--localize-only``).
        goal_kind: ``"room"`` (a named room) or ``"image"`` (a picture of a spot).
        success_radius: m; an image goal is reached by stopping within it.
        goal_offset, compass: ``PlaceNav-ImageGoal-v1``'s (None: its defaults).
    """

    env_id: str = "PlaceNav-GuidedTour-v1"
    n_errands: int = 5
    tour_steps_per_room: int = 150
    layout: str = "grid"
    doors: float | None = None
    local_light: bool = False
    errand_start: str = "continue"
    errand_condition: str | None = None
    errand_learn: bool = True
    goal_kind: str = "room"
    success_radius: float = 1.0
    goal_offset: float | None = None
    compass: str | None = None

    def __post_init__(self) -> None:
        checks = (
            (self.env_id in ENV_IDS, f"env_id must be one of {ENV_IDS}, got {self.env_id!r}"),
            (self.n_errands >= 1, f"n_errands must be positive, got {self.n_errands}"),
            (self.tour_steps_per_room >= 1, "tour_steps_per_room must be positive, got "
             f"{self.tour_steps_per_room}"),
            (self.doors is None or 0 <= self.doors <= 1,
             f"doors must be a fraction in [0, 1], got {self.doors}"),
            (self.goal_kind in GOAL_KINDS,
             f"goal_kind must be one of {GOAL_KINDS}, got {self.goal_kind!r}"),
            (self.success_radius > 0,
             f"success_radius must be positive metres, got {self.success_radius}"),
            (self.goal_offset is None or self.goal_offset >= 0,
             f"goal_offset must be 0 or more metres, got {self.goal_offset}"),
            (self.env_id != "PlaceNav-ImageGoal-v1" or self.goal_kind == "image",
             "PlaceNav-ImageGoal-v1's goals are pictures: goal_kind='image'"),
            (self.env_id == "PlaceNav-ImageGoal-v1"
             or (self.goal_offset is None and self.compass is None),
             "goal_offset and compass are PlaceNav-ImageGoal-v1's; name that env_id"),
        )
        for ok, message in checks:
            if not ok:
                raise ValueError(message)

    @property
    def images(self) -> bool:
        """Whether the errands' goals are pictures (the spot agents run them; the ceiling is
        ``oracle-pose``, which knows the picture's pose)."""
        return self.goal_kind == "image"

    def kwargs(self) -> dict[str, Any]:
        """The env's keyword arguments: ``n_errands`` and every other field not at its
        default, so a default task's job keeps its plain name (and its kept result)."""
        default = ErrandTask()
        return {k: v for k, v in asdict(self).items()
                if k == "n_errands" or v != getattr(default, k)}

    def tour_kwargs(self) -> dict[str, Any]:
        """:meth:`kwargs` that make the tour (:data:`TOUR_KEYS`)."""
        return {k: v for k, v in self.kwargs().items() if k in TOUR_KEYS}

    def errand_kwargs(self) -> dict[str, Any]:
        """:meth:`kwargs` that only the errands read (not ``n_errands``: a job's own field)."""
        return {k: v for k, v in self.kwargs().items()
                if k not in TOUR_KEYS and k != "n_errands"}

    @classmethod
    def from_kwargs(cls, kwargs: Mapping[str, Any]) -> ErrandTask:
        """The task of env keyword arguments (:meth:`kwargs`, a results file's ``task``).

        Raises:
            ValueError: an argument that is not one of the task's, or a bad value.
        """
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(kwargs) - names)
        if unknown:
            raise ValueError(f"unknown task arguments {unknown}; the task's are {sorted(names)}")
        return cls(**dict(kwargs))

    @classmethod
    def within(cls, kwargs: Mapping[str, Any]) -> ErrandTask:
        """The task among env keyword arguments that may hold others too (``errand_steps``,
        a camera's size: the env's, passed on as they are), its own checked."""
        names = {f.name for f in fields(cls)}
        return cls(**{k: v for k, v in kwargs.items() if k in names})

    def with_settings(self, settings: Mapping[str, Any], source: str) -> ErrandTask:
        """This task with ``settings`` (a track's), refusing one that contradicts what this
        task already set away from its default: ``source`` names who set it (``--track
        carried``)."""
        default = ErrandTask()
        for key, value in settings.items():
            mine = getattr(self, key)
            if mine != getattr(default, key) and mine != value:
                raise ValueError(f"{source} sets {key}={value!r}; leave out the option that "
                                 f"sets it to {mine!r}")
        return replace(self, **dict(settings))

    def far_text(self) -> str:
        """How far an errand's start is drawn from its goal, in words (a report's)."""
        if not self.images:
            return "at least 1 m of walking from their goal"
        return (f"at least {max(1.0, 2 * self.success_radius):g} m of walking from their "
                f"goal, a picture reached by stopping within {self.success_radius:g} m of it")
