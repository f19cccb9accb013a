"""How a hand-held 6-DoF tracker records a hand motion: grip, tremor, sampling and measurement error.

Every number is a module constant with its source (see ``docs/dataset.md``); none was chosen by
looking at recognition results.

The chain for one sample at time ``t``::

    hand pose H(t) in the user frame          (the intended motion, see gestures.py)
      → physiological tremor                   H'(t) = [exp(δφ) R_H, p_H + δp]
      → grip (tracker held in the hand)        H'(t) · G          G: offset + rotation
      → placement of the user in the world     W · H'(t) · G      W: tracker world (base stations)
      → tracker measurement error              p += e_p(t),  R ← R · exp(e_φ(t))
      → 50 Hz time stamps with jitter and dropped samples
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory

__all__ = [
    "CANONICAL_W_PROBABILITY",
    "DROP_RATE",
    "GRIP_OFFSET_RANGE",
    "SAMPLE_PERIOD",
    "SIGN_FLIP_RATE",
    "TIMESTAMP_JITTER",
    "TRACKER_DRIFT_POS",
    "TRACKER_DRIFT_ROT",
    "TRACKER_DRIFT_TIME",
    "TRACKER_JITTER_POS",
    "TRACKER_JITTER_ROT",
    "TREMOR_ACCEL_RANGE",
    "TREMOR_FREQ_RANGE",
    "TREMOR_LEVER",
    "MeasurementNoise",
    "measure",
    "measurement_noise",
    "random_grip",
    "random_rotation",
    "sample_times",
    "stored_quaternions",
    "tracker_error",
    "tracker_poses",
    "tremor",
    "write_recording",
]

# ------------------------------------------------------------------------------------------ sampling
#: Nominal sample period [s]: the HPM recordings are 50 Hz (the paper, Section III).
SAMPLE_PERIOD = 0.02
#: Standard deviation of the time-stamp jitter [s] of a software logging loop (assumption: ~1 ms OS
#: scheduling jitter; truncated at ±4 ms so stamps stay strictly increasing).
TIMESTAMP_JITTER = 0.001
#: Probability that a sample is missing (assumption: occasional lost packets of a wireless tracker).
DROP_RATE = 0.005

# ----------------------------------------------------------------------------------------- the hand
#: Physiological tremor frequency band [Hz] (classical 8–12 Hz; Elble, Handbook of Clinical
#: Neurophysiology vol. 1, ch. 22, 2003; Lakie et al., J Physiol 593:4411, 2015: peak 6–12 Hz).
TREMOR_FREQ_RANGE = (8.0, 12.0)
#: Peak tremor acceleration of the outstretched hand [m/s²]: 0.0015–0.035 g, modal 0.01 g
#: (Wade, Gresty & Findley, Arch Neurol 39:358, 1982, 97 normal subjects). Drawn log-uniformly.
TREMOR_ACCEL_RANGE = (0.0015 * 9.81, 0.035 * 9.81)
#: Lever [m] from the wrist to the palm centre that turns tremor displacement into a rotation
#: (about 0.4 hand lengths; hand length 0.108 × body height, Drillis & Contini 1966).
TREMOR_LEVER = 0.07

#: Distance [m] from the palm centre to the tracker origin, drawn uniformly in this range with a
#: random direction: a puck-sized tracker (≈ 7 cm across) held in the fist.
GRIP_OFFSET_RANGE = (0.02, 0.06)

# -------------------------------------------------------------------------------------- the tracker
#: White position jitter [m]: sub-millimetre precision of Lighthouse tracking when tracking is good
#: (Niehorster, Li & Lappe, i-Perception 8(3), 2017).
TRACKER_JITTER_POS = 0.0003
#: White orientation jitter [rad] (assumption: IMU-fused orientation is smooth; 0.1°).
TRACKER_JITTER_ROT = math.radians(0.1)
#: Slowly varying position error [m], std: reproducibility "within a few millimetres" (Bauer,
#: Lienhart & Jost, Sensors 21:1622, 2021; accuracy 0.5 ± 0.2 cm in-plane, Sansone et al., Virtual
#: Reality 26:903, 2022).
TRACKER_DRIFT_POS = 0.002
#: Slowly varying orientation error [rad], std: "a few degrees" (the paper, Section III); 1.5°.
TRACKER_DRIFT_ROT = math.radians(1.5)
#: Correlation time [s] of the slowly varying error (assumption: errors change as the tracker's
#: pose relative to the base stations changes, i.e. on the time scale of the motion).
TRACKER_DRIFT_TIME = 0.5

# ------------------------------------------------------------------------------------- stored files
#: Probability that a recording stores quaternions in the hemisphere convention ``w ≥ 0`` (many
#: SDKs do), which flips the sign whenever ``w`` crosses zero.
CANONICAL_W_PROBABILITY = 0.5
#: Otherwise, probability per sample of an isolated sign flip.
SIGN_FLIP_RATE = 0.005


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation matrix (3, 3) drawn uniformly from SO(3) (normalized Gaussian quaternion)."""
    q = rng.standard_normal(4)
    return se3.matrix_from_quaternion(q / np.linalg.norm(q))


