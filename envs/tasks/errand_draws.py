"""Where the errands of ``PlaceNav-GuidedTour-v1`` go and where they start.

Each errand's goal is a room the guide named, other than the robot's. An errand starts where
the last one ended, at the door of the room just reached, so the room behind that door would be
an errand of one step across a threshold: a goal drawn closer than ``min_errand_distance`` of
walking is drawn again among the rooms far enough (its :class:`~envs.tasks.records.Errand` says
``redrawn``), as Habitat rejects episodes that start within the success distance; where no
named room is far enough the first draw stands. A carried errand starts at a random pose of a
random room other than the goal's, at least ``min_errand_distance`` of walking from it, as if
the robot were kidnapped. The draws come from the task's generator and the base env's, in a
fixed order, so one seed gives one sequence of errands.

Examples:
    >>> import numpy as np
    >>> from envs.tasks.goals import GoalRoom
    >>> from envs.world.layout import generate_floor_plan
    >>> plan = generate_floor_plan(3, np.random.default_rng(0))
    >>> names = [r.name for r in plan.rooms]
    >>> goal, redrawn = draw_goal(np.random.default_rng(0), GoalRoom(plan), names,
    ...                           (*plan.rooms[0].center, 0.0), 0, min_distance=1.0)
    >>> goal != plan.rooms[0].name
    True
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .goals import GoalRoom
from .place_nav import PlaceNavEnv

#: where an errand starts: where the last one ended, or carried to a random room
ERRAND_STARTS = ("continue", "carried")
#: draws of a carried start before one closer than ``min_errand_distance`` is accepted
CARRY_DRAWS = 20


def check_errands(n_errands: int, errand_steps: int, tour_steps_per_room: int, name_after: int,
                  min_errand_distance: float, errand_start: str, n_rooms: int) -> None:
    """A ``ValueError`` naming the first of the tour's and errands' arguments that is wrong."""
    if n_errands < 1 or errand_steps < 1 or tour_steps_per_room < 1 or name_after < 1:
        raise ValueError("n_errands, errand_steps, tour_steps_per_room and name_after must "
                         f"be positive, got {n_errands}, {errand_steps}, "
                         f"{tour_steps_per_room}, {name_after}")
    if not min_errand_distance >= 0:
        raise ValueError(f"min_errand_distance must be 0 or more metres, got "
                         f"{min_errand_distance}")
    if errand_start not in ERRAND_STARTS:
        raise ValueError(f"errand_start must be one of {ERRAND_STARTS}, got {errand_start!r}")
    if errand_start == "carried" and n_rooms < 2:
        raise ValueError("errand_start='carried' puts the robot down outside the goal room: "
                         f"it needs at least 2 rooms, got n_rooms={n_rooms}")


def draw_goal(rng: np.random.Generator, goal_room: GoalRoom, named: list[str],
              pose: Sequence[float], room: int, min_distance: float) -> tuple[str, bool]:
    """A named room other than ``room``; drawn again among those at least ``min_distance``
    of walking away if the first draw is closer. Returns (name, redrawn)."""
    plan = goal_room.plan
    here = plan.rooms[room].name
    others = [n for n in named if n != here] or named
    goal = others[int(rng.integers(len(others)))]
    far = [n for n in others if goal_room.walk(plan.room_by_name(n).id, pose,
                                               room) >= min_distance]
    if goal in far or not far:  # the first draw stands: the same goals as v0 where far
        return goal, False
    return far[int(rng.integers(len(far)))], True


def carry(nav: PlaceNavEnv, rng: np.random.Generator, goal_room: GoalRoom, goal: int,
          min_distance: float) -> tuple[dict[str, Any], dict[str, Any]]:
    """Put the robot down at a random pose (``nav``'s draw) of a random room (``rng``'s)
    other than ``goal``, at least ``min_distance`` of walking from it where one of
    :data:`CARRY_DRAWS` draws finds one; ``nav``'s observation and info there."""
    rooms = [r for r in goal_room.plan.rooms if r.id != goal]
    for _ in range(CARRY_DRAWS):
        room = rooms[int(rng.integers(len(rooms)))]
        obs, info = nav.reset(options={"room": room.name})
        if goal_room.walk(goal, info["pose"], room.id) >= min_distance:
            break
    return obs, info
