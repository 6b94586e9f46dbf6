"""The benchmark's report: ``results.csv``, a Fig. 2-style markdown table and two plots."""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Iterable, Sequence
from operator import itemgetter
from pathlib import Path

import numpy as np

from placeclust.features import BINARY
from placeclust.stats import interval

from ..world.splits import split_of

METRIC_COLUMNS = ["precision", "recall", "f_measure", "nmi", "ari", "n_places", "n_rooms",
                  "unknown_rate", "matching_rate", "mean_AC", "mean_TP", "mean_P",
                  "ms_per_frame", "ms_p95", "ms_mean", "map_precision"]
TABLE_KEYS = ("precision", "recall", "nmi", "ari")


METRIC_KEYS = ("precision", "recall", "f_measure", "nmi", "ari", "n_places", "n_rooms",
              "ms_per_frame")


def format_table(rows: dict[str, dict[str, float]], keys: tuple[str, ...] = METRIC_KEYS) -> str:
    """A markdown table: one row per method, one column per metric."""
    head = "| method | " + " | ".join(keys) + " |"
    sep = "|---" * (len(keys) + 1) + "|"
    lines = [head, sep]
    for name, m in rows.items():
        cells = [f"{m[k]:.3f}" if isinstance(m[k], float) else str(m[k]) for k in keys]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def params_text(params: Iterable[Sequence[object]] | None) -> str:
    """Recognizer parameters of a run as ``name=value`` joined by commas ("" for none)."""
    return ", ".join(f"{name}={value}" for name, value in params or ())


def write_csv(rows: list[dict], path: str | Path, spec_columns: list[str]) -> None:
    """One line per run: its ``spec_columns`` (the configuration), metrics, then the versions
    that produced it."""
    rows = [{**r, "params": params_text(r.get("params"))} for r in rows]
    columns = spec_columns + METRIC_COLUMNS
    columns += sorted({k for r in rows for k in r} - set(columns) - {"kind"})
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, columns, restval="", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def _methods(rows: list[dict]) -> dict[tuple[str, str, str], list[dict]]:
    groups: dict[tuple[str, str, str], list[dict]] = {}
    for r in rows:
        feat = ", ".join(filter(None, (r["features"], params_text(r.get("params")))))
        groups.setdefault((r["algo"], feat, r["condition"]), []).append(r)
    return groups


#: The bar a tour meets: precision, NMI at least, places per room at most (the 360° bar).
BAR = {"precision": 0.95, "nmi": 0.80, "places_per_room": 2.0}
#: The bar for binary features (ORB, AKAZE): ids pure enough for agents, fewer than 3 per room.
BINARY_BAR = {"precision": 0.93, "nmi": 0.0, "places_per_room": 3.0}


def meets_bar(row: dict) -> bool:
    """Whether one run meets its feature type's bar (:data:`BAR`, or :data:`BINARY_BAR` for
    binary descriptors) on all three counts."""
    bar = BINARY_BAR if row.get("features") in BINARY else BAR
    return (row["precision"] >= bar["precision"] and row["nmi"] >= bar["nmi"]
            and row["n_places"] <= bar["places_per_room"] * row["n_rooms"])


def by_building(rows: list[dict], value: Callable[[dict], float]) -> list[list[float]]:
    """``value`` of each run, grouped by building (scene seed): the sample a bootstrap over
    buildings resamples (:mod:`placeclust.stats`)."""
    groups: dict[object, list[float]] = {}
    for r in rows:  # a data set is one "building": its runs are not independent draws
        groups.setdefault(r.get("dataset") or int(r["scene_seed"]), []).append(float(value(r)))
    return list(groups.values())


def _cell(rows: list[dict], value: Callable[[dict], float], worst: Callable, digits: int) -> str:
    est = interval(by_building(rows, value))
    low = "" if np.isnan(est.low) else f" [{est.low:.{digits}f}, {est.high:.{digits}f}]"
    return f"{est.mean:.{digits}f}{low} ({worst(value(r) for r in rows):.{digits}f})"


