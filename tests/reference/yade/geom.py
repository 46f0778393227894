# YADE 2023.02a reference for yade.geom's facet generators: for each call (written with it), the global
# vertices of every facet in the order returned (or the exception raised). Run: yade -n -x geom.py  (writes geom.json)
import os
import sys
from math import pi

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from yade import geom  # noqa: E402
from _common import catch, dump  # noqa: E402

Q = Quaternion((1, 1, 0), 0.7)  # a general orientation (axis normalised by YADE)

CASES = {
    # name: (function, positional args, keyword args)
    'cylinder': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=6)),
    'cylinder_default': ('facetCylinder', [(0.1, -0.2, 0.3), 0.5, 1.5], {}),
    'cylinder_oriented': ('facetCylinder', [(1, 2, 3), 1, 2], dict(orientation=Q, segmentsNumber=5)),
    'cylinder_side': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, wallMask=4)),
    'cylinder_mask9': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, wallMask=9)),
    'cylinder_range': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=6, angleRange=(0, pi / 2))),
    'cylinder_gap_wedge': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=6, angleRange=(0, pi / 2), closeGap=True)),
    'cylinder_gap_wedge_mask3': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, wallMask=3, angleRange=(0, pi / 2), closeGap=True)),
    'cylinder_gap_chord': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=3, angleRange=(0.3, 0.3 + 1.2 * pi), closeGap=True)),
    'cylinder_gap_chord_mask6': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=3, wallMask=6, angleRange=(0.3, 0.3 + 1.5 * pi), closeGap=True)),
    'cylinder_gap_full': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, closeGap=True)),
    'cylinder_inner': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, radiusTopInner=0.5, radiusBottomInner=0.3)),
    'cylinder_top_inner': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, radiusTopInner=0.5)),
    'cylinder_inner_gap': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, radiusTopInner=0.5, radiusBottomInner=0.3, angleRange=(0, pi / 2), closeGap=True)),
    'cylinder_inner_gap_chord': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=3, radiusTopInner=0.5, radiusBottomInner=0.3, angleRange=(0.3, 0.3 + 1.2 * pi), closeGap=True)),
    'cylinder_flat': ('facetCylinder', [(0, 0, 0), 1, 0], dict(segmentsNumber=5)),
    'cylinder_segments3': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=3)),
    'cylinder_kw': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=5, wallMask=4, color=(1, 0, 0), wire=False, mask=5)),
    'cone': ('facetCone', [(0, 0, 0), 1, 0.5, 2], dict(segmentsNumber=5)),
    'cone_oriented_inner': ('facetCone', [(1, -1, 2), 1, 2, 2], dict(orientation=Q, segmentsNumber=5, radiusTopInner=0.5, radiusBottomInner=1.5)),
    'cone_range': ('facetCone', [(0, 0, 0), 2, 1, 1], dict(segmentsNumber=4, angleRange=(0.5, 2.5), closeGap=True)),
    'generator_cylcone': ('facetCylinderConeGenerator', [(0, 0, 1), 1, 2], dict(segmentsNumber=5, radiusBottom=0.7)),
    'generator_cylcone_default_bottom': ('facetCylinderConeGenerator', [(0, 0, 1), 1, 2], dict(segmentsNumber=4)),
    'bunker': ('facetBunker', [(0, 0, 0)], dict(dBunker=2, dOutput=1, hBunker=3, hOutput=1, hPipe=0.5, segmentsNumber=5)),
    'bunker_all': ('facetBunker', [(0, 0, 0)], dict(dBunker=2, dOutput=1, hBunker=3, hOutput=1, hPipe=0.5, segmentsNumber=5, wallMask=7)),
    'bunker_nopipe': ('facetBunker', [(0, 0, 0)], dict(dBunker=2, dOutput=1, hBunker=3, hOutput=1, segmentsNumber=5, wallMask=7)),
    'bunker_oriented_gap': ('facetBunker', [(1, 2, 3)], dict(dBunker=2, dOutput=1, hBunker=3, hOutput=1, hPipe=0.5, orientation=Q, segmentsNumber=3, angleRange=(0, pi / 2), closeGap=True, wallMask=7)),
    'bunker_default': ('facetBunker', [(0, 0, 0), 3, 1, 2, 1], {}),
    'helix': ('facetHelix', [(0, 0, 0)], dict(radiusOuter=2, pitch=1, segmentsNumber=4, radiusInner=0.5)),
    'helix_turns': ('facetHelix', [(0, 0, 0)], dict(radiusOuter=2, pitch=1, segmentsNumber=4, angleRange=(0, 4 * pi))),
    'helix_range': ('facetHelix', [(0, 0, 0)], dict(radiusOuter=2, pitch=1, segmentsNumber=3, angleRange=(pi / 2, 3 * pi / 2), radiusInner=1)),
    'helix_decreasing': ('facetHelix', [(0, 0, 0)], dict(radiusOuter=2, pitch=1, segmentsNumber=3, angleRange=(2 * pi, 0), radiusInner=0.5)),
    'polygon_decreasing': ('facetPolygon', [(0, 0, 0), 2], dict(segmentsNumber=3, angleRange=(pi, 0))),
    'helix_oriented': ('facetHelix', [(1, 1, 1), 2, 0.5], dict(orientation=Q, segmentsNumber=6, radiusInner=0.2)),
    'polygon_ring': ('facetPolygon', [(0, 0, 0), 2], dict(segmentsNumber=4, radiusInner=1, angleRange=(0, pi))),
    'polygon_fan': ('facetPolygon', [(0, 0, 0), 2], dict(segmentsNumber=3, angleRange=(pi / 2, 3 * pi / 2))),
    'polygon_oriented': ('facetPolygon', [(1, 2, 3), 1.5], dict(orientation=Q, segmentsNumber=5, angleRange=(0, 2 * pi))),
    'polygon_default_range': ('facetPolygon', [(0, 0, 0), 2], dict(segmentsNumber=4)),
    'generator_polyhelix': ('facetPolygonHelixGenerator', [(0, 0, 0), 2], dict(pitch=1, segmentsNumber=5, radiusInner=0.5)),
    'parallelepiped': ('facetParallelepiped', [(0, 0, 0), (1, 2, 3)], dict(height=1)),
    'parallelepiped_oriented': ('facetParallelepiped', [(1, 1, 1), (1, 2, 3)], dict(height=2, orientation=Q, wallMask=45)),
    'sphere': ('facetSphere', [(0, 0, 0), 1], dict(thetaResolution=4, phiResolution=4)),
    'sphere_bands': ('facetSphere', [(1, 2, 3), 2], dict(thetaResolution=5, phiResolution=6)),
    'sphere_default': ('facetSphere', [(0, 0, 0), 1], {}),
    'sphere_map': ('facetSphere', [(1, 2, 3), 1], dict(thetaResolution=3, phiResolution=5, returnElementMap=True)),
    'box_flat': ('facetBox', [(0, 0, 0), (1, 0, 3)], {}),
    # refused input
    'err_cylinder_segments': ('facetCylinder', [(0, 0, 0), 1, 2], dict(segmentsNumber=2)),
    'err_cylinder_radius': ('facetCylinder', [(0, 0, 0), -1, 2], {}),
    'err_cylinder_radius0': ('facetCylinder', [(0, 0, 0), 0, 2], {}),
    'err_cylinder_height': ('facetCylinder', [(0, 0, 0), 1, -2], {}),
    'err_cylinder_range_reversed': ('facetCylinder', [(0, 0, 0), 1, 2], dict(angleRange=(pi / 2, 0))),
    'err_cylinder_range_large': ('facetCylinder', [(0, 0, 0), 1, 2], dict(angleRange=(0, 7))),
    'err_cylinder_inner': ('facetCone', [(0, 0, 0), 1, 2, 2], dict(radiusTopInner=1.5)),
    'err_helix_segments': ('facetHelix', [(0, 0, 0), 2, 1], dict(segmentsNumber=2)),
    'err_helix_radius': ('facetHelix', [(0, 0, 0), -2, 1], {}),
    'err_helix_pitch': ('facetHelix', [(0, 0, 0), 2, -1], {}),
    'err_helix_pitch0': ('facetHelix', [(0, 0, 0), 2, 0], {}),
    'err_polygon_radius': ('facetPolygon', [(0, 0, 0), -1], dict(angleRange=(0, 1))),
    'err_bunker_diameter': ('facetBunker', [(0, 0, 0), -2, 1, 3, 1], {}),
    'err_bunker_output': ('facetBunker', [(0, 0, 0), 2, -1, 3, 1], {}),
    'err_bunker_height': ('facetBunker', [(0, 0, 0), 2, 1, -3, 1], {}),
    'err_bunker_pipe': ('facetBunker', [(0, 0, 0), 2, 1, 3, 1], dict(hPipe=-1)),
    'err_parallelepiped_height': ('facetParallelepiped', [(0, 0, 0), (1, 2, 1)], dict(height=2)),
    'err_sphere_theta': ('facetSphere', [(0, 0, 0), 1], dict(thetaResolution=2)),
    'err_sphere_phi': ('facetSphere', [(0, 0, 0), 1], dict(phiResolution=2)),
    'err_sphere_radius': ('facetSphere', [(0, 0, 0), -1], {}),
}


def facets(fs):
    return [[f.state.pos + f.state.ori * v for v in f.shape.vertices] for f in fs]


def run(name, args, kw):
    out = getattr(geom, name)(*args, **kw)
    if isinstance(out, tuple):  # facetSphere(returnElementMap=True)
        return {'facets': facets(out[0]), 'nodes': list(out[1]), 'elements': [list(e) for e in out[2]]}
    res = {'facets': facets(out)}
    if 'color' in kw:
        res['attrs'] = [[list(f.shape.color), f.shape.wire, f.mask, f.dynamic] for f in out]
    return res


# each case: the call ([function, args, kwargs], orientation as [w, x, y, z]) and its result
dump('geom', {case: {'call': list(spec), 'result': catch(lambda: run(*spec))} for case, spec in CASES.items()})
