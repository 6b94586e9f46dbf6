"""The Gymnasium tasks and wrappers: ``PlaceNav-v0`` and the tasks built on it.

``place_nav`` is the base env (its docstring is the spec); every task with a goal subclasses it
or wraps it and takes its distances, shaping and success from ``goals``; ``place_id`` runs a
recognizer inside the loop; ``tour`` drives scripted tours with ground truth; ``vector`` makes
vector envs.
"""
