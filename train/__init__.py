"""Training and evaluation of agents on the ``PlaceNav`` tasks (stable-baselines3).

``python -m train.train`` trains an agent from a hyperparameter file in ``train/hyperparams``
(the rl-baselines3-zoo pattern); ``python -m train.evaluate`` scores it beside the baselines.
"""
