"""A tour planner that finds where it is again: its rangefinders matched to the tour's scans.

:class:`~envs.agents.teach_repeat.TourPlanner` dead-reckons from the tour's last step, so it is
lost once the robot is carried (the kidnapped robot), once a failed errand left it somewhere
else than it believes, or once its wheels slipped. :class:`RelocalizingPlanner` keeps a map of
the tour's scans: every rangefinder's endpoint on the tour, placed by the tour's dead-reckoned
path and compass (:class:`ScanMap`). At each step it asks two questions of its pose:

- does the scan fit the map there (the median distance of its endpoints from the tour's)?
- is the place the recognizer reports anywhere near (within ``FAR`` of the tour's path in
  that place)?

When either says no for ``PATIENCE`` steps in a row, or at the first step of an errand, it
searches the tour's steps *in the reported place* for the position whose scan fits best
(the compass fixes the orientation, so only the position is searched) and moves its belief
there if it fits clearly better, or, at an errand's start, if the reported place says so. A
move under ``JUMP`` only mends drift; a larger one is a new start, planned again from the
reported place. Mid-errand the reported place alone moves nothing: a recognizer aliasing for a
few frames must not throw the robot across the building. The recognizer's place decides
where to search: in identical offices along a corridor the scans fit every office alike, and
only the place id tells which one the robot is in. The agent still sees no pixels, so the
closed loop keeps scoring the recognizer.

Examples:
    >>> import gymnasium as gym
    >>> import envs
    >>> env = gym.make("PlaceNav-GuidedTour-v1", recognizer="oracle", n_rooms=3, n_errands=2,
    ...                tour_steps_per_room=60, errand_start="carried")
    >>> obs, info = env.reset(seed=0)
    >>> planner = RelocalizingPlanner(unknown=env.unwrapped.max_places)
    >>> planner.reset(info["tour"], obs)
    >>> done = False
    >>> while not done:
    ...     obs, reward, done, _, info = env.step(planner.act(obs))
    >>> [e["success"] for e in info["errands"]]
    [True, True]
    >>> env.close()
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from ..world.robot import MAX_RANGE, N_RANGES, RADIUS
from .teach_repeat import TourPlanner
from .topological import steer

#: m: a scan whose beams misfit by more than this on average (:meth:`ScanMap.residual`) does
#: not fit the map where the robot believes it is
RESIDUAL = 0.1
#: m: nor does one with a beam that hit within ``NEAR`` misfitting by more than ``NEAR_MISFIT``
NEAR, NEAR_MISFIT = 1.0, 0.3
#: m: how much better a searched position must fit to replace the belief
MARGIN = 0.01
#: m: a correction this small only mends the drift; a larger one is a new start (the robot
#: was carried or lost), and the route is planned again from the reported place
JUMP = 1.0
#: m: an endpoint farther than this from the tour's counts as this far
CLIP = 0.5
#: m: a reported place whose tour path is farther than this is not where the robot believes
FAR = 1.5
#: steps a doubt must last before the planner searches (one step of aliasing is not a carry)
PATIENCE = 3
#: m: the search grid's spacing
GRID = 0.2
#: m: a tour point this close to a beam that read nothing means the beam should have hit it
BLOCKED = 0.12
#: a search over more positions than this measures its beams ``PRUNE_BEAMS`` at a time and
#: drops the positions that cannot fit best (:meth:`ScanMap.best_fit`): the same answer, sooner
PRUNE, PRUNE_BEAMS = 100, 4
_BEAMS = 2 * math.pi * np.arange(N_RANGES) / N_RANGES
#: where along a beam that hit nothing the tour's points are looked for
_FREE = np.arange(0.5, MAX_RANGE - 0.3, 0.15)


def endpoints(position: np.ndarray, yaw: np.ndarray | float, ranges: np.ndarray) -> np.ndarray:
    """(..., N_RANGES, 2) world points the rangefinders hit from ``position`` (..., 2) at
    compass ``yaw``; beams that hit nothing (``MAX_RANGE``) give ``nan``."""
    angle = np.asarray(yaw)[..., None] + _BEAMS
    reach = np.where(ranges < MAX_RANGE - 1e-3, ranges + RADIUS, np.nan)
    offset = reach[..., None] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    return np.asarray(position)[..., None, :] + offset


class ScanMap:
    """The tour's scans as points in the tour's dead-reckoned frame, to match a scan against.

    Args:
        path: (T, 2) the tour's dead-reckoned positions.
        yaw: (T,) its compass headings (radians).
        ranges: (T, N_RANGES) its rangefinder readings.
    """

    def __init__(self, path: np.ndarray, yaw: np.ndarray, ranges: np.ndarray) -> None:
        self.ends = endpoints(path, yaw, ranges)  # (T, N_RANGES, 2)
        points = self.ends.reshape(-1, 2)
        self.tree = cKDTree(points[np.isfinite(points).all(axis=1)])
        self.path = path

    def residual(self, position: np.ndarray, yaw: float, ranges: np.ndarray) -> float:
        """How badly the scan fits the map at ``position`` (m): its beams' mean misfit
        (:meth:`misfits`), small where it fits. ``inf`` with no beam that hit anything."""
        return float(self.misfits(np.asarray(position, float)[None], yaw, ranges)[0].mean())

    def near_misfit(self, position: np.ndarray, yaw: float, ranges: np.ndarray) -> float:
        """The worst misfit (m) of the beams that hit something within ``NEAR`` of the robot:
        a wall the robot stands at, where the map has none, says it is not where it believes
        even where the far beams fit (a long room looks alike along its length)."""
        near = np.flatnonzero(ranges < NEAR)
        if near.size == 0:
            return 0.0
        misfit = self.misfits(np.asarray(position, float)[None], yaw, ranges)[0]
        return float(misfit[near].max())

    def locate(self, yaw: float, ranges: np.ndarray, steps: np.ndarray
               ) -> tuple[np.ndarray, float]:
        """The position where the scan fits best inside what the tour saw from ``steps`` (the
        box of their scans' endpoints: the robot may stand where the tour never drove), and
        its residual: a grid, refined around its best cell."""
        seen = np.concatenate([self.path[steps], self.ends[steps].reshape(-1, 2)])
        seen = seen[np.isfinite(seen).all(axis=1)]
        lo, hi = seen.min(axis=0), seen.max(axis=0)
        xs, ys = np.arange(lo[0], hi[0], GRID), np.arange(lo[1], hi[1], GRID)
        grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
        best = grid[self.best_fit(grid, yaw, ranges)[0]]
        fine = best + np.stack(np.meshgrid(*[np.linspace(-GRID, GRID, 9)] * 2),
                               axis=-1).reshape(-1, 2)
        k, fit = self.best_fit(fine, yaw, ranges)
        return fine[k], fit

    def best_fit(self, positions: np.ndarray, yaw: float, ranges: np.ndarray
                 ) -> tuple[int, float]:
        """The index and mean misfit of the one of ``positions`` where the scan fits best: the
        first minimum of ``misfits(positions, yaw, ranges).mean(axis=1)``, the same index and
        value, found without every position's every beam.

        Misfits are never negative, so the beams measured so far bound a position's mean from
        below: beams are measured a few at a time (those that hit first: a beam that hit
        nothing costs a query at every ``_FREE`` step), and a position whose bound already
        exceeds the best whole mean found is dropped. Those left are measured whole.
        """
        order = np.argsort(ranges >= MAX_RANGE - 1e-3, kind="stable")
        if len(positions) <= PRUNE or ranges.min() >= MAX_RANGE - 1e-3:
            fit = self.misfits(positions, yaw, ranges).mean(axis=1)
            k = int(np.argmin(fit))
            return k, float(fit[k])
        alive = np.arange(len(positions))
        partial = np.zeros(len(positions))
        best = math.inf
        for group in np.array_split(order, N_RANGES // PRUNE_BEAMS):
            partial[alive] += self.misfits(positions[alive], yaw, ranges, group).sum(axis=1)
            lead = alive[np.argmin(partial[alive])]
            best = min(best, float(self.misfits(positions[lead:lead + 1], yaw, ranges).mean()))
            # a margin for rounding: a sum taken in another order may differ in its last bits
            alive = alive[partial[alive] <= best * N_RANGES + 1e-9]
        fit = self.misfits(positions[alive], yaw, ranges).mean(axis=1)
        k = int(np.argmin(fit))
        return int(alive[k]), float(fit[k])

    def misfits(self, positions: np.ndarray, yaw: float, ranges: np.ndarray,
                beams: np.ndarray | None = None) -> np.ndarray:
        """(P, B) each beam's misfit (m) at each of ``positions`` (P, 2), for ``beams`` (indices;
        all ``N_RANGES`` by default): for a beam that hit, the distance of its endpoint from the
        tour's nearest, at most ``CLIP``; for one that hit nothing, ``CLIP`` where the tour saw
        something along it (a wall it should have hit), else 0. ``inf`` everywhere when no beam
        hit anything."""
        beams = np.arange(N_RANGES) if beams is None else np.asarray(beams)
        hits = endpoints(np.zeros(2), yaw, ranges)
        if not np.isfinite(hits).all(axis=1).any():
            return np.full((len(positions), len(beams)), math.inf)
        hits = hits[beams]
        hit = np.isfinite(hits).all(axis=1)
        out = np.zeros((len(positions), len(beams)))
        if hit.any():
            d, _ = self.tree.query((positions[:, None, :] + hits[hit][None]).reshape(-1, 2),
                                   distance_upper_bound=CLIP)
            out[:, hit] = np.minimum(d, CLIP).reshape(len(positions), -1)
        angle = yaw + _BEAMS[beams[~hit]]
        if angle.size:
            ray = np.stack([np.cos(angle), np.sin(angle)], axis=-1)  # (M, 2)
            along = positions[:, None, None, :] + _FREE[None, None, :, None] * ray[None, :, None]
            near, _ = self.tree.query(along.reshape(-1, 2), distance_upper_bound=BLOCKED)
            blocked = np.isfinite(near).reshape(len(positions), len(angle), -1).any(axis=2)
            out[:, ~hit] = CLIP * blocked
        return out


class RelocalizingPlanner(TourPlanner):
    """:class:`~envs.agents.teach_repeat.TourPlanner` that relocalizes on the tour's scans when
    its pose and what it senses disagree (the module's rules). Same arguments and calls."""

    def reset(self, tour, obs: dict[str, np.ndarray]) -> None:
        super().reset(tour, obs)
        self._doubt = 0
        self._errand = ""
        self.relocalized = 0  # searches that moved the belief, for diagnostics
        self.lost = False  # no position fits the scan: wander until one does
        self.scans: ScanMap | None = None
        self._place_trees: dict[int, cKDTree] = {}
        if tour.ranges is None:  # an old record: nothing to match, the plain planner
            return
        yaw = np.arctan2(tour.heading[:, 1], tour.heading[:, 0])
        self.scans = ScanMap(self.path, yaw, np.asarray(tour.ranges, float))
        self._place_trees = {p: cKDTree(self.path[self.places == p]) for p in self.graph.nodes}

    def act(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The planner's action, or a wander while no position fits the scan (the robot
        stands where the tour saw too little): moving, it finds a view the tour knows."""
        action = super().act(obs)
        if self.lost:
            return steer(obs["heading"], obs["ranges"], None, self.rng)
        return action

    def _check_pose(self, obs: dict[str, np.ndarray]) -> None:
        if self.scans is None:
            return
        ranges = np.asarray(obs["ranges"], float)
        place = int(obs["place_id"])
        known = place != self.unknown and place in self._place_trees
        new_errand = str(obs["goal"]) != self._errand
        self._errand = str(obs["goal"])
        beams = self.scans.misfits(self.pos[None], self.yaw, ranges)[0]  # once a step
        misfit = float(beams.mean())
        near = ranges < NEAR
        far = known and self._place_trees[place].query(self.pos)[0] > FAR
        doubt = (misfit > RESIDUAL or far
                 or (near.any() and float(beams[near].max()) > NEAR_MISFIT))
        self._doubt = self._doubt + 1 if doubt else 0
        if not doubt:
            self.lost = False
            return
        # searches are dear: a robot that is lost searches every few steps while it wanders
        if self._doubt < PATIENCE * (3 if self.lost else 1) and not new_errand:
            return
        self._doubt = 0
        steps = (np.flatnonzero(self.places == place) if known
                 else np.arange(len(self.path)))
        position, fit = self.scans.locate(self.yaw, ranges, steps)
        self.lost = fit > RESIDUAL
        # mid-errand, the reported place alone moves nothing: a recognizer aliasing for a few
        # frames would throw the robot across the building; the scan must prefer it too
        if self.lost or not (fit < misfit - MARGIN or (far and new_errand)):
            return
        moved = float(np.linalg.norm(position - self.pos))
        self.pos = position
        if moved < JUMP:  # drift corrected: the route and the places just left still hold
            return
        self.place = place if known else int(self.places[self._nearest_step(steps)])
        self._hop, self._controller = None, None
        self._passed.clear()
        self.relocalized += 1
