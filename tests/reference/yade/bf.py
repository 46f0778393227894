# bf: YADE's breakage functions (yade.bf) as a black box.
# - stress: stressTensor with and without the correction for a standalone sphere with three contacts
#   (two opposite, one unbalanced), one with a single oblique contact (moving, so with shear), and a
#   clump member with one contact; the bodies' net forces; checkFailure on the same bodies.
# - criterion: checkFailure on given stress tensors (stressTensor replaced by a function returning a
#   copy of the tensor: YADE's checkFailure scales the tensor it gets in place), weibull False/True,
#   for several strength pairs and Weibull parameters.
# - replace: replaceSphere of a unit sphere (default, radius_ratio 3, subparticles_mass 2000/1500/
#   1300/600/400, relative_gap .1, grow_radius 1.2, initial_packing_scale 1 and 2, a neighbour
#   sphere, an outer predicate): the new spheres (radius, mass, pos, vel) and the scene's total mass.
# - clumps: evalClump of a clump of three spheres in a line pressed on the middle one (moving at
#   (1,0,0)), of two spheres, and of three in a triangle: every body after it (id, shape, radius,
#   clumpId, mass, pos, vel), the return value and the total mass.
# - growParticle.
# Regenerate: cd tests/reference/yade && yade -n -x bf.py
# YADE 2023.02a
import sys; import os
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson
import numpy as np
import yade.bf.bf as bfm
from yade import pack

def fresh():
    """An empty scene with new engines (YADE's collider, reused after O.reset, can miss the first contacts)."""
    O.reset()
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(damping=0)]
    O.dt = 1e-6


def bodies():
    out = []
    for b in O.bodies:
        if b is None:
            continue
        out.append(tojson({'id': b.id, 'shape': type(b.shape).__name__,
                           'radius': b.shape.radius if isinstance(b.shape, Sphere) else None,
                           'clumpId': b.clumpId, 'mass': b.state.mass, 'pos': b.state.pos, 'vel': b.state.vel,
                           'dynamic': b.dynamic}))
    return out


def total_mass():
    return sum(b.state.mass for b in O.bodies if b is not None and b.dynamic and (b.isClump or b.isStandalone))


STRENGTHS = [(1e3, 5e3), (1e3, 1e4), (2e3, 5e3), (1.0, 1.0), (1.0, 2.0), (2.0, 1.0), (1.0, 1e9), (1e9, 1.0)]
WEIBULL = [dict(), dict(wei_V0=1.0), dict(wei_V0=1.0, wei_P=0.9), dict(wei_V0=1.0, wei_m=5)]


def failure(i):
    # real part: YADE's checkFailure returns a complex number when the tensor's eigenvalues are complex
    def cf(*a, **kw):
        return float(np.real(bfm.checkFailure(O.bodies[i], *a, **kw)))
    return {'%g,%g' % st: {'weibull': [cf(*st, **w) for w in WEIBULL], 'plain': cf(*st, weibull=False),
                           'plain_nocorr': cf(*st, weibull=False, stress_correction=False)}
            for st in STRENGTHS}


def stress(i):
    return {'stress': np.asarray(bfm.stressTensor(O.bodies[i]), dtype=float).tolist(),
            'stress_nocorr': np.asarray(bfm.stressTensor(O.bodies[i], stress_correction=False), dtype=float).tolist(),
            'force': tojson(Vector3(O.forces.f(i))), 'failure': failure(i)}


out = {}
# ---------------------------------------------------------------- stress
st = {}
fresh()
s = O.bodies.append(sphere((0, 0, 0), 1))
O.bodies.append([sphere((1.9, 0, 0), 1, fixed=True), sphere((-1.9, 0, 0), 1, fixed=True),
                 sphere((0, 1.95, 0), 1, fixed=True)])
O.step()
st['three_contacts'] = stress(s)
st['three_contacts']['bodies'] = bodies()
fresh()
s = O.bodies.append(sphere((0, 0, 0), .5))
O.bodies.append(sphere((0.6, 0.5, 0.2), .4, fixed=True))
O.bodies[s].state.vel = (0, 0, 1)
O.bodies[s].state.angVel = (0, 3, 0)
O.step()
O.step()
st['oblique_shear'] = stress(s)
st['oblique_shear']['bodies'] = bodies()
fresh()
cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), .5), sphere((0.6, 0, 0), .4)])
O.bodies.append(sphere((-0.3, 0.8, 0.1), .4, fixed=True))
O.step()
st['clump_member'] = stress(ids[0])
st['clump_member_without_contact'] = stress(ids[1])
st['clump_member']['bodies'] = bodies()
out['stress'] = st