def random_grip(rng: np.random.Generator) -> np.ndarray:
    """Pose (4, 4) of the tracker in the hand frame: uniform random rotation and an offset of
    :data:`GRIP_OFFSET_RANGE` metres in a random direction."""
    d = rng.standard_normal(3)
    d *= rng.uniform(*GRIP_OFFSET_RANGE) / np.linalg.norm(d)
    G = np.eye(4)
    G[:3, :3] = random_rotation(rng)
    G[:3, 3] = d
    return G


def sample_times(duration: float, rng: np.random.Generator) -> np.ndarray:
    """Time stamps (n,) [s] of a 50 Hz recording of ``duration`` seconds: jitter, dropped samples,
    first stamp 0."""
    n = math.floor(duration / SAMPLE_PERIOD) + 1
    t = np.arange(n) * SAMPLE_PERIOD
    jitter = np.clip(
        rng.normal(0.0, TIMESTAMP_JITTER, n), -4 * TIMESTAMP_JITTER, 4 * TIMESTAMP_JITTER
    )
    t = t + jitter
    keep = rng.random(n) >= DROP_RATE
    keep[[0, -1]] = True
    t = t[keep]
    t = np.clip(t - t[0], 0.0, duration)
    return np.unique(t)


def _ou(t: np.ndarray, std: float, tau: float, rng: np.random.Generator) -> np.ndarray:
    """Stationary Ornstein–Uhlenbeck process (n, 3) with standard deviation ``std`` and correlation
    time ``tau`` [s], sampled exactly at the (irregular) times ``t`` (n,)."""
    n = t.shape[0]
    eps = rng.standard_normal((n, 3))
    out = np.empty((n, 3))
    out[0] = std * eps[0]
    a = np.exp(-np.diff(t) / tau)
    b = std * np.sqrt(1.0 - a**2)
    for k in range(1, n):  # a short recursion (n ≈ 10⁴ at most)
        out[k] = a[k - 1] * out[k - 1] + b[k - 1] * eps[k]
    return out


