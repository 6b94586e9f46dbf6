"""The world: a building's floor plan as data, its MuJoCo model, the robot, and how it is drawn.

``layout`` (floor plans) and ``corridor`` are pure data; ``scene`` emits the MuJoCo model from
a plan; ``conditions`` names the lightings and appearance changes that ``scene``, ``changes``,
the CLI and the bench all read; ``rendering``, ``panorama`` and ``portals`` draw it;
``visibility`` says which room a ray of a forward view hits; ``splits`` names the scene seeds.
Nothing here knows Gymnasium.
"""