# ---------------------------------------------------------------- criterion on given tensors
crit = []
fresh()
s = O.bodies.append(sphere((0, 0, 0), .5))
TENSORS = [np.diag([3., -1, -5]), np.diag([3., 2, 1]), np.diag([-1., -2, -3]), np.diag([2., 0, 0]),
           np.diag([1., 0, 0]), np.diag([1.0000001, 0, 0]), np.array([[0, 2., 0], [2, 0, 0], [0, 0, 0]]),
           np.array([[0, 2., 0], [0, 0, 0], [0, 0, 0]]), np.array([[-3., 1, .5], [1, 2, 0], [.5, 0, -1]])]
real_stress = bfm.stressTensor
for M in TENSORS:
    bfm.stressTensor = lambda b, stress_correction=True, M=M: M.copy()
    crit.append({'tensor': M.tolist(), 'failure': failure(s)})
bfm.stressTensor = real_stress
out['criterion'] = {'radius': 0.5, 'cases': crit}

# ---------------------------------------------------------------- replaceSphere
rep = {}
CASES = {
    'default': dict(), 'radius_ratio_3': dict(radius_ratio=3), 'mass_2000': dict(subparticles_mass=2000.),
    'mass_1500': dict(subparticles_mass=1500.), 'mass_1300': dict(subparticles_mass=1300.),
    'mass_600': dict(subparticles_mass=600.), 'mass_400': dict(subparticles_mass=400.),
    'gap_0.1': dict(relative_gap=0.1), 'grow_1.2': dict(grow_radius=1.2),
    'grow_1.5_gap_0.1': dict(grow_radius=1.5, relative_gap=0.1),
    'scale_1': dict(initial_packing_scale=1.0), 'scale_2': dict(initial_packing_scale=2.0),
    'neighbour': dict(), 'neighbour_not_searched': dict(search_for_neighbours=False),
    'neighbour_given': dict(neighbours_ids=[1], search_for_neighbours=False),
    'outer_predicate': dict(outer_predicate=pack.inAlignedBox((-5, -5, -0.2), (5, 5, 5))),
    'outer_predicate_scaled': dict(outer_predicate=pack.inAlignedBox((-5, -5, 0.7), (5, 5, 5))),
}
for name, kw in CASES.items():
    fresh()
    s = O.bodies.append(sphere((0, 0, 0), 1))
    O.bodies[s].state.vel = (1, 2, 3)
    O.bodies[s].state.angVel = (0, 0, 5)
    if name.startswith('neighbour'):
        O.bodies.append(sphere((1.5, 0, 0), 1))
    m0 = total_mass()
    ret = bfm.replaceSphere(s, **kw)
    rep[name] = {'kw': {k: (v if not hasattr(v, 'aabb') else repr(type(v).__name__)) for k, v in kw.items()},
                 'returned': tojson(ret), 'erased': O.bodies[s] is None, 'len': len(O.bodies),
                 'mass_before': m0, 'mass_after': total_mass(), 'bodies': bodies()}
out['replace'] = rep

# ---------------------------------------------------------------- evalClump
clumps = {}
SCENES = {
    'line_middle': ([((0, 0, 0), 1), ((1.5, 0, 0), 1), ((3, 0, 0), 1)], [((1.5, 1.9, 0), 1), ((1.5, -1.9, 0), 1)]),
    'two_members': ([((0, 0, 0), 1), ((1.5, 0, 0), 1)], [((1.5, 1.9, 0), 1), ((1.5, -1.9, 0), 1)]),
    'triangle': ([((0, 0, 0), 1), ((1.5, 0, 0), 1), ((0.75, 1.2, 0), 1)], [((-1.9, 0, 0), 1), ((0, 0, 1.9), 1)]),
}
for name, (members, pressers) in SCENES.items():
    fresh()
    cid, ids = O.bodies.appendClumped([sphere(c, r) for c, r in members], discretization=20)
    O.bodies.append([sphere(c, r, fixed=True) for c, r in pressers])
    O.bodies[cid].state.vel = (1, 0, 0)
    O.step()
    before = {'bodies': bodies(), 'mass': total_mass(),
              'efforts': [bfm.checkFailure(O.bodies[i], 1e3, 5e3, wei_V0=0.001) for i in ids]}
    ret = bfm.evalClump(cid, 2, 1e3, 5e3)
    clumps[name] = {'before': before, 'returned': ret, 'bodies': bodies(), 'mass': total_mass(), 'len': len(O.bodies)}
fresh()
cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((1.5, 0, 0), 1)], discretization=20)
O.step()
clumps['unbroken'] = {'returned': bfm.evalClump(cid, 2, 1e3, 5e3), 'len': len(O.bodies)}
out['clumps'] = clumps

# ---------------------------------------------------------------- growParticle
fresh()
s = O.bodies.append(sphere((0, 0, 0), 1))
bfm.growParticle(s, 1.5)
g = {'grown': [O.bodies[s].shape.radius, O.bodies[s].state.mass, tojson(O.bodies[s].state.inertia)]}
bfm.growParticle(s, 0.5, False)
g['shrunk_same_mass'] = [O.bodies[s].shape.radius, O.bodies[s].state.mass, tojson(O.bodies[s].state.inertia)]
out['growParticle'] = g

dump('bf', out)
