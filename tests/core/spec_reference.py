"""A slow, literal transcription of the reference's algorithms for tests: resampling and progress
(docs/algorithms/progress.md), SE(3) tools (se3.md), Gaussian smoothing (smoothing.md), BILTS
(bilts.md) and the BILTS distances (dtw.md), all in docs/algorithms/.

Written independently of the package, in plain numpy/scipy and in the reference's own terms
(1-based formulas shifted, MATLAB-style helpers): matrix exponentials through ``scipy.linalg.expm``
as the reference's ``interpT`` does, the pose logarithm through the ``G`` matrix of ``logm_pose``,
eigenvalues through LAPACK, the Kabsch rotation through an SVD. The package's compiled pipeline must
agree with it to round-off.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm


def skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]], dtype=float)


def quat2rotm(q):
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rot2quat(R):
    w = 0.5 * math.sqrt(max(np.trace(R) + 1.0, 0.0))
    k0 = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    d = np.diag(R)
    if d[0] >= d[1] and d[0] >= d[2]:
        k1, i = np.array([d[0] - d[1] - d[2] + 1, R[1, 0] + R[0, 1], R[2, 0] + R[0, 2]]), 0
    elif d[1] >= d[2]:
        k1, i = np.array([R[1, 0] + R[0, 1], d[1] - d[0] - d[2] + 1, R[2, 1] + R[1, 2]]), 1
    else:
        k1, i = np.array([R[2, 0] + R[0, 2], R[2, 1] + R[1, 2], d[2] - d[0] - d[1] + 1]), 2
    k = k0 + k1 if k0[i] >= 0 else k0 - k1
    if np.linalg.norm(k) == 0:
        return np.array([1.0, 0, 0, 0])
    return np.concatenate([[w], math.sqrt(1 - w * w) * k / np.linalg.norm(k)])


def quats_continuous(Rs):
    qs = [rot2quat(R) for R in Rs]
    for i in range(1, len(qs)):
        if np.linalg.norm(qs[i] - qs[i - 1]) > 0.5:
            qs[i] = -qs[i]
    return np.array(qs)


def logm_rot(R):
    a = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    c = min(1.0, max(-1.0, (np.trace(R) - 1) / 2))
    s = np.linalg.norm(a)
    alpha = 0.5 if s < 1e-14 else math.atan2(s, c) / (2 * s)
    W = alpha * (R - R.T)
    return np.array([W[2, 1], W[0, 2], W[1, 0]])


def logm_pose(T):
    R, p = T[:3, :3], T[:3, 3]
    phi = logm_rot(R)
    th = np.linalg.norm(phi)
    if th == 0:
        return np.concatenate([phi, p])
    G = ((np.eye(3) - R) @ skew(phi) + np.outer(phi, phi)) / th
    return np.concatenate([phi, th * np.linalg.solve(G, p)])


def twist_matrix(xi):
    X = np.zeros((4, 4))
    X[:3, :3] = skew(xi[:3])
    X[:3, 3] = xi[3:]
    return X


def interpT(x, T, xq):
    out, j = [], 0
    for v in xq:
        while j < len(x) - 2 and v > x[j + 1]:
            j += 1
        if x[j + 1] == x[j]:
            out.append(T[j])
        else:
            a = (v - x[j]) / (x[j + 1] - x[j])
            out.append(T[j] @ expm(a * twist_matrix(logm_pose(np.linalg.inv(T[j]) @ T[j + 1]))))
    return np.array(out)


def load_poses(data):
    t = data[:, 0] - data[0, 0]
    T = np.array([np.block([[quat2rotm(r[4:8]), r[1:4, None]], [0, 0, 0, 1]]) for r in data])
    n = round(1 + math.floor(t[-1] / 0.02))
    tq = np.linspace(0, t[-1], n)
    return interpT(t, T, tq)


def screw_ds(T0, T1, L):
    xi = logm_pose(np.linalg.inv(T0) @ T1)
    phi, rho = xi[:3], xi[3:]
    nphi = np.linalg.norm(phi)
    if nphi == 0:
        d1 = np.linalg.norm(rho)
    else:
        pp = np.cross(phi, rho) / nphi**2
        if np.linalg.norm(pp) > L:
            pb = L * pp / np.linalg.norm(pp)
            d1 = np.linalg.norm(rho + np.cross(phi, pb))
        else:
            d1 = abs(phi @ rho) / nphi
    return math.sqrt(L * L * nphi**2 + d1 * d1)


def smoothdata_gaussian(Y, w):
    b, f = ((w - 1) // 2, (w - 1) // 2) if w % 2 else (w // 2, w // 2 - 1)
    sigma = w / 5
    out = np.empty_like(Y)
    n = Y.shape[0]
    for k in range(n):
        lo, hi = max(0, k - b), min(n - 1, k + f)
        o = np.arange(lo, hi + 1) - k
        g = np.exp(-0.5 * (o / sigma) ** 2)
        out[k] = g @ Y[lo : hi + 1] / g.sum()
    return out


def eqr(X, p_obj, L, regularized):
    X1, X2 = X[:3], X[3:]
    q1 = X1[:, 0] / np.linalg.norm(X1[:, 0])
    u = X1[:, 1] - (X1[:, 1] @ q1) * q1
    q2 = u / np.linalg.norm(u)
    Q = np.column_stack([q1, q2, np.cross(q1, q2)])
    R1 = Q.T @ X1
    Y = Q.T @ X2
    z = Y[1, 0] / R1[0, 0]
    y = -Y[2, 0] / R1[0, 0]
    x = (Y[2, 1] + R1[0, 1] * y) / R1[1, 1]
    ps = np.array([x, y, z])
    if regularized:
        qo = Q.T @ p_obj
        d = ps - qo
        if np.linalg.norm(d) > L:
            d = L * d / np.linalg.norm(d)
        ps = qo + d
    R2 = Y - skew(ps) @ R1
    return np.vstack([R1, R2]), Q, ps


A_MIX = np.array([[0, -1, 1], [1, 0, 0], [0, 1, 0]], dtype=float)


def bilts(data, L, ds_scale, regularized, noise):
    """Descriptor (K, 24) of an (N, 8) recording; ``noise`` (50, 6) is the twist perturbation."""
    T = load_poses(data)
    s = np.concatenate([[0], np.cumsum([screw_ds(T[k], T[k + 1], L) for k in range(len(T) - 1)])])
    sq = np.linspace(0, s[-1], 50)
    Tr = interpT(s, T, sq)
    ds = s[-1] / 49
    m = min(23, max(1, math.floor(ds_scale / ds + 0.5)))
    P = Tr[:, :3, 3]
    Qt = quats_continuous(Tr[:, :3, :3])
    w = 10 if regularized else 20
    Ps = smoothdata_gaussian(P, w)
    Qs = smoothdata_gaussian(Qt, w)
    Ts = np.array(
        [np.block([[quat2rotm(q), p[:, None]], [0, 0, 0, 1]]) for p, q in zip(Ps, Qs, strict=True)]
    )
    xi = np.empty((50, 6))
    for k in range(50):
        lo, hi = max(k - 1, 0), min(k + 1, 49)
        xi[k] = logm_pose(Ts[hi] @ np.linalg.inv(Ts[lo])) / (2 * ds)
    xi = xi + noise
    rows = []
    for k in range(m, 50 - m):
        W = np.column_stack([xi[k - m], xi[k], xi[k + m]])
        Rr, _, _ = eqr(W @ A_MIX, Ps[k], L, regularized)
        F = Rr @ np.linalg.inv(A_MIX)
        F[:3] *= L
        flat = F.T.reshape(-1)
        sw = np.sqrt(np.clip(np.linalg.eigvalsh(F[:3] @ F[:3].T), 0, None))
        sv = np.sqrt(np.clip(np.linalg.eigvalsh(F[3:] @ F[3:].T), 0, None))
        rows.append(np.concatenate([flat, sw, sv]))
    return np.array(rows)


def matlab_dtw_path(X, Y):
    """X (n, F) model, Y (m, F) query -> list of (i, j) from the start, MATLAB tie rule."""
    n, m = len(X), len(Y)
    d = np.linalg.norm(X[:, None, :] - Y[None, :, :], axis=2)
    C = np.full((n + 1, m + 1), np.inf)
    C[0, 0] = 0
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            C[i, j] = d[i - 1, j - 1] + min(C[i - 1, j - 1], C[i - 1, j], C[i, j - 1])
    C = C[1:, 1:]
    i, j, path = n - 1, m - 1, [(n - 1, m - 1)]
    while i > 0 or j > 0:
        if j == 0:
            i -= 1
        elif i == 0:
            j -= 1
        else:
            cd, ci, cj = C[i - 1, j - 1], C[i - 1, j], C[i, j - 1]
            di = ci <= cj or cd <= cj
            dj = cj < ci or cd <= ci
            i -= di
            j -= dj
        path.append((i, j))
    return path[::-1], C[-1, -1]


def kabsch_svd_residual(A, B):
    U, _, Vt = np.linalg.svd(A @ B.T)
    R = Vt.T @ U.T
    if np.linalg.det(R) < 0:
        U[:, -1] *= -1
        R = Vt.T @ U.T
    return float(np.sum((R @ A - B) ** 2))


def bilts_plus_distance(model, query):
    path, _ = matlab_dtw_path(model[:, 18:], query[:, 18:])
    total = sum(
        kabsch_svd_residual(model[i, :18].reshape(6, 3).T, query[j, :18].reshape(6, 3).T)
        for i, j in path
    )
    return total / (len(model) + len(query) - 1)
