"""One table of errand agents on the same buildings, each paired against the brackets.

    python -m train.report noplace=runs/agents/grid/noplace.json \\
        place=runs/agents/grid/place.json oracle=runs/agents/grid/oracle.json \\
        --against oracle noplace [--docs docs/benchmarks.md --section agents-carried-grid]

Each ``NAME=FILE`` is one agent's ``placeclust errands --json`` results, or
``NAME=FILE@RECOGNIZER`` one recognizer's rows of a file that holds several (a leaderboard's
``results.json``, the planner's for instance); ``NAME=FILE,FILE...`` is one agent trained with
several seeds (the training recipe's figure rather than one seed's). The table gives each
agent's success and SPL with their 95% intervals, and for each ``--against`` agent the paired
difference of success with its interval: a bootstrap that resamples the buildings (jointly,
for a paired difference) and each agent's training seeds (:func:`placeclust.stats.over_seeds`),
so seed-to-seed variance is in the interval; an agent of several seeds also shows each seed's
success. A line under the table says whether the first ``--against`` agent, the upper
bracket, is below any other beyond its interval.

Files from different buildings, errands or tours are refused as ``placeclust compare`` refuses
them (:func:`envs.commands.compare.differences`); the agent, its policy and the recognizer may
differ, as they are what the table is about.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from envs.runs.results import differences, groups, load_results, policy_name, seed_span
from placeclust.argparsing import ArgumentParser
from placeclust.docs_section import write_section
from placeclust.stats import Estimate, over_seeds


def load_agents(named: list[str]) -> dict[str, dict[str, Any]]:
    """``NAME=FILE[@RECOGNIZER][,FILE[@RECOGNIZER]...]`` arguments as {name: results document
    of one recognizer, seeds pooled}; every file must be comparable with the first.

    Raises:
        ValueError: a malformed argument, a repeated name or incomparable files.
    """
    docs: dict[str, dict[str, Any]] = {}
    for item in named:
        name, sep, path = item.partition("=")
        if not sep or not name or not path:
            raise ValueError(f"{item!r} is not NAME=FILE")
        if name in docs:
            raise ValueError(f"agent {name!r} is named twice")
        doc = _seeds_pooled([_one_recognizer(one) for one in path.split(",")])
        if docs:
            _check_comparable(next(iter(docs.values())), doc, f"{path} is")
        docs[name] = doc
    if len(docs) < 2:
        raise ValueError("name at least two agents")
    return docs


def _one_recognizer(path: str) -> dict[str, Any]:
    """The results at ``FILE`` or ``FILE@RECOGNIZER``, narrowed to that recognizer's summary
    and buildings; a file of several recognizers (a leaderboard's) must name one."""
    file, sep, name = path.rpartition("@") if "@" in Path(path).name else (path, "", "")
    doc = load_results(Path(file))
    names = [s["recognizer"] for s in doc["summaries"]]
    if not sep:
        if len(names) != 1:
            raise ValueError(f"{file} holds the recognizers {names}; name one as "
                             f"{file}@RECOGNIZER")
        return doc
    if name not in names:
        raise ValueError(f"{file} holds no recognizer {name!r}; it holds {names}")
    return {**doc, "summaries": [s for s in doc["summaries"] if s["recognizer"] == name],
            "buildings": [r for r in doc["buildings"] if r["recognizer"] == name]}


def _seeds_pooled(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """One agent's results from several training seeds, as one document: each building's
    errands pooled over the seeds (the recipe's figure, not one seed's), on the buildings all
    ran. The files must be comparable; their policies are named together."""
    first = runs[0]
    for doc in runs[1:]:
        _check_comparable(first, doc, "a seed's file is")
    if len(runs) == 1:
        return first
    per_seed = [_rows(doc, _shared_seeds(runs)) for doc in runs]
    rows = [{**same[0], "errands": [e for r in same for e in r["errands"]]}
            for same in zip(*per_seed, strict=True)]
    policies = [doc["settings"].get("policy") for doc in runs]
    return {**first, "buildings": rows, "settings": {**first["settings"], "policy": policies},
            "seed_runs": runs}


def _check_comparable(first: dict[str, Any], doc: dict[str, Any], what: str) -> None:
    found = differences(first, doc)
    if found:
        raise ValueError(f"{what} not comparable with the first file: " + "; ".join(found))


def _shared_seeds(docs: Iterable[dict[str, Any]]) -> list[int]:
    """The scene seeds of the buildings every document ran."""
    return sorted(set.intersection(*({r["scene_seed"] for r in d["buildings"]} for d in docs)))


def _rows(doc: dict[str, Any], seeds: list[int]) -> list[dict[str, Any]]:
    by_seed = {r["scene_seed"]: r for r in doc["buildings"]}
    return [by_seed[s] for s in seeds]


def _per_seed(doc: dict[str, Any], seeds: list[int], key: str) -> list[list]:
    """``key``'s groups over the buildings ``seeds``, one per training seed of the agent."""
    return [groups(_rows(run, seeds), key) for run in doc.get("seed_runs", [doc])]


def _cell(est: Estimate, sign: bool = False) -> str:
    text = f"{est.mean:+.2f} [{est.low:+.2f}, {est.high:+.2f}]" if sign else \
        f"{est.mean:.2f} [{est.low:.2f}, {est.high:.2f}]"
    decided = est.low > 0 or est.high < 0
    return f"**{text}**" if sign and decided else text


def agents_table(docs: dict[str, dict[str, Any]], against: list[str]) -> tuple[str, list[str]]:
    """The markdown table and, for the first of ``against``, the agents it falls below
    (the difference's interval wholly under 0)."""
    unknown = [a for a in against if a not in docs]
    if unknown:
        raise ValueError(f"--against names {unknown}, not among the agents {list(docs)}")
    seeds = _shared_seeds(docs.values())
    if len(seeds) < 2:
        raise ValueError(f"the files share {len(seeds)} buildings; pairing needs 2 or more")
    success = {n: _per_seed(d, seeds, "success_rate") for n, d in docs.items()}
    spl = {n: _per_seed(d, seeds, "spl") for n, d in docs.items()}
    seeded = any(len(s) > 1 for s in success.values())
    head = ["agent", "policy", "map", "success", "SPL", *(["success per seed"] if seeded else []),
            *(f"− {a}" for a in against)]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    below = []
    for name, doc in docs.items():
        settings = doc["settings"]
        policies = settings.get("policy")
        policies = policies if isinstance(policies, list) else [policies]
        policy = " + ".join(policy_name(p) for p in policies) \
            if settings.get("agent") == "ppo" else settings.get("agent", "")
        diffs = []
        for ref in against:
            if ref == name:
                diffs.append("")
                continue
            est = over_seeds(success[name], success[ref])
            diffs.append(_cell(est, sign=True))
            if ref == against[0] and est.low > 0:
                below.append(name)
        per_seed = [" / ".join(f"{over_seeds([s]).mean:.2f}" for s in success[name])] \
            if seeded else []
        cells = [f"`{name}`", policy, doc["summaries"][0]["recognizer"],
                 _cell(over_seeds(success[name])), _cell(over_seeds(spl[name])), *per_seed,
                 *diffs]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines), below


def main(argv: list[str] | None = None) -> int:
    p = ArgumentParser(prog="python -m train.report", description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("agents", nargs="+", metavar="NAME=FILE[@RECOGNIZER][,FILE...]")
    p.add_argument("--against", nargs="+", required=True, metavar="NAME",
                   help="agents to pair every other with; the first is the upper bracket")
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's section")
    p.add_argument("--section", default="agents", help="the section's name")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    try:
        docs = load_agents(args.agents)
        text, below = agents_table(docs, args.against)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    first = next(iter(docs.values()))
    seeds = sorted({r["scene_seed"] for r in first["buildings"]})
    task = ", ".join(f"{k} {v}" for k, v in (first["settings"].get("task") or {}).items())
    errands = first["summaries"][0]["n_errands"]
    top = args.against[0]
    bracket = (f"`{top}` is at or above every other agent within its interval." if not below
               else f"`{top}` is below {', '.join(f'`{n}`' for n in below)} beyond the "
               "interval: the bracket does not hold.")
    body = (f"{first['settings']['split']} buildings {seed_span(seeds)} "
            f"({len(seeds)}, {first['settings']['rooms']} rooms, {errands} errands"
            f"{', ' + task if task else ''}); mean [95% bootstrap interval over buildings "
            "and, for an agent of several training seeds, its seeds]; "
            "differences paired on the same buildings and errands, **bold** where the "
            f"interval excludes 0.\n\n{text}\n\n{bracket}")
    print(body)
    if args.docs:
        write_section(args.docs, args.section, body,
                      shlex.join(["python", "-m", "train.report", *argv]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
