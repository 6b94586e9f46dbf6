"""``python -m envs.commands.photo_tour``: a forward-camera tour of a building whose surfaces
have photographic statistics (:func:`envs.tasks.photo_textures.retexture`), for
``placeclust stats``.

It measures the texture lever of issue 72 the way ``placeclust tour --camera forward`` measured
the sensor levers (``docs/benchmarks.md``, "Textures with photographic statistics"): the same
route, camera and sensor, the building retextured before its first frame. ``PlaceNav-v0``
itself renders as before; this is a lever under measurement, not a world option yet.

Example (about a minute)::

    python -m envs.commands.photo_tour --scene-seed 0 --steps 400 --width 160 --height 120 \\
        --fov 60 --detail 0.35 --out runs/photo/corridor-s0
    placeclust stats --images ../shared/data/vpr-bench-corridor \\
        --tour runs/photo/corridor-s0/tour.npz
    python -m envs.commands.photo_tour --cost     # its render cost, as ratios
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import cast

import gymnasium as gym
import numpy as np

from placeclust.argparsing import ArgumentParser

from ..tasks.photo_textures import Photo, record_photo_tour, retexture
from ..tasks.place_nav import PlaceNavEnv
from ..world.scene import build_scene
from ..world.sensor import Sensor
from .speed import _interleaved, _stepper, ratio


def build_parser() -> ArgumentParser:
    """The command's options: a tour's building and camera, and the :class:`Photo` settings."""
    p = ArgumentParser(prog="python -m envs.commands.photo_tour", description=__doc__)
    p.add_argument("--scene-seed", type=int, default=0)
    p.add_argument("--rooms", type=int, default=4)
    p.add_argument("--steps", type=int, default=400)
    p.add_argument("--seed", type=int, default=0, help="start pose and route")
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--height", type=int, default=120)
    p.add_argument("--fov", type=float, default=60.0, help="horizontal field of view, degrees")
    p.add_argument("--sensor", nargs="+", metavar="NAME=VALUE",
                   help="a real camera's effects, as placeclust tour's --sensor")
    p.add_argument("--detail", type=float, default=Photo.detail)
    p.add_argument("--grain", type=float, default=Photo.grain)
    p.add_argument("--stains", type=int, default=Photo.stains)
    p.add_argument("--out", help="folder for tour.npz")
    p.add_argument("--cost", action="store_true",
                   help="instead of a tour, print what the lever costs (cost_ratios)")
    return p


def _nav(env: gym.Env) -> PlaceNavEnv:
    return cast(PlaceNavEnv, env.unwrapped)


def cost_ratios(photo: Photo, sizes: tuple[tuple[int, int], ...] = ((160, 120), (512, 384)),
                rounds: int = 5, steps: int = 60, fov: float = 60.0) -> dict[str, float]:
    """What the lever costs, as ratios against its floor in the same run (medians over
    ``rounds``): :func:`retexture` against the :func:`build_scene` it follows (once a building),
    and ``env.step`` of a retextured building against a plain one, per forward image size,
    taken in turn each round as ``placeclust speed`` takes its runs."""
    once = []
    for seed in range(rounds):
        start = time.perf_counter()
        scene = build_scene(seed, 4)
        built = time.perf_counter()
        retexture(scene.model, seed, photo)
        once.append((time.perf_counter() - built) / (built - start))
    ratios = {"retexture / build_scene": float(np.median(once))}
    for w, h in sizes:
        pair = {name: gym.make("PlaceNav-v0", scene_seed=0, n_rooms=4, camera="forward",
                               image_width=w, image_height=h, image_fov=fov,
                               max_episode_steps=None) for name in ("plain", "photo")}
        retexture(_nav(pair["photo"]).model, 0, photo)  # before _stepper's reset draws
        try:
            times = _interleaved({name: _stepper(env) for name, env in pair.items()}, steps,
                                 rounds)
        finally:
            for env in pair.values():
                env.close()
        ratios[f"env.step {w}x{h}, photo / plain"] = ratio(times, "photo", "plain")
    return ratios


def main(argv: list[str] | None = None) -> int:
    """Record the tour (or, with ``--cost``, time the lever); 0 on success, 2 (one line) on a
    bad setting."""
    args = build_parser().parse_args(argv)
    try:
        if args.steps < 1 or args.rooms < 2:
            raise ValueError(f"need --steps ≥ 1 and --rooms ≥ 2, got {args.steps}, {args.rooms}")
        photo = Photo(args.detail, args.grain, args.stains)
        if args.cost:
            for name, ratio in cost_ratios(photo).items():
                print(f"{name}: {ratio:.2f}")
            return 0
        if not args.out:
            raise ValueError("--out FOLDER is needed for a tour")
        sensor = Sensor.parse(args.sensor)
        # a bad size or field of view is refused by PlaceNav-v0 before anything is drawn
        tour = record_photo_tour(args.scene_seed, args.rooms, args.steps, photo,
                                 seed=args.seed, sensor=sensor, camera="forward",
                                 image_width=args.width, image_height=args.height,
                                 image_fov=args.fov)
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tour.save(str(out / "tour.npz"), scene_seed=args.scene_seed, tour_seed=args.seed,
              lighting="day", camera="forward",  # a photo tour says so in its file
              textures=f"photo detail={photo.detail} grain={photo.grain} stains={photo.stains}")
    print(f"wrote {out / 'tour.npz'} ({args.steps} frames, scene {args.scene_seed}, {photo})")
    return 0


if __name__ == "__main__":
    import envs  # noqa: F401  (registers PlaceNav-v0)

    sys.exit(main())
