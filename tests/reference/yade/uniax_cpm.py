# uniax_cpm: YADE's concrete/uniax.py test (its defaults: CpmMat young 24e9, poisson .2, sigmaT 3.5e6,
# frictionAngle atan(.8), epsCrackOnset 1e-4, relDuctility 30, density 4800; intRadius 1.5 for the first step;
# damping .4; UniaxialStrainer at strain rate .05 in tension and -.5 in compression, from the same initial state)
# on a fixed packing: uniax_pack.txt, 85 spheres (r 3.5e-3, 'x y z r' per line) of YADE's randomDensePack
# (spheresInCell=2000) in uniax.py's hyperboloid for specimenLength .075, made by this script when the file is
# missing. Made deterministic: data after the first step and every 16 steps (uniax.py: every 2e-5 s of simulated
# time, which is 16 steps, or every second of wall-clock time) and the stop test every 160 steps (uniax.py: every
# 4 s of wall-clock time): stop when the stress falls below half its extremum or |strain| passes 5e-3. The script
# drives the run itself (no PyRunner, no labels) so that granum's tests can run it as it is in a namespace of
# their own.
# Records: the uniaxialTestFeatures, O.dt, and per mode the stress, strain and sigma.50 (forcesOnCoordPlane at
# mid-length over approxSectionArea there) every 16 steps, the extremum stress, its strain and step, the last step.
# Regenerate: cd tests/reference/yade && yade -n -j1 -x uniax_cpm.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from math import atan
from yade import plot, pack
import _common
from _common import dump

HERE = os.path.dirname(os.path.abspath(_common.__file__))
PACK = os.path.join(HERE, 'uniax_pack.txt')
specimenLength, sphereRadius, intRadius = .075, 3.5e-3, 1.5
strainRateTension, strainRateCompression = .05, .5
if not os.path.exists(PACK):
    sp = pack.randomDensePack(pack.inHyperboloid((0, 0, -.5 * specimenLength), (0, 0, .5 * specimenLength),
                                                 .25 * specimenLength, .17 * specimenLength),
                              spheresInCell=2000, radius=sphereRadius, returnSpherePack=True)
    with open(PACK, 'w') as f:
        for c, r in sp:
            f.write('%.17g %.17g %.17g %.17g\n' % (c[0], c[1], c[2], r))

concreteId = O.materials.append(CpmMat(young=24e9, frictionAngle=atan(0.8), poisson=.2, density=4800, sigmaT=3.5e6,
                                       relDuctility=30, epsCrackOnset=1e-4, isoPrestress=0))
for line in open(PACK):
    x, y, z, r = map(float, line.split())
    O.bodies.append(sphere((x, y, z), r, material=concreteId))
bb = uniaxialTestFeatures()
negIds, posIds, axis, crossSectionArea = bb['negIds'], bb['posIds'], bb['axis'], bb['area']
O.dt = .8 * PWaveTimeStep()
mm, mx = [pt[axis] for pt in aabbExtrema()]
coord_50 = mm + .5 * (mx - mm)
area_50 = approxSectionArea(coord_50, axis)
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=intRadius)], verletDist=.05 * sphereRadius),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=intRadius)],
                    [Ip2_CpmMat_CpmMat_CpmPhys()], [Law2_ScGeom_CpmPhys_Cpm()]),
    NewtonIntegrator(damping=.4, label='damper'),
    CpmStateUpdater(iterPeriod=100),
    UniaxialStrainer(strainRate=strainRateTension, axis=axis, asymmetry=0, posIds=posIds, negIds=negIds,
                     crossSectionArea=crossSectionArea, blockDisplacements=False, blockRotations=False, setSpeeds=True),
]
O.saveTmp('initial')


def addPlotData(strainer):
    plot.addData(i=O.iter, eps=strainer.strain, sigma=strainer.avgStress,
                 sigma50=forcesOnCoordPlane(coord_50, axis)[axis] / area_50)


out = {'features': bb, 'n': len(O.bodies), 'dt': O.dt, 'area_50': area_50}
for mode in ('tension', 'compression'):
    if mode == 'compression':
        O.loadTmp('initial')
        plot.reset()
    strainer = O.engines[5]
    strainer.strainRate = strainRateTension if mode == 'tension' else -strainRateCompression
    O.step()
    O.engines[2].geomDispatcher.functors[0].interactionDetectionFactor = 1.
    O.engines[1].boundDispatcher.functors[0].aabbEnlargeFactor = 1.
    addPlotData(strainer)
    while True:
        for k in range(10):
            O.run(16, True)
            addPlotData(strainer)
        s = plot.data['sigma']
        extremum = max(s) if mode == 'tension' else min(s)
        if extremum != 0 and (abs(s[-1] / extremum) < .5 or abs(strainer.strain) > 5e-3):
            break
    k = s.index(extremum)
    out[mode] = {'peak': extremum, 'epsPeak': plot.data['eps'][k], 'iterPeak': plot.data['i'][k], 'iter': O.iter,
                 'i': plot.data['i'], 'eps': plot.data['eps'], 'sigma': s, 'sigma50': plot.data['sigma50']}
dump('uniax_cpm', out)
