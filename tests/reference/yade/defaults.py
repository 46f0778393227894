# defaults: .dict() of freshly constructed YADE objects (engines, functors,
# materials, shapes, State, selected Body attributes), plus properties of a
# fresh scene (O.dt, materials, engines) and the default material that
# utils.sphere creates.
# Regenerate: cd tests/reference/yade && yade -n -x defaults.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump, tojson

classes = ['ForceResetter', 'InsertionSortCollider', 'Bo1_Sphere_Aabb', 'Bo1_Facet_Aabb',
           'Bo1_Wall_Aabb', 'Bo1_Box_Aabb', 'InteractionLoop', 'Ig2_Sphere_Sphere_ScGeom',
           'Ig2_Facet_Sphere_ScGeom', 'Ig2_Wall_Sphere_ScGeom', 'Ig2_Box_Sphere_ScGeom',
           'Ip2_FrictMat_FrictMat_FrictPhys', 'Ip2_ViscElMat_ViscElMat_ViscElPhys',
           'Law2_ScGeom_FrictPhys_CundallStrack', 'Law2_ScGeom_ViscElPhys_Basic',
           'NewtonIntegrator', 'GravityEngine', 'PyRunner', 'ForceEngine',
           'TranslationEngine', 'RotationEngine', 'FrictMat', 'ViscElMat', 'Sphere',
           'Facet', 'Wall', 'Box', 'State', 'Material', 'Body']

out = {'classes': {}}
for c in classes:
    out['classes'][c] = catch(lambda: eval(c)().dict())

# InteractionLoop sub-dispatchers (dict shows them as objects -> repr)
il = InteractionLoop()
out['InteractionLoop_functors'] = {
    'geomDispatcher': [type(f).__name__ for f in il.geomDispatcher.functors],
    'physDispatcher': [type(f).__name__ for f in il.physDispatcher.functors],
    'lawDispatcher': [type(f).__name__ for f in il.lawDispatcher.functors]}

b = Body()
out['Body_attrs'] = {a: catch(lambda: getattr(b, a)) for a in
    ['id', 'mask', 'groupMask', 'dynamic', 'aspherical', 'isClump', 'isClumpMember',
     'isStandalone', 'clumpId', 'bounded', 'flags', 'iterBorn', 'timeBorn', 'shape',
     'bound', 'material', 'state']}
out['Body_attrs']['state_class'] = type(b.state).__name__
out['Body_attrs']['state_dict'] = catch(lambda: b.state.dict())

out['fresh_scene'] = {
    'O.dt': O.dt, 'len(O.materials)': len(O.materials), 'len(O.bodies)': len(O.bodies),
    'O.iter': O.iter, 'O.time': O.time, 'O.trackEnergy': O.trackEnergy,
    'O.engines': [type(e).__name__ for e in O.engines],
    'O.engines_dicts': {type(e).__name__: catch(lambda: e.dict()) for e in O.engines},
    'dynDt': catch(lambda: O.dynDt),
}
il = O.engines[2]
out['fresh_scene']['InteractionLoop_functors'] = {
    'geomDispatcher': [type(f).__name__ for f in il.geomDispatcher.functors],
    'physDispatcher': [type(f).__name__ for f in il.physDispatcher.functors],
    'lawDispatcher': [type(f).__name__ for f in il.lawDispatcher.functors]}
out['fresh_scene']['collider_boundFunctors'] = [
    type(f).__name__ for f in O.engines[1].boundDispatcher.functors]
s = utils.sphere((0, 0, 0), 1)
out['utils_sphere_default_material'] = {
    'class': type(s.material).__name__, 'dict': s.material.dict(),
    'len(O.materials)_after': len(O.materials),
    'material_is_O.materials[0]': s.material.id == O.materials[0].id,
    'O.materials[0].label': O.materials[0].label}
out['O.dt_after_utils_sphere'] = O.dt

def mark_uninit(v):
    # some C++ attributes are left uninitialised (values like 6.9e-310): flag them
    if isinstance(v, float) and v != 0 and abs(v) < 1e-300:
        return 'uninitialised(%r)' % v
    if isinstance(v, list):
        return [mark_uninit(x) for x in v]
    if isinstance(v, dict):
        return {k: mark_uninit(x) for k, x in v.items()}
    return v

dump('defaults', mark_uninit(tojson(out)))
