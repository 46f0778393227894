"""The article's four verification cases, set up with the public API (used by examples/idem and the tests).

Each function builds the bodies, runs the solver and returns a dict of per-step series
(``t`` [s] is the time at the end of each step) plus the solver itself. The article gives the
box (2.0 m x 1.0 m x 2.0 m) but not its particles nor the bodies of the collision cases
([A14]); here every body is that box as a lattice of particles with ``spacing`` 0.25 m
(9 x 5 x 9 = 405 particles, 258 on the surface), mass from density 1000 kg/m^3 (the results
do not depend on it).
"""

from __future__ import annotations

import math

import numpy as np

from granum.idem.bodies import box_body, plane_body
from granum.idem.solver import IDEMSolver

BOX = (2.0, 1.0, 2.0)
SLOPE = math.radians(30.0)


def falling_box(e=0.5, mu=0.3, alpha0=15.0, dt=5e-4, h=0.6, duration=1.5, spacing=0.25, **kw):
    """V1: the box dropped flat from ``h`` [m] (bottom face to floor) on a fixed floor.

    mu is not given by the article; it has no effect here (no tangential motion). Series:
    ``vz`` vertical velocity, ``z`` height of the centre above its resting height, ``wmax`` the
    largest |angular velocity| component, ``energy`` kinetic + potential [J].
    """
    s = IDEMSolver(e=e, mu=mu, alpha0=alpha0, dt=dt, **kw)
    s.add(plane_body((0.0, 0.0, 0.0), (BOX[0] + 2.0, BOX[1] + 2.0), spacing))
    box = s.bodies[s.add(box_body((0.0, 0.0, h + 0.5 * BOX[2]), BOX, spacing))]
    rec = {"t": [], "vz": [], "z": [], "wmax": [], "energy": []}

    def sample(solver):
        rec["t"].append(solver.time)
        rec["vz"].append(box.vel[2])
        rec["z"].append(box.pos[2] - 0.5 * BOX[2])
        rec["wmax"].append(float(np.abs(np.asarray(box.angVel)).max()))
        rec["energy"].append(solver.kinetic() + solver.potential())

    s.run(int(round(duration / dt)), sample, every=1)
    return {k: np.array(v) for k, v in rec.items()} | {"solver": s}


def slope(mu, theta=SLOPE, e=0.0, alpha0=15.0, dt=5e-4, duration=1.0, spacing=0.25, **kw):
    """V2: the box released at rest on a fixed plane inclined by ``theta`` [rad], friction ``mu``.

    The plane descends towards +x; the box is turned by the same angle so that a face lies on it.
    Series: ``v`` velocity along the slope (down positive), ``vn`` velocity along the slope normal,
    ``wmax`` largest |angular velocity| component.
    """
    s = IDEMSolver(e=e, mu=mu, alpha0=alpha0, dt=dt, **kw)
    q = ((0.0, 1.0, 0.0), theta)  # rotation about y: local z -> the slope normal, local x -> down the slope
    down = np.array([math.cos(theta), 0.0, -math.sin(theta)])
    normal = np.array([math.sin(theta), 0.0, math.cos(theta)])
    travel = 0.5 * 9.81 * duration ** 2  # upper bound of the distance slid
    length = BOX[0] + travel + 2.0
    s.add(plane_body(np.zeros(3), (length, BOX[1] + 2.0), spacing, ori=q))
    start = -0.5 * length + 1.0 + 0.5 * BOX[0]
    box = s.bodies[s.add(box_body(start * down + 0.5 * BOX[2] * normal, BOX, spacing, ori=q))]
    rec = {"t": [], "v": [], "vn": [], "wmax": []}

    def sample(solver):
        v = np.asarray(box.vel)
        rec["t"].append(solver.time)
        rec["v"].append(float(v @ down))
        rec["vn"].append(float(v @ normal))
        rec["wmax"].append(float(np.abs(np.asarray(box.angVel)).max()))

    s.run(int(round(duration / dt)), sample, every=1)
    return {k: np.array(v) for k, v in rec.items()} | {"solver": s}


def _row(n, e, mu, alpha0, dt, v0, gap, duration, spacing, **kw):
    """``n`` boxes along x: the first at ``v0`` [m/s] ``gap`` [m] behind the others, which touch and
    rest (no gravity, no floor: the article's cradle turns gravity off, and with mu = 0 a floor
    only carries the weight). Series: ``v`` (steps, n) x-velocities, ``p`` total momentum (3,),
    ``L`` angular momentum (3,), ``ke`` kinetic energy."""
    s = IDEMSolver(e=e, mu=mu, alpha0=alpha0, dt=dt, gravity=(0.0, 0.0, 0.0), **kw)
    L = BOX[0]
    boxes = [s.bodies[s.add(box_body((-L - gap, 0.0, 0.0), BOX, spacing))]]
    for k in range(1, n):
        boxes.append(s.bodies[s.add(box_body(((k - 1) * L, 0.0, 0.0), BOX, spacing))])
    boxes[0].vel = (v0, 0.0, 0.0)
    rec = {"t": [], "v": [], "p": [], "L": [], "ke": []}

    def sample(solver):
        rec["t"].append(solver.time)
        rec["v"].append([b.vel[0] for b in boxes])
        rec["p"].append(solver.momentum())
        rec["L"].append(solver.angular_momentum())
        rec["ke"].append(solver.kinetic())

    rec0 = {"p0": s.momentum(), "ke0": s.kinetic(), "L0": s.angular_momentum()}
    s.run(int(round(duration / dt)), sample, every=1)
    return {k: np.array(v) for k, v in rec.items()} | rec0 | {"solver": s}


def two_body(e=0.5, mu=0.0, alpha0=150.0, dt=5e-4, v0=2.0, gap=0.1, duration=0.3, spacing=0.25, **kw):
    """V3: box A at ``v0`` hits box B at rest. Adds ``vA``, ``vB`` to the series of :func:`_row`."""
    out = _row(2, e, mu, alpha0, dt, v0, gap, duration, spacing, **kw)
    out["vA"] = out["v"][:, 0]
    out["vB"] = out["v"][:, 1]
    return out


def cradle(n=10, e=1.0, mu=0.0, alpha0=150.0, dt=5e-4, v0=1.0, gap=0.1, duration=0.4, spacing=0.25, **kw):
    """V4: a striker at ``v0`` hits a row of n - 1 touching boxes at rest. Adds ``v_first``, ``v_last``."""
    out = _row(n, e, mu, alpha0, dt, v0, gap, duration, spacing, **kw)
    out["v_first"] = out["v"][:, 0]
    out["v_last"] = out["v"][:, -1]
    return out
