"""Where a recognizer lost its errands to pictures: the decomposition of ``placenav-v5``'s
success.

Each errand of ``PlaceNav-ImageGoal-v1`` records what the tour's map knew of the place the
recognizer gave the goal picture (:mod:`envs.tasks.image_goal`). Per recognizer and track, with
its 95% interval over buildings (:mod:`placeclust.stats`):

| column | of all errands, the share where | what it says |
|---|---|---|
| unknown | the recognizer gave the picture no place | it abstained (only those that cannot rank) |
| room | the place holds a tour frame in the goal's room | named right, coarsely |
| within 1 m | the place holds a tour frame within 1 m of the goal | named right, finely |
| spot | the place's spot lies within 1 m of the goal | the place is fine enough to succeed |
| success | the agent stopped within 1 m | the errand |
| driving | success, of the errands whose spot was within 1 m | the way there, not the map |
| first step | arrival declared on its first step, the goal's place known | it stood at the spot |

"Room", "within 1 m" and "spot" are what the *tour's* map knew; on a learning map the agent
also drives to spots it remembers from the errands (a place opened by night), so success may
exceed "spot" there. Roughly, success ≈ spot × driving, and spot ≤ within 1 m ≤ room: a
recognizer below true rooms on success but level on "within 1 m" lost to coarse places, one
level on "spot" lost on the way.

Examples:
    >>> rows = [{"recognizer": "r", "scene_seed": s, "errands": [
    ...     {"success": s == 0, "steps": 9, "unknown": False, "named_room": True,
    ...      "named_fine": True, "spot_within": True}]} for s in (0, 1)]
    >>> decomposition({"continued": {"buildings": rows, "summaries": [{"recognizer": "r"}]}}
    ...               )[0]["driving"].mean
    0.5
"""

from __future__ import annotations

from typing import Any

from placeclust.stats import Estimate, interval

#: the errand records' fields (or what they give) behind each column, in the table's order
COLUMNS = {"unknown": "unknown", "room": "named_room", "within 1 m": "named_fine",
           "spot": "spot_within", "success": "success", "driving": "success",
           "first step": "steps"}


def _value(errand: dict[str, Any], column: str) -> float | None:
    """One errand's value of ``column`` (None where the errand does not count for it)."""
    if column == "driving" and not errand["spot_within"]:
        return None
    if column == "first step":  # with a goal place: an unknown one stops by the agent's rule
        return float(errand["steps"] == 1 and not errand["unknown"])
    return float(errand[COLUMNS[column]])


def decomposition(docs: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    """Per track and recognizer (results files by track, as :func:`~envs.commands.score.
    load_tracks` reads them): each column's :class:`~placeclust.stats.Estimate` over
    buildings; a ``ValueError`` where a track's errands lack v5's records."""
    out = []
    for track, doc in docs.items():
        names = [s["recognizer"] for s in doc["summaries"]]
        for name in names:
            rows = [r for r in doc["buildings"] if r["recognizer"] == name]
            errands = [e for r in rows for e in r["errands"]]
            if not all("spot_within" in e for e in errands):
                raise ValueError(f"track {track!r}: {name}'s errands have no decomposition "
                                 "(run PlaceNav-ImageGoal-v1, placenav-v5's task)")
            row: dict[str, Any] = {"track": track, "recognizer": name}
            for column in COLUMNS:
                groups = [[v for e in r["errands"] if (v := _value(e, column)) is not None]
                          for r in rows]
                groups = [g for g in groups if g]
                nan = float("nan")
                row[column] = interval(groups) if groups else Estimate(nan, nan, nan, 0)
            out.append(row)
    return out


def decomposition_table(docs: dict[str, dict[str, Any]]) -> str:
    """:func:`decomposition` as markdown: a row per track and recognizer, each figure a mean
    with its 95% interval over buildings."""
    lines = ["Where success was lost (`envs.runs.decomposition`): of all errands, the goal "
             "picture unknown; its place holding a tour frame in the goal's room, within 1 m "
             "of the goal; its spot within 1 m; success; success where the spot was within "
             "1 m (the driving); arrival declared on the first step, the goal's place known.",
             "",
             "| track | recognizer | " + " | ".join(COLUMNS) + " |",
             "|---|---|" + "---|" * len(COLUMNS)]
    for row in decomposition(docs):
        cells = [_text(row[c]) for c in COLUMNS]
        lines.append(f"| {row['track']} | {row['recognizer']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _text(est: Estimate) -> str:
    if est.mean != est.mean:  # no errand counts (no spot within 1 m at all)
        return "–"
    if est.low != est.low:  # one building: no interval
        return f"{est.mean:.2f}"
    return f"{est.mean:.2f} [{est.low:.2f}, {est.high:.2f}]"
