"""The compiled kernels of :mod:`framefree.core.se3`: every SO(3) / SE(3) / quaternion formula
written once, for a single element (the ``*_one`` functions, and ``*_into`` ones that write into
a given array, both callable from other kernels), and the compiled loops that apply them over a
batch. :mod:`framefree.core.se3` wraps them in validating, shape-preserving functions; other
kernels (the descriptors', the progress's, the paper's pre-processing) call them directly.

Conventions: docs/algorithms/se3.md (poses 4×4, quaternions scalar first, twists rotation first).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: Below this rotation angle [rad] the SE(3) coefficients use their Taylor series.
_SMALL_ANGLE = 1e-4
#: Below this value of cos θ the rotation logarithm reads the axis from the symmetric part (θ near π).
_NEAR_PI_COS = -0.99


# --------------------------------------------------------------------------------------------------
# single-element kernels
# --------------------------------------------------------------------------------------------------


@njit(cache=True)
def cross_one(a, b):
    """Cross product of two 3-vectors."""
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@njit(cache=True)
def hat_one(v):
    """Skew-symmetric matrix ``[v]×`` of a 3-vector."""
    S = np.zeros((3, 3))
    S[0, 1] = -v[2]
    S[0, 2] = v[1]
    S[1, 0] = v[2]
    S[1, 2] = -v[0]
    S[2, 0] = -v[1]
    S[2, 1] = v[0]
    return S


@njit(cache=True)
def _rodrigues(phi, a, b, theta2):
    """``I + a [φ]x + b [φ]x²`` written out (``[φ]x² = φφᵀ - θ² I``)."""
    R = np.empty((3, 3))
    _rodrigues_into(phi, a, b, theta2, R)
    return R


@njit(cache=True)
def _rodrigues_into(phi, a, b, theta2, R):
    """:func:`_rodrigues` written into ``R`` (3×3, or the rotation block of a pose)."""
    d = 1.0 - b * theta2
    for i in range(3):
        for j in range(3):
            R[i, j] = b * phi[i] * phi[j]
        R[i, i] += d
    R[0, 1] -= a * phi[2]
    R[0, 2] += a * phi[1]
    R[1, 0] += a * phi[2]
    R[1, 2] -= a * phi[0]
    R[2, 0] -= a * phi[1]
    R[2, 1] += a * phi[0]


@njit(cache=True)
def rotation_from_vector_one(phi):
    """SO(3) exponential (Rodrigues) of a rotation vector ``phi`` (3,) [rad]."""
    theta2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]
    theta = math.sqrt(theta2)
    if theta < _SMALL_ANGLE:
        a = 1.0 - theta2 / 6.0 + theta2 * theta2 / 120.0
        b = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0
    else:
        a = math.sin(theta) / theta
        b = (1.0 - math.cos(theta)) / theta2
    return _rodrigues(phi, a, b, theta2)


@njit(cache=True)
def vector_from_rotation_one(R):
    """SO(3) logarithm: rotation vector (3,) of a rotation matrix, angle in [0, π].

    Follows the reference closed form (``atan2`` of the skew and trace parts); close to π, where
    the skew part vanishes, the axis is read from the symmetric part instead.
    """
    out = np.empty(3)
    vector_from_rotation_into(R, out)
    return out


@njit(cache=True)
def vector_from_rotation_into(R, out):
    """:func:`vector_from_rotation_one` written into ``out`` (3,): no allocation."""
    ax = 0.5 * (R[2, 1] - R[1, 2])
    ay = 0.5 * (R[0, 2] - R[2, 0])
    az = 0.5 * (R[1, 0] - R[0, 1])
    s = math.sqrt(ax * ax + ay * ay + az * az)
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    c = min(1.0, max(-1.0, c))
    if c < _NEAR_PI_COS:
        theta = math.atan2(s, c)
        # B = (R + R^T)/2 - c I = (1 - c) n n^T
        best = 0
        bval = -1.0
        for i in range(3):
            bii = R[i, i] - c
            if bii > bval:
                bval = bii
                best = i
        n = out  # the axis, scaled in place
        for r in range(3):
            n[r] = 0.5 * (R[r, best] + R[best, r])
        n[best] = R[best, best] - c
        nn = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
        sign = 1.0
        if n[0] * ax + n[1] * ay + n[2] * az < 0.0:
            sign = -1.0
        for r in range(3):
            out[r] = sign * theta * n[r] / nn
        return
    if s < 1e-14:
        alpha = 1.0
    else:
        alpha = math.atan2(s, c) / s
    out[0] = alpha * ax
    out[1] = alpha * ay
    out[2] = alpha * az


@njit(cache=True)
def pose_from_twist_one(xi):
    """SE(3) exponential of a displacement twist ``xi = (phi, rho)`` (6,) → 4×4 pose."""
    T = np.zeros((4, 4))
    pose_from_twist_into(xi, T)
    return T


@njit(cache=True)
def pose_from_twist_into(xi, T):
    """:func:`pose_from_twist_one` written into ``T`` (4×4): no allocation."""
    phi = xi[:3]
    theta2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]
    theta = math.sqrt(theta2)
    if theta < _SMALL_ANGLE:
        a = 1.0 - theta2 / 6.0 + theta2 * theta2 / 120.0
        b = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0
        c = 1.0 / 6.0 - theta2 / 120.0 + theta2 * theta2 / 5040.0
    else:
        st = math.sin(theta)
        a = st / theta
        b = (1.0 - math.cos(theta)) / theta2
        c = (theta - st) / (theta2 * theta)
    _rodrigues_into(phi, a, b, theta2, T[:3, :3])
    rho = xi[3:]
    w10 = phi[1] * rho[2] - phi[2] * rho[1]
    w11 = phi[2] * rho[0] - phi[0] * rho[2]
    w12 = phi[0] * rho[1] - phi[1] * rho[0]
    T[0, 3] = rho[0] + b * w10 + c * (phi[1] * w12 - phi[2] * w11)
    T[1, 3] = rho[1] + b * w11 + c * (phi[2] * w10 - phi[0] * w12)
    T[2, 3] = rho[2] + b * w12 + c * (phi[0] * w11 - phi[1] * w10)
    T[3, 0] = 0.0
    T[3, 1] = 0.0
    T[3, 2] = 0.0
    T[3, 3] = 1.0


@njit(cache=True)
def twist_from_pose_one(T):
    """SE(3) logarithm of a 4×4 pose → displacement twist ``(phi, rho)`` (6,).

    ``rho = V(phi)^-1 p``; identical to the reference's ``theta * G^-1 p`` (docs/algorithms/se3.md).
    """
    out = np.empty(6)
    twist_from_pose_into(T, out)
    return out


@njit(cache=True)
def twist_from_pose_into(T, out):
    """:func:`twist_from_pose_one` written into ``out`` (6,): no allocation."""
    phi = out[:3]
    vector_from_rotation_into(T[:3, :3], phi)
    theta2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]
    theta = math.sqrt(theta2)
    p = T[:3, 3]
    if theta == 0.0:
        out[3] = p[0]
        out[4] = p[1]
        out[5] = p[2]
        return
    if theta < _SMALL_ANGLE:
        beta = 1.0 / 12.0 + theta2 / 720.0 + theta2 * theta2 / 30240.0
    else:
        half = 0.5 * theta
        beta = (1.0 - half * math.cos(half) / math.sin(half)) / theta2
    k0 = phi[1] * p[2] - phi[2] * p[1]
    k1 = phi[2] * p[0] - phi[0] * p[2]
    k2 = phi[0] * p[1] - phi[1] * p[0]
    out[3] = p[0] - 0.5 * k0 + beta * (phi[1] * k2 - phi[2] * k1)
    out[4] = p[1] - 0.5 * k1 + beta * (phi[2] * k0 - phi[0] * k2)
    out[5] = p[2] - 0.5 * k2 + beta * (phi[0] * k1 - phi[1] * k0)


@njit(cache=True)
def rotation_increment_one(A, B):
    """Rotation vector (3,) of ``R_B R_Aᵀ``: the rotation from pose A to pose B in world axes."""
    Rr = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            Rr[i, j] = B[i, 0] * A[j, 0] + B[i, 1] * A[j, 1] + B[i, 2] * A[j, 2]
    return vector_from_rotation_one(Rr)


@njit(cache=True)
def compose_one(A, B):
    """Product of two 4×4 poses (rigid transforms), written out for speed."""
    C = np.zeros((4, 4))
    compose_into(A, B, C)
    return C


@njit(cache=True)
def compose_into(A, B, C):
    """:func:`compose_one` written into ``C`` (4×4, not ``A`` or ``B``): no allocation."""
    for i in range(3):
        for j in range(3):
            C[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]
        C[i, 3] = A[i, 0] * B[0, 3] + A[i, 1] * B[1, 3] + A[i, 2] * B[2, 3] + A[i, 3]
    C[3, 0] = 0.0
    C[3, 1] = 0.0
    C[3, 2] = 0.0
    C[3, 3] = 1.0


@njit(cache=True)
def inverse_one(T):
    """Inverse of a rigid transform: ``[R^T, -R^T p]``."""
    Ti = np.zeros((4, 4))
    for i in range(3):
        for j in range(3):
            Ti[i, j] = T[j, i]
    for i in range(3):
        Ti[i, 3] = -(T[0, i] * T[0, 3] + T[1, i] * T[1, 3] + T[2, i] * T[2, 3])
    Ti[3, 3] = 1.0
    return Ti


@njit(cache=True)
def relative_one(A, B):
    """``A^-1 B`` for rigid transforms, without forming the inverse."""
    C = np.zeros((4, 4))
    relative_into(A, B, C)
    return C


@njit(cache=True)
def relative_into(A, B, C):
    """:func:`relative_one` written into ``C`` (4×4, not ``A`` or ``B``): no allocation."""
    for i in range(3):
        for j in range(3):
            C[i, j] = A[0, i] * B[0, j] + A[1, i] * B[1, j] + A[2, i] * B[2, j]
        C[i, 3] = (
            A[0, i] * (B[0, 3] - A[0, 3])
            + A[1, i] * (B[1, 3] - A[1, 3])
            + A[2, i] * (B[2, 3] - A[2, 3])
        )
    C[3, 0] = 0.0
    C[3, 1] = 0.0
    C[3, 2] = 0.0
    C[3, 3] = 1.0


@njit(cache=True)
def sclerp_one(A, B, alpha):
    """Screw linear interpolation ``A exp(alpha log(A^-1 B))`` (constant body twist)."""
    out = np.empty((4, 4))
    sclerp_into(A, B, alpha, out, np.empty((4, 4)), np.empty(6))
    return out


@njit(cache=True)
def sclerp_into(A, B, alpha, out, work, xi):
    """:func:`sclerp_one` written into ``out`` (4×4) with scratch ``work`` (4×4) and ``xi``
    (6,): no allocation."""
    relative_into(A, B, work)
    twist_from_pose_into(work, xi)
    for r in range(6):
        xi[r] = alpha * xi[r]
    pose_from_twist_into(xi, work)
    compose_into(A, work, out)


@njit(cache=True)
def matrix_from_quaternion_one(q):
    """Rotation matrix of a quaternion ``(w, x, y, z)``; the quaternion is normalized first."""
    R = np.empty((3, 3))
    matrix_from_quaternion_into(q, R)
    return R


@njit(cache=True)
def matrix_from_quaternion_into(q, R):
    """:func:`matrix_from_quaternion_one` written into ``R`` (3×3): no allocation."""
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    w = q[0] / n
    x = q[1] / n
    y = q[2] / n
    z = q[3] / n
    R[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    R[0, 1] = 2.0 * (x * y - w * z)
    R[0, 2] = 2.0 * (x * z + w * y)
    R[1, 0] = 2.0 * (x * y + w * z)
    R[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    R[1, 2] = 2.0 * (y * z - w * x)
    R[2, 0] = 2.0 * (x * z - w * y)
    R[2, 1] = 2.0 * (y * z + w * x)
    R[2, 2] = 1.0 - 2.0 * (x * x + y * y)


@njit(cache=True)
def quaternion_from_matrix_one(R):
    """Quaternion ``(w, x, y, z)`` with ``w >= 0`` of a rotation matrix (the reference's algorithm,
    docs/algorithms/se3.md)."""
    tr1 = R[0, 0] + R[1, 1] + R[2, 2] + 1.0
    w = 0.5 * math.sqrt(max(tr1, 0.0))
    k0 = np.empty(3)
    k0[0] = R[2, 1] - R[1, 2]
    k0[1] = R[0, 2] - R[2, 0]
    k0[2] = R[1, 0] - R[0, 1]
    k1 = np.empty(3)
    if R[0, 0] >= R[1, 1] and R[0, 0] >= R[2, 2]:
        k1[0] = R[0, 0] - R[1, 1] - R[2, 2] + 1.0
        k1[1] = R[1, 0] + R[0, 1]
        k1[2] = R[2, 0] + R[0, 2]
        idx = 0
    elif R[1, 1] >= R[2, 2]:
        k1[0] = R[1, 0] + R[0, 1]
        k1[1] = R[1, 1] - R[0, 0] - R[2, 2] + 1.0
        k1[2] = R[2, 1] + R[1, 2]
        idx = 1
    else:
        k1[0] = R[2, 0] + R[0, 2]
        k1[1] = R[2, 1] + R[1, 2]
        k1[2] = R[2, 2] - R[0, 0] - R[1, 1] + 1.0
        idx = 2
    sgn = 1.0 if k0[idx] >= 0.0 else -1.0
    k = k0 + sgn * k1
    nk = math.sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2])
    q = np.zeros(4)
    if nk == 0.0:
        q[0] = 1.0
        return q
    sv = math.sqrt(max(1.0 - w * w, 0.0)) / nk
    q[0] = w
    q[1] = sv * k[0]
    q[2] = sv * k[1]
    q[3] = sv * k[2]
    return q


# --------------------------------------------------------------------------------------------------
# batch loops (compiled)
# --------------------------------------------------------------------------------------------------


@njit(cache=True)
def rotation_from_vector_batch(phi):
    out = np.empty((phi.shape[0], 3, 3))
    for i in range(phi.shape[0]):
        out[i] = rotation_from_vector_one(phi[i])
    return out


@njit(cache=True)
def vector_from_rotation_batch(R):
    out = np.empty((R.shape[0], 3))
    for i in range(R.shape[0]):
        out[i] = vector_from_rotation_one(R[i])
    return out


@njit(cache=True)
def pose_from_twist_batch(xi):
    out = np.empty((xi.shape[0], 4, 4))
    for i in range(xi.shape[0]):
        out[i] = pose_from_twist_one(xi[i])
    return out


@njit(cache=True)
def twist_from_pose_batch(T):
    out = np.empty((T.shape[0], 6))
    for i in range(T.shape[0]):
        out[i] = twist_from_pose_one(T[i])
    return out


@njit(cache=True)
def matrix_from_quaternion_batch(q):
    out = np.empty((q.shape[0], 3, 3))
    for i in range(q.shape[0]):
        matrix_from_quaternion_into(q[i], out[i])
    return out


@njit(cache=True)
def quaternion_from_matrix_batch(R):
    out = np.empty((R.shape[0], 4))
    for i in range(R.shape[0]):
        out[i] = quaternion_from_matrix_one(R[i])
    return out


@njit(cache=True)
def sign_flip_one(q, ref, threshold):
    """The sign-continuity rule: True when ``q`` is farther than ``threshold`` from ``ref`` (R^4).

    Every sign correction of the package goes through this rule; ``threshold`` is
    :data:`~framefree.core.se3.REFERENCE_SIGN_THRESHOLD` in the reference batch path and
    :data:`~framefree.core.se3.NEAREST_SIGN`
    (negate when ``q · ref < 0``) in the streaming paths.
    """
    d = 0.0
    for c in range(4):
        diff = q[c] - ref[c]
        d += diff * diff
    return d > threshold * threshold


@njit(cache=True)
def continuity_inplace(q, threshold):
    """Negate every quaternion farther than ``threshold`` (Euclidean, R^4) from its predecessor."""
    for i in range(1, q.shape[0]):
        if sign_flip_one(q[i], q[i - 1], threshold):
            for c in range(4):
                q[i, c] = -q[i, c]


@njit(cache=True)
def sclerp_batch(A, B, alpha):
    out = np.empty((A.shape[0], 4, 4))
    for i in range(A.shape[0]):
        out[i] = sclerp_one(A[i], B[i], alpha[i])
    return out


@njit(cache=True)
def interpolate_poses_kernel(x, T, xq):
    """Reference ``interpT``: ScLERP of poses ``T`` (n,4,4) at knots ``x`` (n,) for sorted ``xq``.

    The segment index only walks forward; equal knots return the left pose (docs/algorithms/se3.md).
    """
    n = x.shape[0]
    out = np.empty((xq.shape[0], 4, 4))
    work = np.empty((4, 4))
    xi = np.empty(6)
    j = 0
    for i in range(xq.shape[0]):
        while j < n - 2 and xq[i] > x[j + 1]:
            j += 1
        if x[j + 1] == x[j]:
            out[i] = T[j]
        else:
            alpha = (xq[i] - x[j]) / (x[j + 1] - x[j])
            sclerp_into(T[j], T[j + 1], alpha, out[i], work, xi)
    return out


@njit(cache=True)
def central_spatial_twists_kernel(T, ds):
    """Central spatial twists ``log(T_{k+1} T_{k-1}^-1) / (2 ds)`` with the reference boundary quirk."""
    n = T.shape[0]
    out = np.empty((n, 6))
    for k in range(n):
        lo = k - 1 if k > 0 else 0
        hi = k + 1 if k < n - 1 else n - 1
        D = compose_one(T[hi], inverse_one(T[lo]))
        xi = twist_from_pose_one(D)
        for c in range(6):
            out[k, c] = xi[c] / (2.0 * ds)
    return out


@njit(cache=True)
def relative_twists_kernel(T):
    n = T.shape[0]
    out = np.empty((max(n - 1, 0), 6))
    for k in range(n - 1):
        out[k] = twist_from_pose_one(relative_one(T[k], T[k + 1]))
    return out
