"""A trained errand policy as an agent of the closed loop: what it observes, how it acts.

``python -m train.train`` writes ``config.yml`` beside every ``policy.zip``. Its ``env.observe``
says what the policy was trained to see: ``hints`` (the residual agent of
:mod:`envs.agents.hints`, also the default for a policy without one) or one of
:data:`~envs.agents.tour_features.SENSES` (an agent on its own, :mod:`envs.agents.tour_features`);
its ``env.repeat`` how many steps each action is held for; its ``algo`` whether the policy has
a memory (``recurrent_ppo``, sb3-contrib's RecurrentPPO), whose state is carried from step to
step and cleared at each episode's start.

Examples:
    >>> from envs.agents.learned import LearnedAgent
    >>> from envs.world.textures import ASSETS
    >>> LearnedAgent.load(ASSETS / "policies" / "errands" / "ppo_errands.zip").observe
    'hints'
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from .hints import PlannerHints
from .tour_features import SENSES, TourFeatures

#: what a policy may have been trained to observe
OBSERVE = ("hints", *SENSES)
#: the learners a config's ``algo`` names: PPO, or sb3-contrib's PPO with an LSTM (memory)
ALGOS = ("ppo", "recurrent_ppo")


def observed(env: gym.Env, observe: str, repeat: int = 1, seed: int = 0) -> gym.Env:
    """``env`` (``PlaceNav-GuidedTour-v1``) as an agent that observes ``observe`` (one of
    :data:`OBSERVE`) sees it: the planner's hints, or the tour features with each action held
    ``repeat`` steps. Training and the closed loop both wrap through here."""
    if observe not in OBSERVE:
        raise ValueError(f"unknown observe {observe!r}; choose one of {OBSERVE}")
    if observe == "hints":
        return PlannerHints(env, seed)
    return TourFeatures(env, observe, repeat)


def learner(algo: str) -> Any:
    """The stable-baselines3 (or sb3-contrib) class for ``algo``, one of :data:`ALGOS`.

    Raises:
        ValueError: an unknown ``algo``, or ``recurrent_ppo`` without sb3-contrib installed.
    """
    if algo not in ALGOS:
        raise ValueError(f"unknown algo {algo!r}; choose one of {ALGOS}")
    if algo == "recurrent_ppo":
        try:
            from sb3_contrib import RecurrentPPO
        except ImportError as exc:  # an install without the train extra
            raise ValueError("algo: recurrent_ppo needs sb3-contrib: pip install "
                             "'placeclust[train]'") from exc
        return RecurrentPPO
    from stable_baselines3 import PPO

    return PPO


@dataclass
class LearnedAgent:
    """A loaded policy with the observation it was trained on.

    Attributes:
        model: the stable-baselines3 (or sb3-contrib) model.
        observe: one of :data:`OBSERVE`.
        recurrent: whether the policy carries a memory between steps.
        repeat: env steps each of its actions is held for, as in training.
    """

    model: Any
    observe: str = "hints"
    recurrent: bool = False
    repeat: int = 1

    @classmethod
    def load(cls, policy: str | Path) -> LearnedAgent:
        """The policy file ``policy`` and what its ``config.yml`` says (none: a hints agent).

        Raises:
            FileNotFoundError: no such policy file.
            ValueError: a config whose ``observe`` or ``algo`` is unknown.
        """
        policy = Path(policy)
        if not policy.is_file():
            raise FileNotFoundError(f"no policy file {policy}; train one with python -m "
                                    "train.train (see train/hyperparams/)")
        config = _config(config_path(policy))
        env = config.get("env", {})
        observe, repeat = env.get("observe", "hints"), int(env.get("repeat", 1))
        algo = config.get("algo", "ppo")
        if observe not in OBSERVE:
            raise ValueError(f"{policy}'s config observes {observe!r}; known: {OBSERVE}")
        if algo not in ALGOS:
            raise ValueError(f"{policy}'s config names algo {algo!r}; known: {ALGOS}")
        model = learner(algo).load(policy, device="cpu")
        return cls(model, observe, algo == "recurrent_ppo", repeat)

    def wrap(self, env: gym.Env, seed: int = 0) -> gym.Env:
        """``env`` (``PlaceNav-GuidedTour-v1``) seen as the policy was trained to see it."""
        return observed(env, self.observe, self.repeat, seed)

    def actor(self) -> Callable[[np.ndarray], np.ndarray]:
        """A function from one observation of a fresh episode on to the action: the policy's
        mean action, with its memory carried between calls if it has one."""
        if not self.recurrent:
            return lambda obs: self.model.predict(obs, deterministic=True)[0]
        memory: dict[str, Any] = {"state": None, "start": np.ones(1, bool)}

        def act(obs: np.ndarray) -> np.ndarray:
            action, memory["state"] = self.model.predict(
                obs, state=memory["state"], episode_start=memory["start"], deterministic=True)
            memory["start"] = np.zeros(1, bool)
            return action
        return act


def config_path(policy: Path) -> Path:
    """The ``config.yml`` that describes ``policy``: beside it, or for a checkpoint
    (``<run>/checkpoints/ppo_<n>_steps.zip``) its run folder's."""
    beside = policy.parent / "config.yml"
    if not beside.is_file() and policy.parent.name == "checkpoints":
        return policy.parent.parent / "config.yml"
    return beside


def _config(path: Path) -> dict[str, Any]:
    if not path.is_file():
        return {}
    import yaml  # the train extra, as the policies' learners are

    return yaml.safe_load(path.read_text()) or {}
