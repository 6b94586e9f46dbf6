"""Closed-loop results files: per-building rows, their summaries with intervals, provenance,
and what the calibration recognizers in them say (:func:`calibration`).

``placeclust leaderboard`` (``OUT/results.json``) and ``placeclust errands --json`` write one
format, which ``placeclust compare`` reads::

    {"format": "placeclust-results/2",
     "provenance": {suite, size, buildings, versions, render_fingerprint, ...},
     "settings": {split, scene_seeds, rooms, n_errands, seed, agent, task},
     "summaries": [{recognizer, n_errands, success_rate, success_rate_interval, ...}, ...],
     "buildings": [one row per (recognizer, building): its errands and its tour's map scores]}

A building's ``errands`` is the list of its errands; ``n_errands`` counts them. Files of
``placeclust-results/1`` (before 0.19.0: ``goals`` and a summary's ``errands`` for the count)
are read as /2.

Every figure of a summary is a mean over errands (or tours) with its 95% interval from a
bootstrap over buildings (:mod:`placeclust.stats`).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from placeclust import strict_json
from placeclust.atomic import write_atomic
from placeclust.stats import Estimate, buildings_for, interval, paired_difference

from ..tasks.oracles import error_of
from .task_spec import ErrandTask

FORMAT = "placeclust-results/2"
#: the formats :func:`load_results` still reads, each upgraded to :data:`FORMAT` on reading
OLD_FORMATS = ("placeclust-results/1",)
#: per-errand figures (one value per errand) and per-tour ones (one per building)
ERRAND_METRICS = ("success_rate", "spl", "mean_length")
TOUR_METRICS = ("precision", "nmi", "n_places", "places_per_room")
#: image goals' errands also record the walking distance (m) left when they ended
GOAL_METRICS = ("final_distance",)
_ERRAND_KEY = {"success_rate": "success", "spl": "spl", "mean_length": "steps",
               "final_distance": "final_distance"}
#: the half-widths a full-size suite is sized for (docs/design.md, "How many buildings")
TARGET_HALF_WIDTH = {"success_rate": 0.05, "spl": 0.05, "precision": 0.01}


def groups(rows: list[dict[str, Any]], metric: str) -> list[list[float]]:
    """One list of values per building (row): its errands' values of an errand metric, or
    its tour's single value of a tour metric."""
    if metric in _ERRAND_KEY:
        return [[float(e[_ERRAND_KEY[metric]]) for e in r["errands"]] for r in rows]
    if metric in TOUR_METRICS:
        return [[float(r[metric])] for r in rows]
    raise ValueError(f"unknown metric {metric!r}; choose one of "
                     f"{ERRAND_METRICS + GOAL_METRICS + TOUR_METRICS}")


def estimate(rows: list[dict[str, Any]], metric: str) -> Estimate:
    """``metric``'s mean over the rows' buildings with its bootstrap interval."""
    return interval(groups(rows, metric))


