"""Floor plan pictures with matplotlib: rooms and their names, walls, doors, furniture, a path."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only, never a window: this runs headless
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

from .layout import FloorPlan  # noqa: E402


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
