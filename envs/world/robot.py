"""The differential-drive robot of ``assets/robot.xml``: commands in, pose out.

Actions are normalised ``(forward, turn)`` in [-1, 1]: ``forward`` scales :data:`MAX_SPEED`
(m/s) and ``turn`` scales :data:`MAX_TURN` (rad/s, counter-clockwise positive). They become
wheel speeds through the unicycle model, which the wheels' velocity actuators then track.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

MAX_SPEED = 0.5  # m/s
MAX_TURN = 1.5  # rad/s
WHEEL_RADIUS = 0.05
WHEEL_BASE = 0.32  # distance between the wheels
RADIUS = 0.2  # footprint radius, for planning clearances
N_RANGES = 16  # rangefinders in the ring, evenly spaced, the first looking ahead
MAX_RANGE = 4.0  # m; farther (or nothing hit) reads as MAX_RANGE


def wheel_speeds(action: np.ndarray) -> np.ndarray:
    """Wheel angular speeds (left, right) in rad/s for a normalised ``(forward, turn)``."""
    v = float(action[0]) * MAX_SPEED
    w = float(action[1]) * MAX_TURN
    half = w * WHEEL_BASE / 2
    return np.array([(v - half) / WHEEL_RADIUS, (v + half) / WHEEL_RADIUS])


#: what each entry of an action is: the robot's two, and an image goal's arrival
_ENTRIES = ("forward", "turn", "stop")


def check_action(action: np.ndarray, size: int = 2) -> np.ndarray:
    """The action as a float64 array of shape (size,), or a ``ValueError`` naming the problem:
    the robot's (forward, turn), with ``size=3`` also an image goal's stop."""
    a = np.asarray(action, dtype=np.float64)
    if a.shape != (size,):
        raise ValueError(f"action must have shape ({size},) = ({', '.join(_ENTRIES[:size])}), "
                         f"got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"action contains NaN or inf: {a.tolist()}")
    if np.any(np.abs(a) > 1.0 + 1e-6):
        raise ValueError(f"action {a.tolist()} is outside [-1, 1]; clip it or rescale it")
    return a


class Robot:
    """Reads and writes the robot's state in a model built by :mod:`envs.world.scene`."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self._root = model.joint("robot/root")
        self._qpos = self._root.qposadr[0]
        self._qvel = self._root.dofadr[0]
        self._body = model.body("robot/base").id
        self._act = [model.actuator("robot/left_wheel").id, model.actuator("robot/right_wheel").id]
        self._ranges = [model.sensor(f"range{k}").adr[0] for k in range(N_RANGES)]
        self._wheels = [model.joint(f"robot/{side}_wheel").dofadr[0] for side in ("left", "right")]

    def place(self, data: mujoco.MjData, x: float, y: float, heading: float) -> None:
        """Put the robot at rest at (x, y) facing ``heading`` (radians from +x, CCW)."""
        q = self._qpos
        data.qpos[q:q + 3] = [x, y, 0.05]
        data.qpos[q + 3:q + 7] = [math.cos(heading / 2), 0.0, 0.0, math.sin(heading / 2)]
        data.qvel[self._qvel:self._qvel + 6] = 0.0
        data.ctrl[self._act] = 0.0

    def command(self, data: mujoco.MjData, action: np.ndarray) -> None:
        """Set the wheel actuators for a normalised ``(forward, turn)`` action."""
        data.ctrl[self._act] = wheel_speeds(action)

    def pose(self, data: mujoco.MjData) -> np.ndarray:
        """(x, y, heading) with heading in (-pi, pi], from the simulator's ground truth."""
        x, y = data.xpos[self._body][:2]
        return np.array([x, y, self._yaw(data)])

    def velocity(self, data: mujoco.MjData) -> np.ndarray:
        """(forward speed m/s, turn rate rad/s) in the robot frame, from wheel odometry."""
        left, right = data.qvel[self._wheels]
        v = (left + right) * WHEEL_RADIUS / 2
        w = (right - left) * WHEEL_RADIUS / WHEEL_BASE
        return np.array([v, w])

    def ranges(self, data: mujoco.MjData) -> np.ndarray:
        """Distances (m) read by the ring of :data:`N_RANGES` rangefinders, CCW from ahead.

        A ray that hits nothing within :data:`MAX_RANGE` (MuJoCo reports -1) reads MAX_RANGE.
        """
        r = data.sensordata[self._ranges]
        return np.where((r < 0) | (r > MAX_RANGE), MAX_RANGE, r)

    def heading(self, data: mujoco.MjData) -> np.ndarray:
        """Compass reading (cos, sin) of the heading, as a magnetometer would give it."""
        yaw = self._yaw(data)
        return np.array([math.cos(yaw), math.sin(yaw)])

    def _yaw(self, data: mujoco.MjData) -> float:
        mat = data.xmat[self._body]
        return math.atan2(mat[3], mat[0])