def summarize(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """One recognizer's rows as scores over buildings: each metric's mean, its interval
    (``<metric>_interval``: [low, high]), the worst building's success, how many errands were
    redrawn to start 1 m from their goal, and for :data:`TARGET_HALF_WIDTH`'s metrics the
    buildings a sample like this one needs to reach it (``<metric>_buildings_needed``)."""
    if not rows:
        raise ValueError("no rows to summarize")
    errands = [e for r in rows for e in r["errands"]]
    out: dict[str, Any] = {
        "recognizer": rows[0]["recognizer"], "agent": rows[0]["agent"],
        "scenes": [r["scene_seed"] for r in rows], "n_errands": len(errands),
        "redrawn": sum(bool(e.get("redrawn")) for e in errands),
        "worst_scene_success": float(min(r["success_rate"] for r in rows)),
        "seconds": float(sum(r["seconds"] for r in rows)),
    }
    goal = GOAL_METRICS if all("final_distance" in e for e in errands) else ()
    for metric in ERRAND_METRICS + goal + TOUR_METRICS:
        est = estimate(rows, metric)
        out[metric], out[f"{metric}_interval"] = est.mean, [est.low, est.high]
        if metric in TARGET_HALF_WIDTH and len(rows) >= 2:
            out[f"{metric}_buildings_needed"] = buildings_for(groups(rows, metric),
                                                              TARGET_HALF_WIDTH[metric])
    return out


def seed_span(seeds: list[int]) -> str:
    """Scene seeds as a report names them: ``2000–2059`` when they run on without a gap,
    else listed (``0, 5, 9``)."""
    if len(seeds) > 2 and seeds == list(range(seeds[0], seeds[-1] + 1)):
        return f"{seeds[0]}–{seeds[-1]}"
    return ", ".join(map(str, seeds))


def interval_text(summary: dict[str, Any], metric: str, digits: int = 2) -> str:
    """``"0.82 [0.68, 0.91]"`` from a summary."""
    low, high = summary[f"{metric}_interval"]
    return Estimate(summary[metric], low, high, len(summary["scenes"])).text(digits)


def write_results(path: Path, rows: list[dict[str, Any]], recognizers: list[str],
                  settings: dict[str, Any], provenance: dict[str, Any]) -> dict[str, Any]:
    """Summarize ``rows`` per recognizer and write the results file atomically; its content."""
    summaries = [summarize([r for r in rows if r["recognizer"] == name]) for name in recognizers]
    doc = {"format": FORMAT, "provenance": provenance, "settings": settings,
           "summaries": summaries, "buildings": rows}
    text = strict_json.dumps(doc, indent=1).encode()  # null, not NaN: an undefined interval
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, lambda f: f.write(text))
    return doc


def load_results(path: Path) -> dict[str, Any]:
    """A results file; a ``ValueError`` naming the file if it is not one."""
    try:
        doc = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: cannot read a results file ({exc})") from exc
    if not isinstance(doc, dict) or doc.get("format") not in (FORMAT, *OLD_FORMATS):
        raise ValueError(f"{path} is not a {FORMAT} results file (written by placeclust "
                         "leaderboard or placeclust errands --json)")
    if doc["format"] in OLD_FORMATS:
        _upgrade(doc)
    for summary in doc.get("summaries", []):  # an interval of one building is null: NaN
        for key, value in summary.items():
            if key.endswith("_interval"):
                summary[key] = strict_json.nan_for_none(value)
    return doc


def _upgrade(doc: dict[str, Any]) -> None:
    """A ``placeclust-results/1`` file as /2: the errand count's one name, ``n_errands``, the
    task as :class:`~envs.runs.task_spec.ErrandTask` writes it (a default value left out, so
    the same task compares equal), and a suite's own buildings said."""
    settings, prov = doc.get("settings", {}), doc.get("provenance", {})
    if "goals" in settings:
        settings["n_errands"] = settings.pop("goals")
    if isinstance(settings.get("task"), dict):  # as /2 writes it: what differs from defaults
        task = ErrandTask.within({**settings["task"], "n_errands": 1}).kwargs()
        settings["task"] = {k: v for k, v in task.items() if k != "n_errands"}
    for summary in doc.get("summaries", []):
        if isinstance(summary.get("errands"), int):
            summary["n_errands"] = summary.pop("errands")
    if isinstance(prov.get("definition"), dict) and "goals" in prov["definition"]:
        prov["definition"]["n_errands"] = prov["definition"].pop("goals")
    if prov.get("suite") is not None:
        prov.setdefault("buildings", "suite")
    doc["format"] = FORMAT


def slug(name: str) -> str:
    """``name`` as a part of a docs section's name: lowercase letters, digits and ``-``."""
    return re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")


def policy_name(policy: str | None) -> str:
    """A policy's short name: its run folder for a run's ``policy.zip`` or ``best_model.zip``
    (:mod:`train.train`, :mod:`train.choose`), else its file's stem."""
    if policy is None:
        return "shipped"
    path = Path(policy)
    return path.parent.name if path.name in ("policy.zip", "best_model.zip") else path.stem


