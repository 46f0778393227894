# cdm_check: YADE's own check of the extended Hertz-Mindlin law, scripts/checks-and-tests/checks/checkHertzExtended.py
# (Debian: /usr/share/doc/yade/scripts/...), run as YADE's checkList.py runs it (its text executed with
# YadeCheckError defined): it raises if its 40 steps do not give its precomputed overlaps, normal forces, contact
# radii and stresses. Recorded after it passed: for its three contacts (sphere-facet, sphere-wall, sphere-sphere,
# hertzian geometries), the ids, refR1/refR2, penetrationDepth, the MindlinPhysCDM's R, isYielding, kn, ks, kno,
# normalForce and shearForce, and the force on the moving sphere; O.iter and O.dt.
# Regenerate: cd tests/reference/yade && yade -n -x cdm_check.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

CHECK = '/usr/share/doc/yade/scripts/checks-and-tests/checks/checkHertzExtended.py'


class YadeCheckError(Exception):
    pass


exec(compile(open(CHECK).read(), CHECK, 'exec'))
data = {'iter': O.iter, 'dt': O.dt, 'contacts': []}
for a, b in ((0, 10), (13, 14), (15, 16)):
    i = O.interactions[a, b]
    data['contacts'].append({
        'ids': [i.id1, i.id2], 'refR1': i.geom.refR1, 'refR2': i.geom.refR2, 'pen': i.geom.penetrationDepth,
        'R': i.phys.R, 'isYielding': i.phys.isYielding, 'kn': i.phys.kn, 'ks': i.phys.ks, 'kno': i.phys.kno,
        'normalForce': i.phys.normalForce, 'shearForce': i.phys.shearForce, 'f': O.forces.f(a)})
dump('cdm_check', data)
