"""The Gymnasium tasks and wrappers: ``PlaceNav-v0`` and the tasks built on it.

``place_nav`` is the base env (its docstring is the spec); every task with a goal owns one
(``goals.NavTask``, never a subclass) and takes its distances, shaping and success from
``goals``, whose ``HeardGoal`` makes the guided tour's goal one-hot for stable-baselines3;
``place_id`` runs a recognizer inside the loop; ``oracles`` are the true rooms and their
calibration family; ``tour`` drives scripted tours with ground truth; ``vector`` makes vector
envs.
"""
