"""Shared fixtures: a fresh YADE-style scene for every test."""

from __future__ import annotations

import json
import math
import pathlib
import sys

import numpy as np
import pytest

REFERENCE = pathlib.Path(__file__).parent / "reference" / "yade"


@pytest.fixture
def yade():
    """The ``granum.yade`` namespace with an empty scene (``yade.O``)."""
    import granum.yade as y

    y.O.reset()
    y.O._namespace = None
    yield y
    y.O.pause()
    y.O.reset()


def reference(topic: str) -> dict:
    """Reference data produced by real YADE (see tests/reference/yade/README.md)."""
    return json.loads((REFERENCE / f"{topic}.json").read_text())


def granum_reference_run(script: str) -> dict:
    """What the YADE reference script ``script`` (in tests/reference/yade) records when granum runs it unmodified:
    its ``_common.dump`` is captured instead of writing the JSON file."""
    import granum.yade as y

    sys.path.insert(0, str(REFERENCE))
    import _common

    out: dict = {}
    saved = _common.dump
    try:
        _common.dump = lambda topic, data: out.update(data)
        ns: dict = {}
        exec("from granum.yade import *", ns)
        exec(compile((REFERENCE / script).read_text(), script, "exec"), ns)
    finally:
        _common.dump = saved
        sys.path.remove(str(REFERENCE))
        y.O.reset()
    return out


def resumed_run_matches(y, scene, steps, path, probe=lambda: None):
    """Build ``scene()`` and run ``steps`` steps; build it again, run half of them, save to ``path``, load and
    run the rest: every body's position, velocity and angular velocity, and ``probe()``, must be the same bits."""

    def state():
        return np.array([list(b.state.pos) + list(b.state.vel) + list(b.state.angVel) for b in y.O.bodies]), probe()

    scene()
    y.O.run(steps, True)
    whole, whole_probe = state()
    scene()
    y.O.run(steps // 2, True)
    y.O.save(str(path))
    y.O.load(str(path))
    y.O.run(steps - steps // 2, True)
    resumed, resumed_probe = state()
    np.testing.assert_array_equal(resumed, whole)
    assert resumed_probe == whole_probe


def frict_engines(y, gravity=(0, 0, 0), damping=0.0, bounds=None, geoms=None):
    """The engine list of the tutorials: collider, frictional contacts, Newton."""
    return [
        y.ForceResetter(),
        y.InsertionSortCollider(bounds or [y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb(), y.Bo1_Wall_Aabb(),
                                           y.Bo1_Box_Aabb()]),
        y.InteractionLoop(
            geoms or [y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom(), y.Ig2_Wall_Sphere_ScGeom(),
                      y.Ig2_Box_Sphere_ScGeom()],
            [y.Ip2_FrictMat_FrictMat_FrictPhys()],
            [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
        y.NewtonIntegrator(gravity=gravity, damping=damping),
    ]


def viscel_engines(y):
    """Spheres with the visco-elastic law (ViscElMat): collider, InteractionLoop, Newton without gravity."""
    return [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
            y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                              [y.Law2_ScGeom_ViscElPhys_Basic()]),
            y.NewtonIntegrator()]


def factory_in_box(y, rate_per_step=1.5, r_min=0.004, r_max=0.006, force_full_runs=False, half_width=0.08,
                   height=0.15):
    """A seeded BoxFactory throwing spheres down into a 0.2 m facet box from ``height`` (the first land after about
    700 steps from the default height); returns the factory."""
    O = y.O
    mat = O.materials.append(y.FrictMat(young=1e6, poisson=0.3, frictionAngle=math.radians(30), density=2600))
    O.bodies.append(y.geom.facetBox((0, 0, 0.1), (0.1, 0.1, 0.1), material=mat))
    O.dt = 1e-4
    mean_mass = 2600 * 4 / 3 * math.pi * 0.25 * (r_min + r_max) * (r_min ** 2 + r_max ** 2)
    factory = y.BoxFactory(center=(0, 0, height), extents=(half_width, half_width, 0.01), rMin=r_min, rMax=r_max,
                           vMin=1.5, vMax=1.5, normal=(0, 0, -1), massFlowRate=rate_per_step * mean_mass / O.dt,
                           maxParticles=-1, materialId=mat, seed=11, label="factory")
    O.engines = [
        y.ForceResetter(),
        y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb()]),
        y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom()],
                          [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
        y.NewtonIntegrator(damping=0.2, gravity=(0, 0, -9.81)),
        factory,
    ]
    if force_full_runs:   # setting a body's mask makes the collider run in full at the next step
        O.engines = O.engines + [y.PyRunner(iterPeriod=1, command="O.bodies[0].mask = O.bodies[0].mask")]
    return factory
