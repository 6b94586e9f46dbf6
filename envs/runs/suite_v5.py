"""``placenav-v5``'s definition and its map-fixed tracks, as data (:mod:`envs.runs.suite` builds
the :class:`~envs.runs.suite.Suite` and :class:`~envs.runs.suite.Track` objects from it).

v5 is v4's question, where a picture was taken, asked so that the verdict is the recognizer's
(``docs/design.md``, "`placenav-v5`"):

- every recognizer and agent gets the same goals, errand by errand: goal ``k`` of a building
  comes from its own random stream (the suite's seed, the building, ``k``), kept apart from
  where a perfect agent would stand (the previous goal), never from where this robot stopped
  (:class:`~envs.tasks.image_goal.SharedImageGoals`);
- the agent (``spot-memory``, :class:`~envs.agents.spot_memory.SpotMemoryPlanner`) remembers
  where it was during the errands too, so a place the map opened then has a spot, and it
  declares arrival only where it drove to one;
- a recognizer that can rank places answers every goal with its best-ranked place, below its
  threshold too; "unknown" is left to those that cannot rank;
- the compass is a gyro's heading, with the drift and noise of a stated part
  (:class:`envs.world.robot.GyroCompass`), and goal pictures are taken near the taught route,
  not on it;
- the changed tracks run twice, the map learning during the errands and fixed (``-fixed``):
  what a day map is worth by night.

Its sizes were chosen on ``val`` (``docs/design.md``); its full run is in ``docs/benchmarks.md``
("`placenav-v5` at full size", the job store in ``docs/runs/placenav-v5``). A published suite
is never edited: a change of rules is a new suite.

Examples:
    >>> V5["name"], V5["agent"], dict(V5["errands"])["env_id"]
    ('placenav-v5', 'spot-memory', 'PlaceNav-ImageGoal-v1')
    >>> [name for name, _, _ in V5_TRACKS]
    ['changed-night-fixed', 'changed-cloudy-fixed', 'changed-moved-fixed']
"""

from __future__ import annotations

from typing import Any

#: the map-fixed twins of the changed tracks: the COLD question, a day map by night
V5_TRACKS: tuple[tuple[str, dict[str, Any], str], ...] = tuple(
    (f"changed-{condition}-fixed",
     {"local_light": True, "errand_condition": condition, "errand_learn": False},
     f"errands {what} on the day map, fixed: the recognizer only localizes")
    for condition, what in (("night", "by night, lamps on and windows dark,"),
                            ("cloudy", "under cloud"),
                            ("moved", "after furniture moved and posters were swapped,")))

#: m: how far from the taught route a goal picture is taken, at most (uniform in the disc):
#: the farthest of 0.25, 0.5, 0.75 that kept the ceiling above 0.90 on every val track with a
#: margin (docs/design.md, "placenav-v5")
GOAL_OFFSET = 0.5

#: ``placenav-v5``: :class:`~envs.runs.suite.Suite`'s arguments
V5: dict[str, Any] = {
    "name": "placenav-v5", "env_id": "PlaceNav-ImageGoal-v1", "split": "test",
    "n_buildings": 10, "n_quick": 1, "n_long": 3, "n_rooms": 6, "n_errands": 15, "seed": 0,
    "tour_steps_per_room": 150, "long_tour_steps_per_room": 500, "agent": "spot-memory",
    "metrics": ("success_rate", "spl", "final_distance", "precision", "nmi", "places_per_room"),
    "tracks": (("continued", 10), ("changed-night", 10), ("changed-cloudy", 10),
               ("changed-moved", 10), ("carried", 10), ("corridor", 10),
               ("corridor-carried", 10), ("long", 3), ("changed-night-fixed", 10),
               ("changed-cloudy-fixed", 10), ("changed-moved-fixed", 10)),
    "errands": (("env_id", "PlaceNav-ImageGoal-v1"), ("goal_kind", "image"),
                ("success_radius", 1.0), ("goal_offset", GOAL_OFFSET),
                ("compass", "mpu9250")),
    # the quick check: every track but the long tours, 5 errands (one building of every
    # track with 15 took 16 minutes on 2 cores, PANORAMA's lit tour alone 11)
    "quick_tracks": ("continued", "changed-night", "changed-cloudy", "changed-moved", "carried",
                     "corridor", "corridor-carried", "changed-night-fixed",
                     "changed-cloudy-fixed", "changed-moved-fixed"),
    "quick_errands": 5,
}
