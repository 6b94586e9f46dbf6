"""The differential-drive robot of ``assets/robot.xml``: commands in, pose out; and its gyro.

Actions are normalised ``(forward, turn)`` in [-1, 1]: ``forward`` scales :data:`MAX_SPEED`
(m/s) and ``turn`` scales :data:`MAX_TURN` (rad/s, counter-clockwise positive). They become
wheel speeds through the unicycle model, which the wheels' velocity actuators then track.

**Its gyro compass** (placenav-v5's heading): a heading as a small robot's IMU gives it, the
gyro's rate integrated, with its noise and drift. ``PlaceNav-v0``'s ``heading`` is the true
heading. A wheeled robot's comes from its gyro: TurtleBot3 takes its yaw from the IMU alone
(``use_imu: true``; the wheels give only the distance), an MPU-9250 until 2020. A gyro's rate
carries white noise (its *rate noise spectral density*, integrated: angle random walk) and a
bias that wanders (its *bias instability*); the heading integrates both, so its error grows
with time and never resets, through a carry too (the gyro feels the robot being turned).
:class:`GyroCompass` draws that error, a step at a time, for a stated part (:data:`COMPASSES`):

- ``mpu9250``: rate noise 0.01 °/s/√Hz (InvenSense, *MPU-9250 Product Specification*
  PS-MPU-9250A-01 rev. 1.0, Table 1, typical at 25 °C); bias instability 4.6 °/h with a
  correlation time of 500 s, the Allan-variance figure of its sibling, the MPU-6000 (Greenheck
  2009, *Design and characterization of a low cost MEMS IMU cluster for precision
  navigation*, Marquette University, §2.2); the bias left after a standstill calibration at
  power-on, drawn with the same spread.
- ``ideal``: no error (v1–v4's compass).

The bias is a first-order Gauss-Markov process (the usual model of bias instability, e.g.
Woodman 2007, *An introduction to inertial navigation*, §3.2): ``b ← φ b + σ √(1 − φ²) n``
with ``φ = exp(−dt / τ)``; the heading error ``e ← e + (b + w) dt`` with ``w`` the rate
noise, of standard deviation ``N / √dt`` for a density ``N``. Over a 20-minute episode the
MPU-9250's heading is off by about a degree: a gyro this good is nearly a compass, which is
what the suite states rather than assumes.

Examples:
    >>> import numpy as np
    >>> gyro = GyroCompass.part("mpu9250", dt=0.1, seed=0)
    >>> errors = gyro.errors(12_000)                       # 20 minutes of 0.1 s steps
    >>> errors.shape, bool(abs(np.degrees(errors[-1])) < 5)
    ((12000,), True)
    >>> bool((gyro.errors(10) == errors[:10]).all())       # the same stream, step for step
    True
    >>> GyroCompass.part("ideal", dt=0.1, seed=0).errors(3)
    array([0., 0., 0.])
    >>> np.round(reading(np.array([1.0, 0.0]), np.pi / 2), 6).tolist()
    [0.0, 1.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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


# -- the gyro compass ----------------------------------------------------------------------
@dataclass(frozen=True)
class GyroSpec:
    """A gyro's error figures: ``noise_density`` (°/s/√Hz), ``bias_instability`` (°/h),
    ``correlation_time`` (s) of the bias, and ``source`` (where the figures are from)."""

    noise_density: float
    bias_instability: float
    correlation_time: float
    source: str


#: the compasses a task can name: a part's gyro, or ``ideal`` (None: the true heading)
COMPASSES: dict[str, GyroSpec | None] = {
    "ideal": None,
    "mpu9250": GyroSpec(0.01, 4.6, 500.0,
                        "MPU-9250 datasheet PS-MPU-9250A-01 Table 1 (noise); MPU-6000 Allan "
                        "variance, Greenheck 2009 §2.2 (bias instability)"),
}


class GyroCompass:
    """The heading error (radians) of a gyro-integrated compass at each control step.

    Args:
        spec: the gyro's figures, or None for no error.
        dt: seconds per control step.
        seed: the error's random stream; one seed, one error sequence, however it is read.
    """

    def __init__(self, spec: GyroSpec | None, dt: float, seed: int) -> None:
        if not dt > 0:
            raise ValueError(f"dt must be a positive number of seconds, got {dt}")
        self.spec, self.dt = spec, float(dt)
        self._rng = np.random.default_rng(seed)
        self._errors = np.zeros(0)
        self._bias = 0.0
        if spec is not None:  # what a standstill calibration at power-on leaves
            self._bias = math.radians(spec.bias_instability / 3600.0) * self._rng.normal()

    @classmethod
    def part(cls, name: str, dt: float, seed: int) -> GyroCompass:
        """The compass of :data:`COMPASSES` called ``name``; a ``ValueError`` naming them."""
        if name not in COMPASSES:
            raise ValueError(f"unknown compass {name!r}; choose one of {sorted(COMPASSES)}")
        return cls(COMPASSES[name], dt, seed)

    def errors(self, n: int) -> np.ndarray:
        """(n,) the heading error at steps 0 .. n-1 (0 at step 0), drawn once and kept."""
        self._extend(n)
        return self._errors[:n].copy()

    def error(self, step: int) -> float:
        """The heading error at control step ``step`` (read once a step: no copy)."""
        self._extend(step + 1)
        return float(self._errors[step])

    def _extend(self, n: int) -> None:
        """Draw at least ``n`` errors, doubling what is kept (a step at a time would copy the
        whole stream each step); the stream is the same however far ahead it is drawn."""
        if len(self._errors) < n:
            more = max(n, 2 * len(self._errors), 1024) - len(self._errors)
            self._errors = np.concatenate([self._errors, self._draw(more)])

    def _draw(self, n: int) -> np.ndarray:
        """The next ``n`` errors: one increment each (none before step 0), so that the stream
        is the same however it is read in pieces."""
        first = not len(self._errors)
        increments = self._increments(n - 1 if first else n)
        out = np.empty(len(increments))
        error = 0.0 if first else float(self._errors[-1])
        for i, step in enumerate(increments):  # in order, so pieces add up bit for bit
            error += step
            out[i] = error
        return np.concatenate([[0.0], out]) if first else out

    def _increments(self, n: int) -> np.ndarray:
        """The heading's change over each of the next ``n`` steps: (bias + rate noise) dt."""
        if self.spec is None or n <= 0:
            return np.zeros(max(n, 0))
        phi = math.exp(-self.dt / self.spec.correlation_time)
        sigma_b = math.radians(self.spec.bias_instability / 3600.0)
        sigma_w = math.radians(self.spec.noise_density) / math.sqrt(self.dt)
        shocks = self._rng.normal(size=(n, 2))
        rates = np.empty(n)
        bias = self._bias
        for i in range(n):  # the bias's recursion is sequential; n is a few thousand
            rates[i] = bias + sigma_w * shocks[i, 0]
            bias = phi * bias + sigma_b * math.sqrt(1 - phi * phi) * shocks[i, 1]
        self._bias = bias
        return rates * self.dt


def reading(heading: np.ndarray, error: float | np.ndarray) -> np.ndarray:
    """A compass reading, ``(cos, sin)`` (as ``PlaceNav-v0``'s ``heading``, one or (T, 2)),
    turned by ``error`` radians (one or (T,))."""
    heading = np.asarray(heading, float)
    yaw = np.arctan2(heading[..., 1], heading[..., 0]) + np.asarray(error, float)
    return np.stack([np.cos(yaw), np.sin(yaw)], axis=-1).astype(np.float32)
