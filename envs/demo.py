"""The main job: tour the default world, recognise places online, write a report folder.

``placeclust demo --out DIR`` (``make demo``) writes:

- ``tour.npz``: the recorded frames with ground truth;
- ``floorplan.png``: rooms, names, doors, furniture and the path;
- ``map.png``: the path coloured by the place the online recognizer (seed 000) reported;
- ``panoramas.png``: a panorama from every room;
- ``report.md``: metrics of the online recognizer and the nested mapper (seed 001) against
  ground truth, also printed on the terminal.
"""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import imageio.v3 as iio
import matplotlib.pyplot as plt
import numpy as np

import envs  # noqa: F401 - registers PlaceNav-v0
from envs.floorplan import draw_floor_plan, save_floor_plan
from envs.layout import FloorPlan
from envs.tour import Tour, drive_tour


def record_tour(scene_seed: int, n_rooms: int, steps: int, seed: int = 0, width: int = 512,
                height: int = 128, lighting: str = "day", progress: bool = True
                ) -> tuple[Tour, FloorPlan]:
    """Drive a scripted tour of ``steps`` frames; returns it with the world's floor plan."""
    env = gym.make("PlaceNav-v0", scene_seed=scene_seed, n_rooms=n_rooms, panorama_width=width,
                   panorama_height=height, lighting=lighting, max_episode_steps=None)
    try:
        tour = drive_tour(env, steps, seed=seed, progress=progress)
        return tour, env.unwrapped.plan
    finally:
        env.close()


def save_place_map(plan: FloorPlan, poses: np.ndarray, places: np.ndarray, path: str,
                   title: str) -> None:
    """The floor plan with each frame's position coloured by its place id."""
    fig, ax = plt.subplots(figsize=(7, 6))
    draw_floor_plan(ax, plan, room_colors=False)
    known = places >= 0
    cmap = plt.get_cmap("tab20")
    ax.scatter(poses[known, 0], poses[known, 1], c=cmap(places[known] % 20), s=6, zorder=5)
    ax.scatter(poses[~known, 0], poses[~known, 1], c="k", marker="x", s=8, zorder=5)
    for p in np.unique(places[known]):
        xy = poses[places == p, :2].mean(axis=0)
        ax.text(*xy, f"P{p}", fontsize=9, weight="bold", color=cmap(p % 20), zorder=6,
                bbox=dict(facecolor="white", alpha=0.7, lw=0))
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def save_panoramas(tour: Tour, path: str) -> None:
    """One panorama from the middle of each room's first visit, stacked, labelled by room."""
    import cv2

    rows = []
    for room in np.unique(tour.room[tour.room >= 0]):
        idx = np.nonzero(tour.room == room)[0]
        frame = tour.frames[idx[len(idx) // 2]].copy()
        cv2.putText(frame, tour.room_names[room], (6, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.55,
                    (255, 255, 255), 2, cv2.LINE_AA)
        rows.append(frame)
    iio.imwrite(path, np.concatenate(rows, axis=0))


def run_demo(out: str, scene_seed: int = 0, n_rooms: int = 4, steps: int = 1000,
             seed: int = 0) -> dict[str, dict[str, float]]:
    """Run the main job and write the report folder ``out``; returns the metrics table."""
    from placeclust.cli import format_table
    from placeclust.runner import evaluate, run

    if steps < 1:
        raise ValueError(f"steps must be positive, got {steps}")
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    tour, plan = record_tour(scene_seed, n_rooms, steps, seed)
    tour.save(str(folder / "tour.npz"), scene_seed=scene_seed, tour_seed=seed)
    save_floor_plan(plan, str(folder / "floorplan.png"), tour.pose,
                    title=f"scene {scene_seed}: {n_rooms} rooms, {steps} steps")
    save_panoramas(tour, str(folder / "panoramas.png"))
    table, results = {}, {}
    for algo, label in (("online", "online (seed 000)"), ("nested", "nested (seed 001)")):
        results[algo] = run(algo, tour.frames, "sift", progress=True)
        table[label] = evaluate(results[algo], tour.room)
        np.save(folder / f"assignments_{algo}.npy", results[algo].assignments)
    save_place_map(plan, tour.pose, results["online"].assignments, str(folder / "map.png"),
                   "places found online (seed 000), coloured per place")
    text = format_table(table)
    (folder / "report.md").write_text(
        f"# placeclust demo\n\nScene seed {scene_seed}, {n_rooms} rooms, {steps} frames of "
        f"512x128 panoramas, SIFT features, tour seed {seed}.\n\n{text}\n\n"
        "precision: clustering precision (purity) as in seed 000 Fig. 2; recall: inverse "
        "purity; ms_per_frame: median latency.\n")
    (folder / "metrics.json").write_text(json.dumps(table, indent=2))
    print(text)
    print(f"\nreport written to {folder}/")
    return table
