# domain_limiter: DomainLimiter's defaults, and what it erases: spheres outside the box (one fixed), a clump
# whose centre is on the box's face (kept although a member sticks out), one whose centre is outside (erased
# with its members), one inside; then with mask=2. Bodies left, nDeleted, mDeleted, vDeleted after each step.
# Regenerate: cd tests/reference/yade && yade -n -x domain_limiter.py
# YADE 2023.02a
import sys; import os
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

d = DomainLimiter().dict()
out = {'defaults': {k: v for k, v in d.items() if k != 'realLast'}}
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             DomainLimiter(lo=(-1, -1, -1), hi=(1, 1, 1), iterPeriod=1, label='dl'), NewtonIntegrator()]
O.dt = 1e-6
O.bodies.append([sphere((0, 0, 0), .1), sphere((2, 0, 0), .1, mask=2), sphere((0, 0, 5), .2),
                 sphere((0, 0, -5), .1, fixed=True)])
O.bodies.appendClumped([sphere((0.9, 0, 0), .1), sphere((1.1, 0, 0), .1)])
O.bodies.appendClumped([sphere((1.05, 0, 0.5), .1), sphere((1.25, 0, 0.5), .1)])
O.bodies.appendClumped([sphere((0.5, 0.5, 0.5), .1), sphere((0.7, 0.5, 0.5), .1)])
steps = []
def record():
    steps.append({'iter': O.iter, 'bodies': [b.id for b in O.bodies if b is not None], 'nDeleted': dl.nDeleted,
                  'mDeleted': dl.mDeleted, 'vDeleted': dl.vDeleted})
for k in range(2):
    O.step()
    record()
dl.mask = 2
O.bodies.append([sphere((3, 0, 0), .1, mask=1), sphere((3, 3, 0), .1, mask=3)])
O.step()
record()
out['steps'] = steps
# a facet outside the box is not erased (a box outside it crashes YADE 2023.02a: not run)
O.reset()
O.bodies.append(facet([(0, 3, 0), (1, 3, 0), (0, 4, 0)]))
O.bodies.append(sphere((0, 3, 0), .1, fixed=True))
O.bodies.append(sphere((0, -3, 0), .1))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
             DomainLimiter(lo=(-1, -1, -1), hi=(1, 1, 1), iterPeriod=1, label='dl'), NewtonIntegrator()]
O.dt = 1e-4
O.run(3, True)
out['facet'] = {'bodies': [b.id for b in O.bodies if b is not None], 'nDeleted': dl.nDeleted}
dump('domain_limiter', out)
