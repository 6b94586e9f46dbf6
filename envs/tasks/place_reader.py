"""The place of every frame a guided tour and its errands see, whoever answers it.

:class:`PlaceReader` is ``PlaceNav-GuidedTour-v1``'s one seam for places: a recognizer that
learns from the frames (through :class:`~envs.tasks.place_id.PlaceIdWrapper`), or the true
rooms of ``oracle`` and its calibration family (:mod:`envs.tasks.oracles`), which read the
ground truth instead. Either way the task asks it the same questions: step the world the robot
is in now, take in a frame seen without a step, tell it the robot was carried, read the place,
keep and restore what it has learnt. It also owns the two worlds: the tour's, and the errands'
(the same building under ``errand_condition``), and says which one the robot is in.

Examples:
    >>> reader = PlaceReader("oracle", n_rooms=3)
    >>> reader.truth is not None and reader.recognizer is None, reader.place
    (True, -1)
    >>> reader.close()
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

import gymnasium as gym

from placeclust.protocol import reads_images

from ..world.conditions import CONDITION_KEYS, CONDITIONS
from ..world.layout import FloorPlan
from .oracles import BoundTrueRooms, TrueRooms
from .place_id import PlaceIdWrapper, Recognizer
from .place_nav import NavSnapshot, PlaceNavEnv
from .recognizers import RecognizerName, parse_recognizer


class PlaceReader:
    """Which place each frame gets, on the world the robot is in (the tour's or the errands').

    Args:
        recognizer: a closed-loop name (:func:`~envs.tasks.recognizers.parse_recognizer`:
            a built-in, a calibration oracle, ``package.module:Class``) or a recognizer object.
        n_rooms, max_places: the building's rooms; the place ids a recognizer may open.
        recognizer_params: a ``package.module:Class``'s constructor arguments.
        errand_condition: the errands' condition (None: the tour's world serves them too).
        errand_learn: whether the map keeps learning in the errands' world; False needs a
            recognizer with ``localize_one`` (a ``ValueError`` here, before any tour).
        observe_image: render the camera even for a recognizer that reads no images.
        render_mode, **world: ``PlaceNav-v0``'s; the camera defaults to the one the
            recognizer reads (the forward one for ``nested``).
    """

    def __init__(self, recognizer: str | Recognizer, n_rooms: int, max_places: int = 64,
                 recognizer_params: Mapping[str, Any] | None = None,
                 errand_condition: str | None = None, errand_learn: bool = True,
                 observe_image: bool = False, render_mode: str | None = None,
                 **world: Any) -> None:
        if recognizer_params and not isinstance(recognizer, str):
            raise ValueError("recognizer_params go with a package.module:Class recognizer, "
                             "not with a recognizer object")
        parsed: RecognizerName | None = None
        built: Recognizer | TrueRooms
        if isinstance(recognizer, str):  # one parse: what it builds and the camera it reads
            parsed = parse_recognizer(recognizer)
            built = parsed.build(n_rooms, max_places, recognizer_params)
        else:
            built = recognizer
        #: the true rooms (``oracle`` and its calibration family), or None for a recognizer
        self.truth: TrueRooms | None = built if isinstance(built, TrueRooms) else None
        #: the true rooms bound to this building by :meth:`bind` (each tour binds anew)
        self.bound: BoundTrueRooms | None = None
        model = None if isinstance(built, TrueRooms) else built
        world.setdefault("camera", "panorama" if parsed is None else parsed.camera)
        # a recognizer that reads no images (random, none) gets none rendered: the same ids
        looks = model is not None and reads_images(model)
        self.tour_nav = PlaceNavEnv(n_rooms=n_rooms, render_mode=render_mode,
                                    panorama=looks or observe_image, **world)
        self.wrapper = None if model is None else PlaceIdWrapper(
            self.tour_nav, model, max_places=max_places, learn=True, reset_map=True)
        if self.wrapper is not None and not errand_learn and self.wrapper.reads_images:
            self.wrapper.check_localizes()  # a ValueError before any tour is driven
        #: what a step goes through: the world the robot is in, wrapped by the recognizer
        self.env: gym.Env = self.tour_nav if self.wrapper is None else self.wrapper
        #: the errands' world: the same building under another condition, built once
        self.errand_nav = self.tour_nav if errand_condition is None else PlaceNavEnv(
            n_rooms=n_rooms, render_mode=render_mode, panorama=looks or observe_image,
            **{k: v for k, v in world.items() if k not in CONDITION_KEYS},
            **CONDITIONS[errand_condition])
        #: the raw place of the current frame (-1 unknown)
        self.place = -1

    @property
    def recognizer(self) -> Recognizer | None:
        """The recognizer with the map it has built (``None`` for the true rooms)."""
        return None if self.wrapper is None else self.wrapper.recognizer

    def bind(self, plan: FloorPlan, seed: int) -> None:
        """Bind the true rooms to the building for a new tour (nothing for a recognizer)."""
        if self.truth is not None:
            self.bound = self.truth.bind(plan, seed)

    def use(self, nav: PlaceNavEnv, learn: bool) -> None:
        """Run on ``nav`` from now on, the recognizer learning or only localizing."""
        if self.wrapper is None:
            self.env = nav
        else:
            self.wrapper.env = nav
            # one that reads no images has no map to fix: its ids go on as they were
            self.wrapper.learn = learn or not self.wrapper.reads_images

    def read(self, info: dict[str, Any]) -> int:
        """The raw place of the frame ``info`` describes (-1 unknown), read once per frame: a
        noisy oracle draws as it answers."""
        if self.bound is not None:
            self.place = self.bound.place(info["room_id"], info["pose"])
        else:
            self.place = int(info["place_id"])
        return self.place

    def see(self, obs: dict[str, Any], info: dict[str, Any]
            ) -> tuple[dict[str, Any], dict[str, Any]]:
        """The observation and info of a robot placed without a step: the recognizer takes in
        the frame (learning or not, as set) and its place is read."""
        if self.wrapper is not None:
            obs = self.wrapper.observation(obs)
            info = {**info, **self.wrapper.last_info}
        self.read(info)
        return obs, info

    def relocated(self, obs: dict[str, Any], info: dict[str, Any]
                  ) -> tuple[dict[str, Any], dict[str, Any]]:
        """A robot carried elsewhere: the recognizer and the true rooms forget where it was,
        and the new frame's place is read."""
        if self.wrapper is not None:  # the recognizer sees the new start, lost
            obs, info = self.wrapper.relocated(obs, info)
        if self.bound is not None:
            self.bound.reset_position()
        self.read(info)
        return obs, info

    def keep(self) -> tuple[Recognizer | None, BoundTrueRooms | None]:
        """Copies of what it has learnt: the recognizer's map, the bound true rooms."""
        return copy.deepcopy(self.recognizer), copy.deepcopy(self.bound)

    def restore(self, recognizer: Recognizer | None, bound: BoundTrueRooms | None,
                place: int, nav: NavSnapshot) -> None:
        """Put back what :meth:`keep` copied, the current place and the tour's world as
        ``nav`` (its :meth:`~envs.tasks.place_nav.PlaceNavEnv.snapshot`) holds it; a
        ``ValueError`` for another kind of recognizer or another building, before any change."""
        if (self.wrapper is None) != (recognizer is None):
            raise ValueError("the tour state is of another kind of recognizer than this env's")
        self.tour_nav.restore(nav)
        if self.wrapper is not None and recognizer is not None:
            self.wrapper.recognizer = copy.deepcopy(recognizer)
        self.bound = copy.deepcopy(bound)
        self.place = place

    def close(self) -> None:
        self.tour_nav.close()
        if self.errand_nav is not self.tour_nav:
            self.errand_nav.close()