def paired_rows(a: dict[str, Any], b: dict[str, Any], name_a: str, name_b: str
                ) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The two recognizers' rows on the buildings both ran, in the same order."""
    ra = {r["scene_seed"]: r for r in a["buildings"] if r["recognizer"] == name_a}
    rb = {r["scene_seed"]: r for r in b["buildings"] if r["recognizer"] == name_b}
    shared = sorted(set(ra) & set(rb))
    if len(shared) < 2:
        raise ValueError(f"{name_a} and {name_b} share {len(shared)} buildings; a paired "
                         "interval needs at least 2")
    return [ra[s] for s in shared], [rb[s] for s in shared]


def calibration(docs: dict[str, dict[str, Any]], ceiling: str = "oracle"
                ) -> tuple[str, list[dict[str, Any]]]:
    """The calibration recognizers on each track (:mod:`envs.tasks.oracles`): each one's
    success and its paired difference from ``ceiling``, and each track's *resolution*: per kind
    of error, the smallest one injected whose difference's interval excludes 0 on this sample.
    Returns the markdown and the points (``track``, ``kind``, ``value``, ``success``,
    ``diff``)."""
    points: list[dict[str, Any]] = []
    for track, doc in docs.items():
        for name in sorted({s["recognizer"] for s in doc["summaries"]}):
            error = error_of(name)
            if error is not None:
                rows, base = paired_rows(doc, doc, name, ceiling)
                got, top = groups(rows, "success_rate"), groups(base, "success_rate")
                points.append({"track": track, "kind": error[0], "value": error[1],
                               "success": interval(got), "diff": paired_difference(got, top)})
    points.sort(key=lambda q: (list(docs).index(q["track"]), q["kind"], q["value"]))
    lines = [f"| track | recognizer | success | − {ceiling} [95% interval] |", "|---|---|---|---|"]
    lines += [f"| {q['track']} | oracle-{q['kind']}:{q['value']:g} | {q['success'].text(2)} | "
              f"{q['diff'].text(3)} |" for q in points]
    found = [f"{track}: {resolution(points, track)}" for track in docs
             if any(q["track"] == track for q in points)]
    return ("\n".join(lines) + f"\n\nResolution, the smallest error whose difference from "
            f"`{ceiling}` excludes 0 on this sample: " + "; ".join(found) + "."), points


def resolution(points: list[dict[str, Any]], track: str) -> str:
    """Per kind of error on ``track``, the smallest injected one whose difference excludes 0,
    or the largest tried, said to be unresolved."""
    parts = []
    for kind in dict.fromkeys(q["kind"] for q in points if q["track"] == track):
        tried = [q for q in points if q["track"] == track and q["kind"] == kind]
        seen = [q["value"] for q in tried if q["diff"].excludes(0.0)]
        parts.append(f"{kind} {min(seen):g}" if seen else
                     f"{kind} none up to {max(q['value'] for q in tried):g}")
    return ", ".join(parts)


#: settings that say who acted, not what was measured: results differing in them compare
AGENT_KEYS = ("recognizers", "agent", "policy")


def differences(a: dict[str, Any], b: dict[str, Any]) -> list[str]:
    """What makes two results files incomparable: suite, settings, render, physics."""
    found = []
    pa, pb = a["provenance"], b["provenance"]
    for key in ("suite", "size", "buildings", "render_fingerprint", "physics_fingerprint"):
        if pa.get(key) != pb.get(key):  # older files record no physics fingerprint
            found.append(f"{key}: {pa.get(key, 'not recorded')} against "
                         f"{pb.get(key, 'not recorded')}")
    # what runs on the buildings, recognizer and agent, is what a comparison is about
    sa = {k: v for k, v in a["settings"].items() if k not in AGENT_KEYS}
    sb = {k: v for k, v in b["settings"].items() if k not in AGENT_KEYS}
    for key in sorted(set(sa) | set(sb)):
        if sa.get(key) != sb.get(key):
            found.append(f"settings {key}: {sa.get(key)} against {sb.get(key)}")
    return found
