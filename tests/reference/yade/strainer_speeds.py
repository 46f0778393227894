# strainer_speeds: UniaxialStrainer.setSpeeds (concrete/uniax.py sets it). Eight spheres (r .2) along z at 0, 1,
# 2.5, 4, 6, 10, -3, 12, no contacts (ForceResetter, NewtonIntegrator(damping=0), then the strainer, as in
# uniax.py; dt 1e-3); negIds [0] (or [6, 0]), posIds [5]; body 3 starts with velocity (.3, .2, .7), body 4 is
# not dynamic and moves at (0, 0, .1). For setSpeeds True and False, asymmetry 0, 1, -1 and strain rates +-.5:
# every body's velocity after each of 3 steps, originalLength and strain. 'before': the strainer before
# NewtonIntegrator (setSpeeds, asymmetry 0, rate .5).
# Regenerate: cd tests/reference/yade && yade -n -x strainer_speeds.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

ZS = [0, 1, 2.5, 4, 6, 10, -3, 12]


def run(setSpeeds, asymmetry, rate, negIds=(0,), before=False):
    O.reset()
    for i, z in enumerate(ZS):
        O.bodies.append(sphere((0.1 * i, 0, z), .2))
    O.bodies[3].state.vel = (0.3, 0.2, 0.7)
    O.bodies[4].dynamic = False
    O.bodies[4].state.vel = (0, 0, 0.1)
    strainer = UniaxialStrainer(strainRate=rate, axis=2, asymmetry=asymmetry, posIds=[5], negIds=list(negIds),
                                crossSectionArea=1, setSpeeds=setSpeeds)
    O.engines = [ForceResetter(), NewtonIntegrator(damping=0)]
    O.engines = O.engines[:1] + [strainer] + O.engines[1:] if before else O.engines + [strainer]
    O.dt = 1e-3
    steps = []
    for k in range(3):
        O.step()
        steps.append({'vel': [list(b.state.vel) for b in O.bodies], 'pos': [list(b.state.pos) for b in O.bodies]})
    return {'steps': steps, 'originalLength': strainer.originalLength, 'strain': strainer.strain}


out = {}
for setSpeeds in (True, False):
    for asymmetry in (0, 1, -1):
        for rate in (.5, -.5):
            out['%s_%d_%g' % (setSpeeds, asymmetry, rate)] = run(setSpeeds, asymmetry, rate)
out['neg60'] = run(True, 0, .5, negIds=(6, 0))
out['before'] = run(True, 0, .5, before=True)
dump('strainer_speeds', out)
