"""Edits of ``yade.utils``: calming, placing and recolouring bodies, finding engines, random orientations.

Edits over many bodies write the scene's arrays at once; edits of one body go
through its :class:`~granum.yade.bodies.State`/shape view (same checks as a script).
"""

from __future__ import annotations

import math
import random

import numpy as np

from granum.core.bodies import DOF_ALL
from granum.core.shapes import ShapeKind
from granum.mathtypes import Quaternion, as_vec3
from granum.yade.omega import O

__all__ = [
    "randomOrientation", "calm", "setRefSe3", "shiftBodies", "setBodyPosition", "setBodyVelocity",
    "setBodyOrientation", "setBodyAngularVelocity", "setBodyColor", "highlightNone", "wireAll", "wireNone",
    "wireNoSpheres", "randomizeColors", "typedEngine", "replaceCollider",
]


def randomOrientation():
    """A random orientation, uniformly distributed over rotations (Shoemake's method).

    Draws from Python's :mod:`random`, so ``random.seed()`` makes it repeatable.
    """
    u1, u2, u3 = random.random(), random.random(), random.random()
    a, b = math.sqrt(1.0 - u1), math.sqrt(u1)
    t2, t3 = 2.0 * math.pi * u2, 2.0 * math.pi * u3
    return Quaternion(a * math.cos(t2), a * math.sin(t2), b * math.sin(t3), b * math.cos(t3))


def _live(mask: int = -1) -> np.ndarray:
    b = O._scene.bodies
    n = b.count
    sel = b.alive[:n].copy()
    if mask != -1:
        sel &= (b.mask[:n] & mask) != 0
    return np.nonzero(sel)[0]


def calm(mask=-1) -> None:
    """Zero the velocity, angular velocity and angular momentum of the bodies whose mask shares a bit
    with ``mask`` (-1: all)."""
    b = O._scene.bodies
    ids = _live(mask)
    b.vel[ids] = 0.0
    b.ang_vel[ids] = 0.0
    if b.stored("ang_mom").shape[0]:
        b.ang_mom[ids] = 0.0


def setRefSe3() -> None:
    """Reference position and orientation of every body := current ones."""
    b = O._scene.bodies
    ids = _live()
    b.ref_pos[ids] = b.pos[ids]
    b.ref_ori[ids] = b.ori[ids]


def shiftBodies(ids, shift) -> float:
    """Move bodies ``ids`` by ``shift`` [m], velocities untouched; returns 1.0 as YADE does."""
    d = as_vec3(shift)
    for i in ids:
        st = O.bodies[i].state
        st.pos = np.asarray(st.pos._a) + d
    return 1.0


def _set_axes(current, value, axis: str) -> np.ndarray:
    """``current`` with the components named in ``axis`` ('x', 'y', 'z' letters) taken from ``value``."""
    unknown = set(axis) - set("xyz")
    if unknown:
        raise ValueError(f"axis must name components among 'xyz', got {axis!r}")
    out = np.array(current._a, dtype=float)
    v = as_vec3(value)
    for k, name in enumerate("xyz"):
        if name in axis:
            out[k] = v[k]
    return out


def setBodyPosition(id, pos, axis="xyz") -> None:
    """Set the components ``axis`` of body ``id``'s position [m]."""
    st = O.bodies[id].state
    st.pos = _set_axes(st.pos, pos, axis)


def setBodyVelocity(id, vel, axis="xyz") -> None:
    """Set the components ``axis`` of body ``id``'s velocity [m/s]."""
    st = O.bodies[id].state
    st.vel = _set_axes(st.vel, vel, axis)


def setBodyOrientation(id, ori) -> None:
    """Set body ``id``'s orientation."""
    O.bodies[id].state.ori = ori


def setBodyAngularVelocity(id, angVel) -> None:
    """Set body ``id``'s angular velocity [rad/s]."""
    O.bodies[id].state.angVel = angVel


def setBodyColor(id, color) -> None:
    """Set body ``id``'s display colour (RGB in [0, 1])."""
    O.bodies[id].shape.color = color


def highlightNone() -> None:
    """Clear the highlight flag of every body."""
    O._scene.bodies.highlight[_live()] = False


def wireAll() -> None:
    """Draw every body as a wire frame."""
    O._scene.bodies.wire[_live()] = True


def wireNone() -> None:
    """Draw every body solid."""
    O._scene.bodies.wire[_live()] = False


def wireNoSpheres() -> None:
    """Draw every body that is not a sphere as a wire frame."""
    b = O._scene.bodies
    ids = _live()
    b.wire[ids[b.shape_kind[ids] != ShapeKind.SPHERE]] = True


def randomizeColors(onlyDynamic=False) -> None:
    """Give bodies random colours (RGB uniform in [0, 1)); with ``onlyDynamic`` only the dynamic ones."""
    b = O._scene.bodies
    ids = _live()
    if onlyDynamic:
        ids = ids[b.blocked[ids] != DOF_ALL]
    b.color[ids] = [[random.random() for _ in range(3)] for _ in ids]


def typedEngine(name):
    """The first engine of O.engines whose class is called ``name``; IndexError if none."""
    found = [e for e in O.engines if type(e).__name__ == name]
    if not found:
        raise IndexError(f"typedEngine: no {name} in O.engines")
    return found[0]


def replaceCollider(colliderEngine) -> None:
    """Put ``colliderEngine`` in place of the collider of O.engines; RuntimeError if there is none."""
    from granum.engines.pipeline import InsertionSortCollider

    engines = list(O.engines)
    where = [k for k, e in enumerate(engines) if isinstance(e, InsertionSortCollider)]
    if not where:
        raise RuntimeError("replaceCollider: no collider in O.engines")
    engines[where[0]] = colliderEngine
    O.engines = engines