def summary_table(rows: list[dict]) -> str:
    """Per method and condition, the distribution over worlds and tours, as in seed 000's Fig. 2.

    Each metric is the mean over tours with its 95% interval from a bootstrap over buildings
    (:func:`placeclust.stats.interval`; none with one building) and the worst run in
    parentheses (lowest precision, recall, NMI and ARI; most places per room); ``bar`` is the
    share of runs meeting their bar (:func:`meets_bar`), with its interval.
    """
    lines = ["| method | condition | " + " | ".join(f"{k} [95%] (worst)" for k in TABLE_KEYS)
             + " | places/rooms [95%] (worst) | bar [95%] | ms/frame | runs |",
             "|---" * (len(TABLE_KEYS) + 6) + "|"]
    for (algo, feat, condition), sel in _methods(rows).items():
        cells = [_cell(sel, itemgetter(k), min, 3) for k in TABLE_KEYS]
        ratio = _cell(sel, lambda r: r["n_places"] / r["n_rooms"], max, 2)
        met = sum(map(meets_bar, sel))
        bar = interval(by_building(sel, meets_bar))
        bar_text = f"{met}/{len(sel)}" + ("" if np.isnan(bar.low)
                                          else f" [{bar.low:.2f}, {bar.high:.2f}]")
        ms = np.median([r["ms_per_frame"] for r in sel])
        lines.append(f"| {algo} ({feat}) | {condition} | " + " | ".join(cells)
                     + f" | {ratio} | {bar_text} | {ms:.1f} | {len(sel)} |")
    return "\n".join(lines)


def worlds_line(rows: list[dict]) -> str:
    """Which scene seeds the runs come from, and their split (:mod:`envs.world.splits`)."""
    seeds = sorted({int(r["scene_seed"]) for r in rows})
    splits = sorted({split_of(s) or "none" for s in seeds})
    doors = sorted({r["doors"] for r in rows if r.get("doors") is not None})
    with_doors = f"; doors {', '.join(map(str, doors))} (envs.world.doors)" if doors else ""
    if any(r.get("local_light") for r in rows):
        with_doors += "; windows and lamps (envs.world.local_light)"
    return f"Scene seeds {', '.join(map(str, seeds))}; split: {', '.join(splits)}{with_doors}."


def latency_table(latency: list[dict]) -> str:
    """Median ms per frame of the online recognizer at each map size."""
    lines = ["| features | places | tracking ms | loop closure ms |", "|---|---|---|---|"]
    for row in latency:
        for p in row["points"]:
            lines.append(f"| {row['features']} | {p['places']} | {p['track_ms']:.1f} | "
                         f"{p['loop_ms']:.1f} |")
    return "\n".join(lines)


