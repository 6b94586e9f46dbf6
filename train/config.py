"""Hyperparameter files: one section per agent, and files that change only a few keys of another.

A file is the rl-baselines3-zoo layout: a section per agent (``place``, ``noplace``,
``oracle``; ``default`` is the shared YAML anchor and what agents without a section of their own,
``random`` and ``planner``, are evaluated with). Each section holds ``env`` (arguments of
:func:`train.make.make_env`), ``map`` (the place map's recognizer, :mod:`train.mapping`), the
run's ``n_envs``, ``n_timesteps`` and ``policy``, and the rest goes to stable-baselines3's PPO.

A file that differs from another by a few keys names it instead of copying it::

    base: ppo.yml          # relative to this file
    all:                   # merged into every section of the base
      env:
        range_limit: 0.8
    place:                 # merged into the base's place section only
      n_timesteps: 200000

Merging is recursive for mappings; any other value replaces the base's. A base may have a
base of its own.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

HYPERPARAMS = Path(__file__).resolve().parent / "hyperparams" / "ppo.yml"


def read_config(path: str | Path = HYPERPARAMS) -> dict[str, Any]:
    """Every section of the hyperparameter file at ``path``, its ``base`` merged in."""
    return _read(Path(path), ())


def load_config(agent: str, path: str | Path = HYPERPARAMS) -> dict[str, Any]:
    """The section for ``agent``, or a ``ValueError`` naming the sections the file has."""
    config = read_config(path)
    if agent not in config:
        known = sorted(k for k in config if k != "default")
        raise ValueError(f"{path} has no section {agent!r}; it has {known}")
    return config[agent]


def env_section(path: str | Path, agent: str) -> dict[str, Any]:
    """The ``env`` settings ``agent`` trains with: its own section's, else ``default``'s."""
    config = read_config(path)
    section = config.get(agent, config.get("default"))
    if section is None:
        raise ValueError(f"{path} has neither a section {agent!r} nor a 'default' one")
    return dict(section.get("env", {}))


def merge(base: dict[str, Any], changes: dict[str, Any]) -> dict[str, Any]:
    """``base`` with ``changes`` merged in: mappings recursively, other values replaced."""
    out = dict(base)
    for key, value in changes.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = value
    return out


def _read(path: Path, seen: tuple[Path, ...]) -> dict[str, Any]:
    resolved = path.resolve()
    if resolved in seen:
        chain = " -> ".join(str(p) for p in (*seen, resolved))
        raise ValueError(f"hyperparameter files include each other: {chain}")
    config = yaml.safe_load(path.read_text()) or {}
    if not isinstance(config, dict):
        raise ValueError(f"{path} must hold a mapping of sections, got {type(config).__name__}")
    if "base" not in config:
        if "all" in config:
            raise ValueError(f"{path} has an 'all' section but no 'base' to merge it into")
        return config
    base = _read(path.parent / str(config.pop("base")), (*seen, resolved))
    common = config.pop("all", {}) or {}
    unknown = sorted(set(config) - set(base))
    if unknown:
        raise ValueError(f"{path} changes sections {unknown} that its base does not have; "
                         f"the base has {sorted(base)}")
    return {name: merge(merge(section, common), config.get(name) or {})
            for name, section in base.items()}
