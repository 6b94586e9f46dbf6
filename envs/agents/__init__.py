"""Non-learned agents that act on a recognizer's map: the planners of the closed loop.

``topological`` plans over the place graph of a map (``PlaceNav-ReachRoom-v0``);
``teach_repeat`` repeats the guided tour's path (``PlaceNav-GuidedTour-v1``); ``hints`` turns
the tour planner into the observation of the learned errand agent.
"""
