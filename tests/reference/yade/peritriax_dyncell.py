# PeriTriaxController(dynCell=True) step by step (YADE 2023.02a): the strain rate's equation of motion, on the
# shared packing of periiso.py with radii 1.0004 times (a few light contacts, stresses far from the goal).
# Run: yade -n -x peritriax_dyncell.py  (writes peritriax_dyncell.json); globUpdate 1 (rows) and 5 (rows_glob5)
import os
import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump
from yade import pack



def run(glob_update, steps):
    O.reset()
    O.periodic = True
    O.cell.setBox(1, 1.2, 0.9)
    sp = pack.SpherePack()
    sp.load(os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), 'periiso_pack.txt'))
    for c, r in sp:
        O.bodies.append(sphere(c, r * 1.0004))
    triax = PeriTriaxController(dynCell=True, mass=0.2, maxUnbalanced=0.01, relStressTol=0.01,
                                goal=(-1e4, -1e4, -1e4), stressMask=7, globUpdate=glob_update,
                                maxStrainRate=(100., 100., 100.))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]), triax, NewtonIntegrator(damping=.2)]
    O.dt = 1e-5
    rows = []
    for i in range(steps):
        O.step()
        rows.append({'iter': O.iter, 'stress': list(triax.stress), 'rate': [O.cell.velGrad[k, k] for k in range(3)],
                     'size': list(O.cell.size), 'stiff': list(triax.stiff), 'unbalanced': triax.currUnbalanced})
    return rows


# globUpdate 1; then YADE's default 5 (the stress is still that of the current step; the unbalanced force is
# recomputed every 5 steps; the stiffness is not computed with dynCell)
dump('peritriax_dyncell', {'rows': run(1, 8), 'rows_glob5': run(5, 12)})
