# omega_env: Omega's scene management and the names YADE puts in a script's namespace (the scripting
# environment of YADE's launcher): Omega() sharing O's simulation, switchScene/addScene/switchToScene,
# reset, resetTime, labeledEngine, dynDt without a TimeStepper, filename/saveTmp/reload, sceneToString,
# sub-stepping defaults, dispatchers, yade.system's class queries, and the namespace's modules and opts.
# Regenerate: cd tests/reference/yade && yade -n -x omega_env.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
import yade.system

out = {}
# --- Omega() is the same simulation as O
o = Omega()
o.dt = 5e-3
o.engines = [ForceResetter(), NewtonIntegrator()]
o.bodies.append(sphere((0, 0, 0), 1))
out['Omega_shares'] = {'O.dt': O.dt, 'len(O.engines)': len(O.engines), 'len(O.bodies)': len(O.bodies)}

# --- scenes
O.reset()
O.bodies.append(sphere((0, 0, 0), 1))
seq = [('start', O.thisScene, len(O.bodies))]
O.switchScene(); seq.append(('switchScene', O.thisScene, len(O.bodies)))
out['other_scene_dt_engines'] = [O.dt, len(O.engines)]
O.bodies.append(sphere((0, 0, 0), 1)); O.bodies.append(sphere((3, 0, 0), 1))
O.switchScene(); seq.append(('switchScene again', O.thisScene, len(O.bodies)))
i = O.addScene(); seq.append(('addScene -> %d' % i, O.thisScene, len(O.bodies)))
O.switchToScene(i); seq.append(('switchToScene(new)', O.thisScene, len(O.bodies)))
O.bodies.append(sphere((0, 0, 0), 1))
O.switchToScene(0); seq.append(('switchToScene(0)', O.thisScene, len(O.bodies)))
O.resetThisScene(); seq.append(('resetThisScene', O.thisScene, len(O.bodies)))
O.switchToScene(i); seq.append(('scene 1 after resetThisScene of 0', O.thisScene, len(O.bodies)))
O.switchToScene(0)
O.switchScene(); seq.append(('other after resetThisScene', O.thisScene, len(O.bodies)))
O.switchScene()
O.reset(); seq.append(('reset', O.thisScene, len(O.bodies)))
O.switchScene(); seq.append(('other after reset', O.thisScene, len(O.bodies)))
O.switchScene()
out['scene_sequence'] = seq
out['addScene_after_reset'] = O.addScene()

# --- clock
O.reset()
O.engines = [ForceResetter(), NewtonIntegrator()]
O.dt = 1e-3
out['realtime_type'] = type(O.realtime).__name__
out['speed_before_run'] = O.speed
O.run(100, True)
out['after_run'] = [O.iter, O.time]
O.resetTime()
out['after_resetTime'] = [O.iter, O.time, O.realtime < 1.0]
out['dynDt'] = [O.dynDt, O.dynDtAvailable]
out['dynDt=True'] = catch(lambda: setattr(O, 'dynDt', True))
out['subStep'] = [O.subStep, O.subStepping]
out['forceSyncCount'] = O.forceSyncCount
out['miscParams'] = len(O.miscParams)

# --- labels
e = ForceResetter(label='myResetter')
O.engines = [e, NewtonIntegrator()]
out['labeledEngine_found'] = O.labeledEngine('myResetter') is e
out['labeledEngine_missing'] = catch(lambda: O.labeledEngine('nope'))

# --- files
O.reset()
out['filename_fresh'] = O.filename
O.saveTmp(quiet=True)
out['filename_after_saveTmp'] = O.filename
O.saveTmp('mark1', quiet=True)
out['filename_after_saveTmp_mark'] = O.filename
out['tmpToString'] = catch(lambda: O.tmpToString('mark1'))
O.bodies.append(sphere((0, 0, 0), 1))
O.engines = [InsertionSortCollider([Bo1_Sphere_Aabb()]), NewtonIntegrator()]
O.step()
O.saveTmp(quiet=True)
mn0 = Vector3(O.bodies[0].bound.min)
O.reload(quiet=True)
out['reload'] = {'len(O.bodies)': len(O.bodies), 'bound_min_before': mn0, 'bound_min_after': Vector3(O.bodies[0].bound.min),
                 'iter': O.iter}
s = O.sceneToString()
out['sceneToString_type'] = type(s).__name__
O.reset()
O.stringToScene(s)
out['stringToScene'] = {'len(O.bodies)': len(O.bodies), 'len(O.engines)': len(O.engines), 'iter': O.iter}

# --- dispatchers
out['LawDispatcher_same'] = len(LawDispatcher([Law2_ScGeom_FrictPhys_CundallStrack(), Law2_ScGeom_FrictPhys_CundallStrack()]).functors)
out['IGeomDispatcher_two'] = len(IGeomDispatcher([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()]).functors)
out['LawDispatcher_wrong'] = catch(lambda: LawDispatcher([Bo1_Sphere_Aabb()]))
il = InteractionLoop([Ig2_Facet_Sphere_ScGeom(), Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                     [Law2_ScGeom_FrictPhys_CundallStrack()])
out['InteractionLoop_dispatchers'] = [type(il.geomDispatcher).__name__, type(il.physDispatcher).__name__,
                                      type(il.lawDispatcher).__name__, len(il.geomDispatcher.functors)]
out['collider_boundDispatcher'] = type(InsertionSortCollider([Bo1_Sphere_Aabb()]).boundDispatcher).__name__
out['nBins'] = catch(lambda: InsertionSortCollider(nBins=5))

# --- class hierarchy
out['childClasses'] = {b: sorted(yade.system.childClasses(b)) for b in
                       ('Serializable', 'Engine', 'GlobalEngine', 'PartialEngine', 'Functor', 'IGeomFunctor',
                        'IPhysFunctor', 'LawFunctor', 'BoundFunctor', 'Material', 'ElastMat', 'FrictMat', 'Shape',
                        'IGeom', 'IPhys', 'FrictPhys', 'Dispatcher', 'NoSuchClass')}
out['childClasses_nonrecursive_ElastMat'] = sorted(O.childClassesNonrecursive('ElastMat'))
out['isChildClassOf'] = [O.isChildClassOf('FrictMat', 'Material'), O.isChildClassOf('ViscElMat', 'ElastMat'),
                         O.isChildClassOf('Material', 'FrictMat'), O.isChildClassOf('Sphere', 'Shape')]

# --- the script namespace
g = globals()
out['namespace_modules'] = {n: type(g[n]).__name__ if n in g else None for n in
                            ('sys', 'os', 'math', 'time', 'random', 'numpy', 'argparse', 'itertools', 'warnings',
                             'doctest', 'standard_library', 'opts', 'args', 'features', 'SpherePack', 'inSphere',
                             'regularOrtho', 'Omega', 'O', 'pi', 'sqrt')}
out['opts'] = {k: getattr(opts, k) for k in ('threads', 'nogui', 'exitAfter', 'script')}
out['args'] = args
out['from_math_import'] = [g.get('pi'), g.get('sqrt')(16.0)]
dump('omega_env', out)
