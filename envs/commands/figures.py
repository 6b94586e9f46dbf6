"""Pictures for reports: floor plans with matplotlib (rooms and their names, walls, doors,
furniture, a path), a tour, the places a recognizer found in it, and calibration curves."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import cv2
import imageio.v3 as iio
import matplotlib

matplotlib.use("Agg")  # files only, never a window

import matplotlib.pyplot as plt  # noqa: E402
import networkx as nx  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

from ..tasks.tour import Tour  # noqa: E402
from ..world.layout import FloorPlan  # noqa: E402


def draw_floor_plan(ax: Axes, plan: FloorPlan, room_colors: bool = True) -> None:
    """Draw ``plan`` on ``ax``: tinted rooms with names, walls, door gaps and furniture."""
    cmap = plt.get_cmap("Pastel1")
    for r in plan.rooms:
        face = cmap(r.id % cmap.N) if room_colors else "white"
        ax.add_patch(Rectangle((r.x0, r.y0), r.x1 - r.x0, r.y1 - r.y0, facecolor=face,
                               edgecolor="none", alpha=0.6, zorder=0))
        ax.text(*r.center, f"{r.name}\n#{r.id}", ha="center", va="center", fontsize=8,
                color="0.25", zorder=4)
    for f in plan.furniture:
        ax.add_patch(Rectangle((f.x - f.hx, f.y - f.hy), 2 * f.hx, 2 * f.hy, facecolor="0.7",
                               edgecolor="0.45", lw=0.5, zorder=1))
    for w in plan.walls:
        ax.plot([w.x0, w.x1], [w.y0, w.y1], color="0.15", lw=3, solid_capstyle="butt", zorder=3)
    for d in plan.doors:
        ax.plot(d.x, d.y, marker="s", ms=4, color="tab:brown", zorder=3)
    x0, y0, x1, y1 = plan.bounds
    ax.set_xlim(x0 - 0.3, x1 + 0.3)
    ax.set_ylim(y0 - 0.3, y1 + 0.3)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def draw_path(ax: Axes, poses: np.ndarray, label: str = "path") -> None:
    """Draw a trajectory (T, >=2) coloured by time, with its start and end marked."""
    xy = np.asarray(poses)[:, :2]
    ax.plot(xy[:, 0], xy[:, 1], color="tab:blue", lw=1, alpha=0.7, zorder=5, label=label)
    ax.plot(*xy[0], marker="o", color="tab:green", ms=7, zorder=6, label="start")
    ax.plot(*xy[-1], marker="X", color="tab:red", ms=8, zorder=6, label="end")


def save_floor_plan(plan: FloorPlan, path: str, poses: np.ndarray | None = None,
                    title: str | None = None) -> None:
    """Write a PNG of ``plan``, with the trajectory ``poses`` if given."""
    x0, y0, x1, y1 = plan.bounds
    scale = 7.0 / max(x1 - x0, y1 - y0)
    fig, ax = plt.subplots(figsize=(max(4.0, (x1 - x0) * scale + 1.5),
                                    max(4.0, (y1 - y0) * scale + 1.0)))
    draw_floor_plan(ax, plan)
    if poses is not None and len(poses):
        draw_path(ax, poses)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.8)
    if title:
        ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def save_place_map(plan: FloorPlan | None, poses: np.ndarray, places: np.ndarray, path: str,
                   title: str, graph: nx.Graph | None = None) -> None:
    """The floor plan with each frame's position coloured by its place id.

    With ``graph`` (the recognizer's topological graph), its edges join the places' centroids;
    without ``plan`` (a real sequence's poses) the positions alone, to scale.
    """
    fig, ax = plt.subplots(figsize=(7, 6))
    if plan is not None:
        draw_floor_plan(ax, plan, room_colors=False)
    else:
        ax.set_aspect("equal")
    known = places >= 0
    cmap = plt.get_cmap("tab20")
    centroids = {int(p): poses[places == p, :2].mean(axis=0) for p in np.unique(places[known])}
    for a, b in (graph.edges() if graph is not None else ()):
        if a in centroids and b in centroids:
            (x0, y0), (x1, y1) = centroids[a], centroids[b]
            ax.plot([x0, x1], [y0, y1], color="0.25", lw=1.2, alpha=0.7, zorder=4)
    ax.scatter(poses[known, 0], poses[known, 1], c=cmap(places[known] % 20), s=6, zorder=5)
    ax.scatter(poses[~known, 0], poses[~known, 1], c="k", marker="x", s=8, zorder=5)
    for p, (x, y) in centroids.items():
        ax.text(x, y, f"P{p}", fontsize=9, weight="bold", color=cmap(p % 20), zorder=6,
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


#: what each calibration family's value means, and the value that is no error at all
_ERRORS = {"noise": ("frames given another room's place", 0.0),
           "split": ("places per room", 1.0), "merge": ("probability a door's rooms merge", 0.0),
           "cells": ("compact places per room", 1.0),
           "door": ("metres the room left is reported", 0.0),
           "revisit": ("probability a revisit opens a place", 0.0)}


def calibration_curves(points: list[dict[str, Any]], ceilings: dict[str, Any],
                       path: str | Path, anchored: bool = True) -> None:
    """Errand success against the injected error: a panel per kind of error
    (:mod:`envs.tasks.oracles`), a line per track, each point with its 95% interval, starting
    from the true rooms' success (``ceilings``, an ``Estimate`` a track) at no error; with
    ``anchored=False`` (a ceiling that is not the family's no-error point, ``oracle-pose``)
    the ceiling is a dashed line in the track's colour instead.

    ``points`` are :func:`envs.commands.compare.calibration`'s: ``track``, ``kind``, ``value``
    and ``success`` (an ``Estimate``).
    """
    kinds = [k for k in _ERRORS if any(q["kind"] == k for q in points)]
    fig, axes = plt.subplots(1, max(1, len(kinds)), figsize=(4 * max(1, len(kinds)), 3.4),
                             squeeze=False, sharey=True)
    for ax, kind in zip(axes[0], kinds):
        label, none = _ERRORS[kind]
        for track in dict.fromkeys(q["track"] for q in points):
            first = [ceilings[track]] if anchored else []
            est = first + [q["success"] for q in points
                           if q["track"] == track and q["kind"] == kind]
            x = [none] * len(first) + [q["value"] for q in points
                                       if q["track"] == track and q["kind"] == kind]
            if len(x) < 2 - (not anchored):
                continue
            line = ax.errorbar(x, [e.mean for e in est], yerr=[[e.mean - e.low for e in est],
                                                               [e.high - e.mean for e in est]],
                               marker="o", capsize=3, label=track)
            if not anchored:
                ax.axhline(ceilings[track].mean, ls="--", lw=0.8, color=line[0].get_color())
        ax.set(xlabel=label, title=f"oracle-{kind}", ylim=(-0.05, 1.05))
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("errand success")
    axes[0][-1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
