# viscel_pairs: per-pair contact constants and ViscEl rolling resistance (YADE 2023.02a).
# 1. rolling: two ViscElMat spheres (r .01 fixed at the origin, r .02 above, overlap 1e-4, kn=1e5, ks=0 unless
#    said, no damping), angular velocities set, one step of dt=1e-9: the contact's mR, mRtype, forces and both
#    torques, for mRtype 1 and 2 and materials with different mR.
# 2. pairs: the ViscElPhys/FrictPhys/CohFrictPhys/MindlinPhys dict after one step of two spheres (r .01 and .02,
#    overlap 1e-5, density 2000) of two materials, with and without MatchMakers for the Ip2 parameters;
#    a sphere on a facet (ViscEl, massless facet).
# 3. matchmaker: MatchMaker called from Python (matches, algos, computeFallback, errors).
# 4. flat_facet_box: geom.facetBox with one zero extent (rotated, wallMask 12): the facets' pos, local vertices,
#    normal; two zero extents: the error.
# Cases that abort YADE (an uncaught C++ exception) are not run here: mRtype differing between the two
# materials, and a MatchMaker without a match whose algo needs values the Ip2 does not supply (ViscElPhys tc,
# en, et, frictAngle; CohFrictPhys normalCohesion, shearCohesion; MindlinPhys en, es, betan, betas).
# Regenerate: cd tests/reference/yade && yade -n -x viscel_pairs.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump, tojson


def rolling(mR1, mR2, t1, t2, w1, w2, ks=0.0, cn=0.0, fix1=True, v2=(0, 0, 0)):
    O.reset()
    m1 = O.materials.append(ViscElMat(kn=1e5, cn=cn, ks=ks, cs=0, mR=mR1, mRtype=t1, frictionAngle=0.5, density=1000))
    m2 = O.materials.append(ViscElMat(kn=1e5, cn=cn, ks=ks, cs=0, mR=mR2, mRtype=t2, frictionAngle=0.5, density=1000))
    a = O.bodies.append(sphere((0, 0, 0), 0.01, material=m1, fixed=fix1))
    b = O.bodies.append(sphere((0, 0, 0.03 - 1e-4), 0.02, material=m2))
    O.bodies[a].state.angVel = Vector3(*w1)
    O.bodies[b].state.angVel = Vector3(*w2)
    O.bodies[b].state.vel = Vector3(*v2)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                 [Law2_ScGeom_ViscElPhys_Basic()]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-9
    O.step()
    i = O.interactions[a, b]
    return tojson(dict(args=dict(mR1=mR1, mR2=mR2, mRtype1=t1, mRtype2=t2, w1=w1, w2=w2, ks=ks, cn=cn, fixed1=fix1,
                                 v2=v2),
                       mR=i.phys.mR, mRtype=i.phys.mRtype, normalForce=i.phys.normalForce,
                       shearForce=i.phys.shearForce, t1=O.forces.t(a), t2=O.forces.t(b), pos1=O.bodies[a].state.pos,
                       pos2=O.bodies[b].state.pos, contactPoint=i.geom.contactPoint))


out = {'rolling': {}}
R = out['rolling']
R['type1'] = rolling(0.05, 0.05, 1, 1, (0, 0, 0), (1, 0, 0))
R['type1_w1'] = rolling(0.05, 0.05, 1, 1, (2, 0, 0), (0, 0, 0))
R['type1_both'] = rolling(0.05, 0.05, 1, 1, (2, 0, 0), (0, 3, 0))
R['type1_twist'] = rolling(0.05, 0.05, 1, 1, (0, 0, 0), (0, 0, 5))
R['type2'] = rolling(0.05, 0.05, 2, 2, (0, 0, 0), (1, 0, 0))
R['type2_w1'] = rolling(0.05, 0.05, 2, 2, (2, 0, 0), (0, 0, 0))
R['type2_both'] = rolling(0.05, 0.05, 2, 2, (2, 0, 0), (0, 3, 0))
R['type2_parallel'] = rolling(0.05, 0.05, 2, 2, (1, 0, 0), (3, 0, 0))
R['type2_twist'] = rolling(0.05, 0.05, 2, 2, (0, 0, 0), (0, 0, 5))
R['type2_free'] = rolling(0.05, 0.05, 2, 2, (1, 0, 0), (0, 2, 0), fix1=False)
R['type2_shear'] = rolling(0.05, 0.05, 2, 2, (0, 0, 0), (1, 0, 0), ks=1e4)
R['type1_damped'] = rolling(0.05, 0.05, 1, 1, (0, 0, 0), (1, 0, 0), cn=50.0, v2=(0, 0, -0.1))
R['mR_harmonic'] = rolling(0.05, 0.1, 1, 1, (0, 0, 0), (1, 0, 0))
R['mR_one_zero'] = rolling(0.0, 0.1, 1, 1, (0, 0, 0), (1, 0, 0))
R['mR_other_zero'] = rolling(0.1, 0.0, 1, 1, (0, 0, 0), (1, 0, 0))
R['mR_both_zero'] = rolling(0.0, 0.0, 1, 1, (0, 0, 0), (1, 0, 0))


