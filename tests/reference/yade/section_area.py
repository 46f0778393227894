# section_area: utils.approxSectionArea and utils.uniaxialTestFeatures (concrete/uniax.py's set-up helpers).
# 'single': one sphere (r 1 at (5, 7, -3)): the area for planes through, at the edge of and beyond it, each axis.
# 'outline': a sphere (r 1) and a point-like one (r 1e-12) at (rho cos phi, rho sin phi, 0), the area about z for
# rho inside and outside the sphere's outline (YADE's is a hexagon, 0.96 to 1.79 from the centre).
# 'pairs': two spheres (r 1) 4 apart in direction theta of the plane, each axis (the outline's width).
# 'cloud': 300 spheres (Python's random, seed 7; r .2-.5) in a 4 x 9 x 3 box, plus a facet and a box (not
# counted): the area at 25 planes along each axis, uniaxialTestFeatures() and with axis 0, distFactor 1.5.
# 'columns': two columns of 401 spheres (r .5) along z (length 20), the second's x offset shrinking (or growing)
# along z: the smallest section is at one end of uniaxialTestFeatures' sections (which ones it samples).
# 'empty': uniaxialTestFeatures() without spheres. 'errors': a bad axis.
# Regenerate: cd tests/reference/yade && yade -n -x section_area.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
import math
import random
from _common import dump, catch

out = {}


def spheres(lst):
    O.bodies.clear()
    for c, r in lst:
        O.bodies.append(utils.sphere(c, r))


spheres([((5, 7, -3), 1)])
center = (5, 7, -3)
out['single'] = {str(ax): [[d, approxSectionArea(center[ax] + d, ax)] for d in (0, .5, -.99, 1, -1, 1.01)] for ax in (0, 1, 2)}

out['outline'] = []
for k in range(24):
    phi = k * math.pi / 12
    out['outline'].append([])
    for rho in (.5, .9, 1.1, 1.5, 1.8, 2.5):
        spheres([((0, 0, 0), 1), ((rho * math.cos(phi), rho * math.sin(phi), 0), 1e-12)])
        out['outline'][-1].append([phi, rho, approxSectionArea(0, 2)])

out['pairs'] = []
for ax in (0, 1, 2):
    u, v = (ax + 1) % 3, (ax + 2) % 3
    for k in range(12):
        th = k * math.pi / 12
        p = [0, 0, 0]
        p[u], p[v] = 4 * math.cos(th), 4 * math.sin(th)
        spheres([((0, 0, 0), 1), (tuple(p), 1)])
        out['pairs'].append([ax, th, approxSectionArea(0, ax)])

rnd = random.Random(7)
spheres([((rnd.uniform(0, 4), rnd.uniform(0, 9), rnd.uniform(0, 3)), rnd.uniform(.2, .5)) for i in range(300)])
O.bodies.append(utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)]))
O.bodies.append(utils.box((10, 20, 5), (1, 1, 1)))
lo, hi = aabbExtrema()
out['cloud'] = {
    'aabb': [lo, hi],
    'areas': [[ax, c, approxSectionArea(c, ax)] for ax in (0, 1, 2)
              for c in [lo[ax] + (hi[ax] - lo[ax]) * (i + .5) / 25 for i in range(25)]],
    'features': catch(lambda: uniaxialTestFeatures()),
    'features_axis0': catch(lambda: uniaxialTestFeatures(axis=0, distFactor=1.5)),
}

out['columns'] = {}
for flip in (0, 1):
    lst = []
    for k in range(401):
        z = .5 + 19 * k / 400
        lst += [((0, 0, z), .5), (((20 - (20 - z if flip else z)) / 2, 0, z), .5)]
    spheres(lst)
    out['columns'][str(flip)] = catch(lambda: uniaxialTestFeatures())

O.bodies.clear()
out['empty'] = catch(lambda: uniaxialTestFeatures())
spheres([((0, 0, 0), 1)])
out['errors'] = {'area_axis3': catch(lambda: approxSectionArea(0, 3)),
                 'area_axis-1': catch(lambda: approxSectionArea(0, -1)),
                 'features_axis3': catch(lambda: uniaxialTestFeatures(axis=3)),
                 'features_file': catch(lambda: uniaxialTestFeatures(filename='spheres.txt'))}
dump('section_area', out)
