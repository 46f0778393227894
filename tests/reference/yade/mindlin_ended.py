# mindlin_ended: Law2_ScGeom_MindlinPhys_Mindlin's accumulators (calcEnergy) keep the share of contacts that
# ended. A sphere (r .01, FrictMat E 1e7, nu .3, density 2000, friction .3) thrown at (0.3, 0, -0.5) m/s onto a
# fixed one, Ip2 betan .3, betas .2, dt 1e-6, no gravity: the four accumulators every 200 steps, at the last step
# with the contact and after it ended (plus 3 more steps). Run 'erase': the same, the interaction erased from
# Python at step 1500 (it forms again at the next step, as the spheres still overlap), run to separation.
# Regenerate: cd tests/reference/yade && yade -n -x mindlin_ended.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

NAMES = ('frictionDissipation', 'shearEnergy', 'normDampDissip', 'shearDampDissip')


def run(erase_at=None):
    O.reset()
    m = O.materials.append(FrictMat(young=1e7, poisson=0.3, density=2000, frictionAngle=0.3))
    a = O.bodies.append(sphere((0, 0, 0), 0.01, material=m, fixed=True))
    b = O.bodies.append(sphere((0, 0, 0.0201), 0.01, material=m))
    O.bodies[b].state.vel = (0.3, 0, -0.5)
    law = Law2_ScGeom_MindlinPhys_Mindlin(calcEnergy=True)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_MindlinPhys(betan=0.3, betas=0.2)],
                                 [law]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-6
    values = lambda: [getattr(law, k) for k in NAMES]
    out = {'every_200': [], 'erased_at': erase_at}
    seen = False
    last_with_contact = None
    for k in range(20000):
        O.step()
        if erase_at is not None and O.iter == erase_at:
            out['before_erase'] = values()
            O.interactions.erase(a, b)
            out['after_erase'] = values()
        real = O.interactions.has(a, b) and O.interactions[a, b].isReal
        if real:
            seen = True
            last_with_contact = [O.iter] + values()
        if O.iter % 200 == 0:
            out['every_200'].append([O.iter, real] + values())
        if seen and not real and O.iter > (erase_at or 0) + 1:
            out['ended_at'] = O.iter
            out['at_end'] = values()
            break
    out['last_with_contact'] = last_with_contact
    for k in range(3):
        O.step()
    out['after'] = values()
    return out


dump('mindlin_ended', {'names': NAMES, 'plain': run(), 'erase': run(erase_at=1500)})