def pair(mats, ip2, law, geom=Ig2_Sphere_Sphere_ScGeom, fixed=False):
    O.reset()
    ids = [O.materials.append(x) for x in mats]
    a = O.bodies.append(sphere((0, 0, 0), 0.01, material=ids[0], fixed=fixed))
    b = O.bodies.append(sphere((0, 0, 0.03 - 1e-5), 0.02, material=ids[-1]))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]), InteractionLoop([geom()], [ip2], [law]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-9
    O.step()
    i = O.interactions[a, b]
    return tojson(dict(phys={k: v for k, v in i.phys.dict().items()}, mass1=O.bodies[a].state.mass,
                       mass2=O.bodies[b].state.mass, material_ids=ids))


MM = MatchMaker
V = lambda **k: ViscElMat(**dict(dict(density=2000, frictionAngle=0.4), **k))
va = dict(tc=1e-3, en=0.5, et=0.6)
vb = dict(tc=2e-3, en=0.8, et=0.3, frictionAngle=0.2)
kk = dict(kn=1e5, cn=1.0, ks=2e4, cs=0.5)
VIp2 = Ip2_ViscElMat_ViscElMat_ViscElPhys
VLaw = Law2_ScGeom_ViscElPhys_Basic
P = out['pairs'] = {}
P['viscel_same'] = pair([V(**va)], VIp2(), VLaw())
P['viscel_mixed'] = pair([V(**va), V(**vb)], VIp2(), VLaw())
P['viscel_mixed_fixed'] = pair([V(**va), V(**vb)], VIp2(), VLaw(), fixed=True)
P['viscel_en_zero_mixed'] = pair([V(tc=1e-3, en=0.0, et=0.0), V(tc=1e-3, en=0.5, et=0.5)], VIp2(), VLaw())
P['viscel_en_zero'] = pair([V(tc=1e-3, en=0.0, et=0.0)], VIp2(), VLaw())
P['viscel_mm_en_match'] = pair([V(**va), V(**vb)], VIp2(en=MM(matches=((0, 1, 0.3),))), VLaw())
P['viscel_mm_et_val'] = pair([V(**va), V(**vb)], VIp2(et=MM(algo='val', val=0.9)), VLaw())
P['viscel_mm_tc_match'] = pair([V(**va), V(**vb)], VIp2(tc=MM(matches=((1, 0, 3e-3),))), VLaw())
P['viscel_mm_numbers'] = pair([V(**va), V(**vb)], VIp2(tc=1e-3, en=0.3, et=0.4), VLaw())
P['viscel_mm_frict_val'] = pair([V(**va), V(**vb)], VIp2(frictAngle=MM(algo='val', val=0.1)), VLaw())
P['viscel_mm_frict_match'] = pair([V(**va), V(**vb)], VIp2(frictAngle=MM(matches=((1, 0, 0.1),))), VLaw())
P['viscel_kn_mm_en_only'] = pair([V(**kk), V(**kk)], VIp2(en=0.5), VLaw())
P['viscel_kn_mm_all'] = pair([V(**kk), V(**kk)], VIp2(tc=1e-3, en=0.5, et=0.5), VLaw())
F = lambda **k: FrictMat(**dict(dict(young=1e7, poisson=0.3, density=2000, frictionAngle=0.4), **k))
fb = dict(frictionAngle=0.2, young=3e7, poisson=0.5)
FIp2 = Ip2_FrictMat_FrictMat_FrictPhys
CS = Law2_ScGeom_FrictPhys_CundallStrack
P['frict_base'] = pair([F(), F(**fb)], FIp2(), CS())
P['frict_kn_avg'] = pair([F(), F(**fb)], FIp2(kn=MM(algo='avg')), CS())
P['frict_kn_match'] = pair([F(), F(**fb)], FIp2(kn=MM(matches=((0, 1, 5e4),))), CS())
P['frict_kn_number'] = pair([F(), F(**fb)], FIp2(kn=5e4), CS())
P['frict_ks_number'] = pair([F(), F(**fb)], FIp2(ks=5e4), CS())
P['frict_ks_avg'] = pair([F(), F(**fb)], FIp2(ks=MM(algo='avg')), CS())
for algo in ('avg', 'min', 'max', 'harmAvg', 'zero'):
    P['frict_angle_' + algo] = pair([F(), F(**fb)], FIp2(frictAngle=MM(algo=algo)), CS())
P['frict_angle_number'] = pair([F(), F(**fb)], FIp2(frictAngle=0.1), CS())
C = lambda **k: CohFrictMat(**dict(dict(young=1e7, poisson=0.3, density=2000, isCohesive=True), **k))
ca = dict(normalCohesion=1e5, shearCohesion=2e5, frictionAngle=0.4)
cb = dict(normalCohesion=3e5, shearCohesion=1e5, frictionAngle=0.2)
CIp2 = lambda **k: Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True, **k)
CLaw = Law2_ScGeom6D_CohFrictPhys_CohesionMoment
G6 = Ig2_Sphere_Sphere_ScGeom6D
P['cohfrict_base'] = pair([C(**ca), C(**cb)], CIp2(), CLaw(), G6)
P['cohfrict_mm'] = pair([C(**ca), C(**cb)], CIp2(normalCohesion=MM(matches=((0, 1, 7e5),)), shearCohesion=4e5,
                                                 frictAngle=MM(algo='max')), CLaw(), G6)