def tremor(t: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Physiological tremor of the hand at times ``t`` (n,) [s].

    A narrow-band oscillation per axis: carrier at a frequency drawn from
    :data:`TREMOR_FREQ_RANGE`, modulated by a slowly varying complex amplitude (correlation time
    0.3 s) so the peak acceleration is of the order drawn from :data:`TREMOR_ACCEL_RANGE`.

    Returns
    -------
    dp : ndarray, shape (n, 3)
        Position tremor [m] (tens of micrometres).
    dphi : ndarray, shape (n, 3)
        Orientation tremor [rad], the position tremor over :data:`TREMOR_LEVER`, about other axes.
    """
    f = rng.uniform(*TREMOR_FREQ_RANGE)
    accel = math.exp(rng.uniform(*np.log(TREMOR_ACCEL_RANGE)))
    amp = accel / (2 * math.pi * f) ** 2  # peak displacement [m]
    env = _ou(t, 1.0, 0.3, rng) + 1j * _ou(t, 1.0, 0.3, rng)
    dp = amp / math.sqrt(2) * np.real(env * np.exp(2j * math.pi * f * t)[:, None])
    env2 = _ou(t, 1.0, 0.3, rng) + 1j * _ou(t, 1.0, 0.3, rng)
    dphi = amp / TREMOR_LEVER / math.sqrt(2) * np.real(env2 * np.exp(2j * math.pi * f * t)[:, None])
    return dp, dphi


def tracker_error(t: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Measurement error of the tracker at times ``t`` (n,): slowly varying plus white parts.

    Returns
    -------
    e_p : ndarray, shape (n, 3)
        Position error [m], world coordinates.
    e_phi : ndarray, shape (n, 3)
        Orientation error [rad], rotation vector in tracker coordinates (right-multiplied).
    """
    n = t.shape[0]
    e_p = _ou(t, TRACKER_DRIFT_POS, TRACKER_DRIFT_TIME, rng) + rng.normal(
        0, TRACKER_JITTER_POS, (n, 3)
    )
    e_r = _ou(t, TRACKER_DRIFT_ROT, TRACKER_DRIFT_TIME, rng) + rng.normal(
        0, TRACKER_JITTER_ROT, (n, 3)
    )
    return e_p, e_r


@dataclass(frozen=True)
class MeasurementNoise:
    """Hand tremor and tracker error sampled at a sequence of time stamps.

    Attributes
    ----------
    tremor_p, tremor_phi : ndarray, shape (n, 3)
        Tremor displacement [m] and rotation vector [rad] of the hand.
    error_p, error_phi : ndarray, shape (n, 3)
        Tracker position [m] and orientation [rad] error.
    """

    tremor_p: np.ndarray
    tremor_phi: np.ndarray
    error_p: np.ndarray
    error_phi: np.ndarray

    def __getitem__(self, index: slice) -> MeasurementNoise:
        return MeasurementNoise(
            self.tremor_p[index], self.tremor_phi[index], self.error_p[index], self.error_phi[index]
        )


def measurement_noise(t: np.ndarray, rng: np.random.Generator) -> MeasurementNoise:
    """Tremor (:func:`tremor`) and tracker error (:func:`tracker_error`) at times ``t`` (n,) [s]."""
    tremor_p, tremor_phi = tremor(t, rng)
    error_p, error_phi = tracker_error(t, rng)
    return MeasurementNoise(tremor_p, tremor_phi, error_p, error_phi)


def tracker_poses(
    hand: np.ndarray, grip: np.ndarray, world: np.ndarray, noise: MeasurementNoise
) -> np.ndarray:
    """Measured tracker poses (n, 4, 4): ``world · (tremor · hand) · grip``, then the tracker error.

    Parameters
    ----------
    hand : ndarray, shape (n, 4, 4)
        Intended hand (palm) poses in the user frame.
    grip : ndarray, shape (4, 4) or (n, 4, 4)
        Tracker pose in the hand frame.
    world : ndarray, shape (4, 4) or (n, 4, 4)
        User frame in the tracker's world frame.
    noise : MeasurementNoise
        Sampled at the same n time stamps.
    """
    H = np.array(hand, dtype=np.float64, copy=True)
    H[:, :3, 3] += noise.tremor_p
    H[:, :3, :3] = se3.rotation_from_vector(noise.tremor_phi) @ H[:, :3, :3]
    T = np.asarray(world) @ H @ np.asarray(grip)
    T[:, :3, 3] += noise.error_p
    T[:, :3, :3] = T[:, :3, :3] @ se3.rotation_from_vector(noise.error_phi)
    return T


def measure(
    t: np.ndarray,
    hand: np.ndarray,
    grip: np.ndarray,
    world: np.ndarray,
    rng: np.random.Generator,
    source: str | None = None,
) -> Trajectory:
    """Record hand poses with a hand-held tracker.

    Parameters
    ----------
    t : ndarray, shape (n,)
        Time stamps [s].
    hand : ndarray, shape (n, 4, 4)
        Intended hand (palm) poses in the user frame at ``t``.
    grip : ndarray, shape (4, 4) or (n, 4, 4)
        Tracker pose in the hand frame.
    world : ndarray, shape (4, 4) or (n, 4, 4)
        User frame in the tracker's world frame.
    rng : numpy.random.Generator
    source : str, optional
        Label stored in the trajectory.

    Returns
    -------
    Trajectory
        Measured tracker poses, time starting at 0.
    """
    T = tracker_poses(hand, grip, world, measurement_noise(t, rng))
    return Trajectory.from_poses(t - t[0], T, source=source)


def stored_quaternions(q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Quaternions (n, 4) as a tracker SDK might store them: with probability
    :data:`CANONICAL_W_PROBABILITY` in the ``w ≥ 0`` hemisphere, else with isolated random sign
    flips at rate :data:`SIGN_FLIP_RATE`. Every row still represents the same rotation."""
    q = np.array(q, dtype=np.float64, copy=True)
    if rng.random() < CANONICAL_W_PROBABILITY:
        q[q[:, 0] < 0] *= -1.0
    else:
        flip = rng.random(q.shape[0]) < SIGN_FLIP_RATE
        q[flip] *= -1.0
    return q


def write_recording(
    path: str | Path, traj: Trajectory, rng: np.random.Generator | None = None
) -> Path:
    """Write ``traj`` as an 8-column CSV (no header, full precision); with ``rng``, store the
    quaternions as a tracker SDK might (:func:`stored_quaternions`: sign flips)."""
    path = Path(path)
    q = traj.q if rng is None else stored_quaternions(traj.q, rng)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack([traj.t, traj.p, q]), delimiter=",", fmt="%.17g")
    return path
