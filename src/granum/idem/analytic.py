"""Analytic solutions of the article's four verification cases (``shared/reference/idem.md`` §11).

Plain NumPy, used by ``examples/idem`` and the tests. g = 9.81 m/s^2 unless given ([A13]).
"""

from __future__ import annotations

import math

import numpy as np

G = 9.81


def bounce_impacts(h: float, e: float, g: float = G, n: int = 50):
    """Impact times t_k [s] and impact speeds u_k [m/s] (k = 0..n-1) of a body dropped from rest
    with its lowest point at height ``h`` [m] above a floor, restitution ``e``.

    u_0 = sqrt(2 g h) at t_0 = sqrt(2 h / g); each rebound leaves at e u_k and lands again after the
    flight 2 e u_k / g, so u_{k+1} = e u_k and t_{k+1} = t_k + 2 e u_k / g (accumulating at
    t_inf = t_0 (1 + 2 e / (1 - e)) for e < 1).
    """
    u0 = math.sqrt(2.0 * g * h)
    t = [math.sqrt(2.0 * h / g)]
    u = [u0]
    for _ in range(n - 1):
        t.append(t[-1] + 2.0 * e * u[-1] / g)
        u.append(e * u[-1])
    return np.array(t), np.array(u)


def bounce_velocity(t, h: float, e: float, g: float = G, n: int = 200):
    """Vertical velocity v(t) [m/s] of the bouncing body (up positive): -g t before the first impact,
    e u_k - g (t - t_k) after impact k, and 0 once the impacts have accumulated (t >= t_inf)."""
    t = np.asarray(t, dtype=np.float64)
    times, speeds = bounce_impacts(h, e, g, n)
    v = -g * t
    for tk, uk in zip(times, speeds, strict=True):
        after = t >= tk
        v = np.where(after, e * uk - g * (t - tk), v)
    if e < 1.0:
        t_inf = times[0] * (1.0 + 2.0 * e / (1.0 - e))
        v = np.where(t >= t_inf, 0.0, v)
    return v


def slope_speed(t, theta: float, mu: float, g: float = G):
    """Speed along a slope of angle ``theta`` [rad] of a block starting at rest, Coulomb friction ``mu``:
    v = g (sin theta - mu cos theta) t when mu < tan theta (sliding), 0 otherwise."""
    a = g * (math.sin(theta) - mu * math.cos(theta))
    return np.maximum(a, 0.0) * np.asarray(t, dtype=np.float64)


def collision_velocities(m_a: float, m_b: float, v_a: float, v_b: float, e: float):
    """Velocities after a 1-D impact with restitution ``e`` (momentum conserved, relative velocity
    reversed and scaled by e): V_A = ((m_A - e m_B) v_A + (1 + e) m_B v_B) / (m_A + m_B), and
    V_B = ((1 + e) m_A v_A + (m_B - e m_A) v_B) / (m_A + m_B)."""
    s = m_a + m_b
    return ((m_a - e * m_b) * v_a + (1.0 + e) * m_b * v_b) / s, ((1.0 + e) * m_a * v_a + (m_b - e * m_a) * v_b) / s


def cradle_velocities(n: int, v0: float):
    """Final velocities of a row of ``n`` equal bodies, the first hitting the others at ``v0``, e = 1:
    the striker and the middle bodies stop, the last one leaves at v0 (a sequence of binary impacts)."""
    out = np.zeros(n)
    out[-1] = v0
    return out
