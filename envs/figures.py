"""Pictures of a tour and of the places a recognizer found in it, for reports."""

from __future__ import annotations

import cv2
import imageio.v3 as iio
import matplotlib

matplotlib.use("Agg")  # files only, never a window

import matplotlib.pyplot as plt  # noqa: E402
import networkx as nx  # noqa: E402
import numpy as np  # noqa: E402

from .floorplan import draw_floor_plan  # noqa: E402
from .layout import FloorPlan  # noqa: E402
from .tour import Tour  # noqa: E402


def save_place_map(plan: FloorPlan, poses: np.ndarray, places: np.ndarray, path: str,
                   title: str, graph: nx.Graph | None = None) -> None:
    """The floor plan with each frame's position coloured by its place id.

    With ``graph`` (the recognizer's topological graph), its edges join the places' centroids.
    """
    fig, ax = plt.subplots(figsize=(7, 6))
    draw_floor_plan(ax, plan, room_colors=False)
    known = places >= 0
    cmap = plt.get_cmap("tab20")
    centroids = {int(p): poses[places == p, :2].mean(axis=0) for p in np.unique(places[known])}
    for a, b in (graph.edges() if graph is not None else ()):
        if a in centroids and b in centroids:
            (x0, y0), (x1, y1) = centroids[a], centroids[b]
            ax.plot([x0, x1], [y0, y1], color="0.25", lw=1.2, alpha=0.7, zorder=4)
    ax.scatter(poses[known, 0], poses[known, 1], c=cmap(places[known] % 20), s=6, zorder=5)
    ax.scatter(poses[~known, 0], poses[~known, 1], c="k", marker="x", s=8, zorder=5)
    for p, xy in centroids.items():
        ax.text(*xy, f"P{p}", fontsize=9, weight="bold", color=cmap(p % 20), zorder=6,
                bbox=dict(facecolor="white", alpha=0.7, lw=0))
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def save_panoramas(tour: Tour, path: str) -> None:
    """One panorama from the middle of each room's first visit, stacked, labelled by room."""
    rows = []
    for room in np.unique(tour.room[tour.room >= 0]):
        idx = np.nonzero(tour.room == room)[0]
        frame = tour.frames[idx[len(idx) // 2]].copy()
        cv2.putText(frame, tour.room_names[room], (6, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.55,
                    (255, 255, 255), 2, cv2.LINE_AA)
        rows.append(frame)
    iio.imwrite(path, np.concatenate(rows, axis=0))




def save_confusion(places: np.ndarray, rooms: np.ndarray, room_names: list[str], path: str,
                   title: str) -> None:
    """Places x rooms: how many frames of each place were taken in each room."""
    from placeclust.metrics import contingency

    table, place_ids, room_ids = contingency(places, rooms)
    fig, ax = plt.subplots(figsize=(1.2 + 0.9 * len(room_ids), 1.0 + 0.35 * len(place_ids)))
    ax.imshow(table, cmap="Blues", aspect="auto")
    for (i, j), n in np.ndenumerate(table):
        if n:
            ax.text(j, i, str(n), ha="center", va="center", fontsize=7,
                    color="white" if n > table.max() / 2 else "black")
    ax.set_xticks(range(len(room_ids)),
                  [room_names[r] if r >= 0 else "outside" for r in room_ids], rotation=30,
                  ha="right", fontsize=8)
    ax.set_yticks(range(len(place_ids)), [f"P{p}" if p >= 0 else "unknown" for p in place_ids],
                  fontsize=8)
    ax.set_xlabel("ground-truth room")
    ax.set_ylabel("place")
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def save_tour_gif(tour: Tour, places: np.ndarray, path: str, every: int = 10,
                  width: int = 384) -> None:
    """An animated GIF of the tour: every ``every``-th panorama with place and room written on.

    Frames are resized to ``width`` pixels wide to keep the file small (a few MB at most).
    """
    frames = []
    for t in range(0, len(tour.frames), every):
        img = tour.frames[t]
        h = max(1, round(img.shape[0] * width / img.shape[1]))
        img = cv2.resize(img, (width, h), interpolation=cv2.INTER_AREA)
        room = tour.room_names[tour.room[t]] if tour.room[t] >= 0 else "outside"
        place = f"P{places[t]}" if places[t] >= 0 else "unknown"
        banner = np.zeros((18, width, 3), np.uint8)
        cv2.putText(banner, f"t={t}  place {place}  room: {room}", (4, 13),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.42, (255, 255, 255), 1, cv2.LINE_AA)
        frames.append(np.concatenate([banner, img], axis=0))
    iio.imwrite(path, np.stack(frames), duration=100, loop=0)
