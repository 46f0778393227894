"""The unbalanced force with clumps against real YADE (tests/reference/yade/unbalanced_clump.py): a clump counts
its members' forces also before NewtonIntegrator has gathered them (a TriaxialCompressionEngine placed before
NewtonIntegrator would otherwise see clumps without force and end its compaction at once)."""

from __future__ import annotations

import builtins
import math

import pytest
from conftest import reference

REF = reference("unbalanced_clump")


def test_utils_unbalanced_force_before_and_after_newton(yade):
    """utils.unbalancedForce from PyRunners before and after NewtonIntegrator: YADE's 0.5 both times."""
    y = yade
    rows = []
    y.O.materials.append(y.FrictMat(young=6e6, poisson=.8, frictionAngle=.5, density=2600))
    y.O.bodies.append(y.sphere((0.4, 0, 0), .2, fixed=True))
    y.O.bodies.appendClumped([y.sphere((.45, 0, .38), .2), y.sphere((.55, .2, .55), .17)])
    y.O.bodies.append(y.sphere((-.3, 0, 0), .2))

    builtins._granum_unbalanced = rows
    cmd = "_granum_unbalanced.append({{'iter': O.iter, 'where': {!r}, 'unbalanced': utils.unbalancedForce()}})"
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.PyRunner(iterPeriod=1, initRun=True, command=cmd.format("before")),
                   y.NewtonIntegrator(damping=0, gravity=(0, 0, 0)),
                   y.PyRunner(iterPeriod=1, initRun=True, command=cmd.format("after"))]
    y.O.dt = 2e-3
    try:
        y.O.step()
        y.O.step()
    finally:
        del builtins._granum_unbalanced
    assert len(rows) == len(REF["midstep"])
    for got, ref in zip(rows, REF["midstep"], strict=True):
        assert (got["iter"], got["where"]) == (ref["iter"], ref["where"])
        assert got["unbalanced"] == pytest.approx(ref["unbalanced"], rel=1e-12)


def test_triaxial_engine_unbalanced_force_with_clumps(yade):
    """TriaxialCompressionEngine.UnbalancedForce over 30 steps of 8 clumps squeezed by the walls, and the state
    (still compacting), as YADE's (without the members' forces the engine would see about 0). Tolerance 5 %:
    the first 4 steps agree to 1e-6, then the values part (6.5e-5 at step 5, 2.5e-3 at step 7, measured; the
    clumps' trajectories differ slightly from YADE's, cause not identified, see test_timestepper_clump)."""
    y = yade
    y.O.materials.append(y.FrictMat(young=6e6, poisson=.4, frictionAngle=0, density=2600))
    for x in (0, 1):
        for yy in (0, 1):
            for z in (0, 1):
                y.O.bodies.appendClumped([y.sphere((x, yy, z), .3), y.sphere((x + .25, yy + .1 * z, z + .2), .3)])
    wid = y.O.bodies.append(y.aabbWalls())
    t = y.TriaxialCompressionEngine(wall_left_id=wid[0], wall_right_id=wid[1], wall_bottom_id=wid[2],
                                    wall_top_id=wid[3], wall_back_id=wid[4], wall_front_id=wid[5],
                                    internalCompaction=False, sigmaIsoCompaction=-1e4, sigmaLateralConfinement=-1e4,
                                    max_vel=1, StabilityCriterion=.01, testEquilibriumInterval=1)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Box_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Box_Sphere_ScGeom()],
                                     [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   t, y.NewtonIntegrator(damping=.4)]
    y.O.dt = 1e-3
    for k, ref in enumerate(REF["triax"]):
        y.O.step()
        assert y.O.interactions.countReal() == ref["contacts"], f"step {k + 1}"
        assert t.currentState == ref["state"], f"step {k + 1}"
        if math.isnan(ref["UnbalancedForce"]):
            assert math.isnan(t.UnbalancedForce), f"step {k + 1}"
        else:
            assert t.UnbalancedForce == pytest.approx(ref["UnbalancedForce"], rel=0.05), f"step {k + 1}"
