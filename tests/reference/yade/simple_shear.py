# YADE's SimpleShear preprocessor: the scene load() builds with the defaults and with other parameters (the boxes,
# their materials, the spheres' count, radii and density, the engines and O.dt). Writes simple_shear.json.
import os, sys, math
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

def scene(**kw):
    SimpleShear(**kw).load()
    spheres = [b for b in O.bodies if isinstance(b.shape, Sphere)]
    radii = [b.shape.radius for b in spheres]
    out = {'dt': O.dt, 'nSpheres': len(spheres), 'rMin': min(radii), 'rMax': max(radii),
           'sphereDensity': [b.state.mass / (4 / 3 * math.pi * b.shape.radius ** 3) for b in spheres[:3]],
           'sphereMaterial': spheres[0].material.dict(), 'sphereColor': spheres[0].shape.color,
           'boxes': [{'pos': b.state.pos, 'extents': b.shape.extents, 'material': b.material.dict(), 'mass': b.state.mass,
                      'inertia': b.state.inertia, 'blockedDOFs': b.state.blockedDOFs, 'wire': b.shape.wire,
                      'color': b.shape.color} for b in O.bodies if isinstance(b.shape, Box)],
           'engines': [type(e).__name__ for e in O.engines],
           'timeStepper': {k: v for k, v in O.engines[1].dict().items() if k in ('defaultDt', 'timestepSafetyCoefficient', 'timeStepUpdateInterval')},
           'newtonDamping': [e.damping for e in O.engines if isinstance(e, NewtonIntegrator)][0],
           'gravity': [e.gravity for e in O.engines if isinstance(e, GravityEngine)],
           'ctd': {k: v for k, v in O.engines[-1].dict().items() if k not in ('label', 'ompThreads', 'dead')}}
    return out

dump('simple_shear', {'defaults': scene(), 'other': scene(density=3000, length=0.05, height=0.03, width=0.02,
                                                         thickness=0.002, matFrictionDeg=30, matYoungModulus=1e8,
                                                         matPoissonRatio=0.3, gravApplied=True,
                                                         gravity=Vector3(0, -5, 1), timeStepUpdateInterval=7)})