MIp2 = Ip2_FrictMat_FrictMat_MindlinPhys
ML = Law2_ScGeom_MindlinPhys_Mindlin
fm = dict(frictionAngle=0.2, young=3e7, poisson=0.25)
P['mindlin_base'] = pair([F(), F(**fm)], MIp2(), ML())
P['mindlin_en_match'] = pair([F(), F(**fm)], MIp2(en=MM(matches=((0, 1, 0.5),))), ML())
P['mindlin_en_es_match'] = pair([F(), F(**fm)], MIp2(en=MM(matches=((0, 1, 0.5),)), es=MM(matches=((0, 1, 0.7),))),
                                ML())
P['mindlin_beta_match'] = pair([F(), F(**fm)], MIp2(betan=MM(matches=((0, 1, 0.2),)), betas=MM(matches=((0, 1, 0.1),))),
                               ML())
P['mindlin_angle_avg'] = pair([F(), F(**fm)], MIp2(frictAngle=MM(algo='avg')), ML())
P['mindlin_angle_match'] = pair([F(), F(**fm)], MIp2(frictAngle=MM(matches=((0, 1, 0.1),))), ML())


def on_facet(mat_sphere, mat_facet):
    O.reset()
    m = O.materials.append(mat_sphere)
    n = O.materials.append(mat_facet)
    s = O.bodies.append(sphere((0, 0, 0.01 - 1e-5), 0.01, material=m))
    f = O.bodies.append(facet([(-1, -1, 0), (1, -1, 0), (0, 1, 0)], material=n))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
                 InteractionLoop([Ig2_Facet_Sphere_ScGeom()], [VIp2()], [VLaw()]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-9
    O.step()
    i = O.interactions[s, f]
    return tojson(dict(phys=i.phys.dict(), sphere_mass=O.bodies[s].state.mass))


P['viscel_facet_same'] = on_facet(V(**va), V(**va))
P['viscel_facet_mixed'] = on_facet(V(**va), V(**vb))

M = out['matchmaker'] = {}
m = MatchMaker(matches=((0, 1, 0.3), (2, 1, 0.5)))
M['matched'] = [catch(lambda: m(0, 1)), catch(lambda: m(1, 0)), catch(lambda: m(1, 2))]
M['no_match_no_values'] = catch(lambda: m(0, 2))
M['no_match_values'] = catch(lambda: m(0, 2, 1.0, 3.0))
for algo in ('avg', 'min', 'max', 'harmAvg', 'val', 'zero'):
    mm = MatchMaker(algo=algo, val=7.0)
    M['algo_' + algo] = dict(call=catch(lambda: mm(0, 2, 1.0, 3.0)), fallback=catch(lambda: mm.computeFallback(1.0, 3.0)),
                            no_values=catch(lambda: mm(0, 2)), fallback_zero=catch(lambda: mm.computeFallback(0.0, 3.0)))
M['bad_algo'] = catch(lambda: MatchMaker(algo='foo'))
M['val_nan'] = catch(lambda: MatchMaker(algo='val')(0, 1, 1.0, 2.0))
M['from_number'] = catch(lambda: Ip2_FrictMat_FrictMat_FrictPhys(frictAngle=0.3).frictAngle.dict())
M['default_dict'] = catch(lambda: MatchMaker().dict())
M['ip2_defaults'] = {n: catch(lambda: globals()[n]().dict()) for n in (
    'Ip2_FrictMat_FrictMat_FrictPhys', 'Ip2_ViscElMat_ViscElMat_ViscElPhys', 'Ip2_CohFrictMat_CohFrictMat_CohFrictPhys',
    'Ip2_FrictMat_FrictMat_MindlinPhys')}
# 4. geom.facetBox with a zero extent (rotationalResistance.py's inclined planes): one rectangle
FB = out['flat_facet_box'] = {}
for e in ((1, 2, 0), (0, 2, 1), (1, 0, 1)):
    fs = geom.facetBox((0.1, 0.2, 0.3), e, orientation=Quaternion(Vector3(1, 0, 0), 0.3), wallMask=12)
    FB[str(e)] = [tojson(dict(pos=f.state.pos, vertices=list(f.shape.vertices), normal=f.shape.normal)) for f in fs]
FB['two_zero'] = catch(lambda: geom.facetBox((0, 0, 0), (1, 0, 0)))
dump('viscel_pairs', out)