def plot_precision(rows: list[dict], path: str | Path) -> None:
    """Bars of mean precision (± std) per method, one group per condition."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = _methods(rows)
    methods = list(dict.fromkeys((a, f) for a, f, _ in groups))
    conditions = list(dict.fromkeys(li for _, _, li in groups))
    width = 0.8 / max(1, len(conditions))
    fig, ax = plt.subplots(figsize=(max(6.0, 0.8 * len(methods) + 2), 4), dpi=100)
    for i, condition in enumerate(conditions):
        xs, means, stds = [], [], []
        for j, (algo, feat) in enumerate(methods):
            sel = groups.get((algo, feat, condition))
            if sel:
                xs.append(j + (i - (len(conditions) - 1) / 2) * width)
                means.append(np.mean([r["precision"] for r in sel]))
                stds.append(np.std([r["precision"] for r in sel]))
        ax.bar(xs, means, width, yerr=stds, capsize=3, label=condition)
    ax.set_xticks(range(len(methods)), [f"{a}\n{f}" for a, f in methods], fontsize=8)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("clustering precision")
    ax.set_title("clustering precision per method (mean ± std over worlds and tours)")
    ax.legend(title="condition", fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def plot_latency(latency: list[dict], path: str | Path) -> None:
    """Median ms per frame against map size: tracking (solid) and loop closures (dashed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    for row in latency:
        places = [p["places"] for p in row["points"]]
        line = ax.plot(places, [p["track_ms"] for p in row["points"]], "o-",
                       label=f"{row['features']} tracking")
        ax.plot(places, [p["loop_ms"] for p in row["points"]], "s--", color=line[0].get_color(),
                label=f"{row['features']} loop closure")
    ax.set_xscale("log")
    ax.set_xlabel("places in the map")
    ax.set_ylabel("median ms per frame")
    ax.set_title("online recognizer latency as the map grows (512×128)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


#: the columns of the data set table, and the score each kind ranks recognizers by
DATASET_KEYS = ("precision", "nmi", "query_top1", "query_recall@1", "query_recall@5",
                "query_chance", "n_places")
DATASET_SCORE = {"images": "precision", "ref>query": "query_top1"}


def dataset_table(rows: list[dict]) -> str:
    """Per recognizer and real data set: the clustering metrics of a labelled folder, or
    VPR-Bench's place-level top-1, recall at N and chance (:mod:`placeclust.vprbench`)."""
    lines = ["| method | data set | " + " | ".join(DATASET_KEYS) + " | ms/frame |",
             "|---" * (len(DATASET_KEYS) + 3) + "|"]
    for r in rows:
        feat = ", ".join(filter(None, (r["features"], params_text(r.get("params")))))
        cells = [(f"{r[k]:.3f}" if isinstance(r[k], float) else str(r[k])) if k in r else "–"
                 for k in DATASET_KEYS]
        lines.append(f"| {r['algo']} ({feat}) | {Path(r['dataset']).name} | "
                     + " | ".join(cells) + f" | {r['ms_per_frame']:.1f} |")
    return "\n".join(lines)


def sim_vs_real(rows: list[dict]) -> str:
    """Whether the simulator ranks the recognizers as each real data set does: per method its
    mean precision on simulated ``day`` tours beside its score on the data set
    (:data:`DATASET_SCORE`), and Spearman's rank correlation over the methods with a 95%
    interval from a bootstrap over methods (:func:`placeclust.stats.rank_agreement`)."""
    from placeclust.stats import rank_agreement

    sim: dict[tuple, list[float]] = {}
    for r in rows:
        if not r.get("dataset") and r["condition"] == "day":
            sim.setdefault(_method(r), []).append(r["precision"])
    parts = []
    for path in dict.fromkeys(r["dataset"] for r in rows if r.get("dataset")):
        real = {_method(r): r[DATASET_SCORE[r["condition"]]] for r in rows
                if r.get("dataset") == path}
        methods = [m for m in real if m in sim]
        if not methods:
            continue
        name = Path(path).name
        lines = [f"| method | simulated precision (day) | {name} |", "|---|---|---|"]
        lines += [f"| {m[0]} ({m[1]}) | {np.mean(sim[m]):.3f} | {real[m]:.3f} |"
                  for m in methods]
        rho = rank_agreement([float(np.mean(sim[m])) for m in methods],
                             [real[m] for m in methods])
        spread = (f" [{rho.low:.2f}, {rho.high:.2f}]" if math.isfinite(rho.low)
                  else " (no interval)")
        agreement = (f"Spearman's rank correlation over {rho.n_buildings} methods: "
                     f"{rho.mean:.2f}{spread}" if rho.n_buildings >= 3 else
                     f"{rho.n_buildings} methods: too few to rank (Spearman needs 3).")
        parts += ["\n".join(lines), "", agreement, ""]
    return "\n".join(parts) or "No method ran on both a simulated `day` tour and a data set.\n"


def _method(r: dict) -> tuple[str, str]:
    return r["algo"], ", ".join(filter(None, (r["features"], params_text(r.get("params")))))


def write_report(rows: list[dict], latency: list[dict], folder: str | Path,
                 spec_columns: list[str], echo: bool = True,
                 skipped: Sequence[str] = ()) -> list[dict]:
    """Write ``results.csv``, ``results.md``, ``precision.png`` and ``latency.png``.

    ``spec_columns`` are the fields that configure a run, the first columns of the CSV;
    ``skipped`` names runs the matrix asked for and could not make (a line under the table).
    Returns ``rows``; prints the markdown when ``echo``.
    """
    folder = Path(folder)
    write_csv(rows, folder / "results.csv", spec_columns)
    parts = ["# placeclust bench", ""]
    simulated = [r for r in rows if not r.get("dataset")]
    real = [r for r in rows if r.get("dataset")]
    if simulated:
        parts += [worlds_line(simulated), "", summary_table(simulated), ""]
        plot_precision(simulated, folder / "precision.png")
    if real:
        parts += ["Real data sets (top-1 and recall at N: VPR-Bench's score at the level of "
                  "places, placeclust.vprbench):", "", dataset_table(real), ""]
    if simulated and real:
        parts += ["Simulated against real: does the simulator rank the recognizers as the "
                  "data set does?", "", sim_vs_real(rows)]
    if rows and skipped:
        parts += ["Skipped, as these recognizers cannot localize on a fixed map: "
                  + "; ".join(skipped) + ".", ""]
    if latency:
        parts += ["Latency as the map grows (synthetic places, 512×128):", "",
                  latency_table(latency), ""]
        plot_latency(latency, folder / "latency.png")
    text = "\n".join(parts)
    (folder / "results.md").write_text(text)
    if echo:
        print(text)
    return rows
