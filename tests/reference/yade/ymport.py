# ymport (stl, gmsh, unv, text, textExt, textFacets, textClumps), gts surfaces and the surface predicates of
# yade.pack, as YADE 2023.02a gives them. Small inputs are in ymport_data/; the meshes of YADE's examples are
# read from /usr/share/doc/yade/examples. Writes ymport.json.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, catch, tojson
from yade import ymport, pack
import gts

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
DATA = os.path.join(HERE, 'ymport_data')
EX = '/usr/share/doc/yade/examples'
O.materials.append(FrictMat(young=1e6, label='m0'))
O.materials.append(FrictMat(young=2e6, label='m1'))


def facets(bs):
    return [[b.state.pos + v for v in b.shape.vertices] for b in bs]


def spheres(bs):
    return [[b.state.pos, b.shape.radius, b.material.label] for b in bs]


out = {}
t = ymport.stl(os.path.join(DATA, 'tet.stl'), shift=Vector3(1, 2, 3), scale=2, color=(1, 0, 0), wire=False, fixed=False)
out['stl_tet'] = dict(vertices=facets(t), pos=[b.state.pos for b in t], wire=[b.shape.wire for b in t],
                      color=[b.shape.color for b in t], dynamic=[b.dynamic for b in t])
t = ymport.stl(os.path.join(DATA, 'tet.stl'))
out['stl_tet_default'] = dict(wire=[b.shape.wire for b in t], dynamic=[b.dynamic for b in t],
                              blocked=[b.state.blockedDOFs for b in t])
t = ymport.stl(EX + '/baraban/baraban.stl', material='m0')
out['stl_baraban'] = dict(n=len(t), first=facets(t[:3]), last=facets(t[-1:]), material=t[0].material.label)
t = ymport.gmsh(EX + '/hourglass/hourglass.mesh', shift=Vector3(0, 0, 1), scale=2, orientation=Quaternion((1, 0, 0), 0.5))
out['gmsh_hourglass'] = dict(n=len(t), first=facets(t[:3]), last=facets(t[-1:]))
t = ymport.unv(EX + '/test/unv-read/shell.unv', shift=(100, 200, 300), scale=1000)
out['unv_shell'] = dict(n=len(t), first=facets(t[:3]), last=facets(t[-1:]))
f, n, ct = ymport.unv(EX + '/test/unv-read/shell.unv', returnConnectivityTable=True)
out['unv_table'] = dict(nodes=n[:5], n_nodes=len(n), elements=ct[:5], n_elements=len(ct))
out['text'] = spheres(ymport.text(os.path.join(DATA, 'sph.txt'), shift=Vector3(1, 0, 0), scale=2))
out['textExt_matId'] = spheres(ymport.textExt(os.path.join(DATA, 'sphm.txt'), format='x_y_z_r_matId'))
out['textExt_bogus'] = catch(lambda: ymport.textExt(os.path.join(DATA, 'sph.txt'), format='bogus'))
out['textFacets'] = facets(ymport.textFacets(os.path.join(DATA, 'facets.txt'), shift=Vector3(0, 0, 1)))
out['textFacets_matId'] = [b.material.label for b in ymport.textFacets(os.path.join(DATA, 'facetsm.txt'), format='x1_y1_z1_x2_y2_z2_x3_y3_z3_matId')]
out['gts_returns'] = catch(lambda: ymport.gts(EX + '/gts-horse/horse.coarse.gts'))
O.bodies.clear()
r = ymport.textClumps(os.path.join(DATA, 'clumps.txt'), shift=Vector3(0, 0, 1), scale=2, orientation=Quaternion((0, 0, 1), 0.5))
out['textClumps'] = dict(ret=r, pos=[b.state.pos for b in O.bodies], isClump=[b.isClump for b in O.bodies],
                         radius=[getattr(b.shape, 'radius', None) for b in O.bodies])
O.bodies.clear()

# gts surfaces
s = gts.read(open(EX + '/gts-horse/horse.coarse.gts'))
out['horse'] = dict(closed=s.is_closed(), volume=s.volume(), area=s.area(), Nvertices=s.Nvertices, Nedges=s.Nedges,
                    Nfaces=s.Nfaces, facets=len(pack.gtsSurface2Facets(s)))
pred = pack.inGtsSurface(s)
mn, mx = pred.aabb()
out['horse_aabb'] = [mn, mx]
# a deterministic grid of points over the bounding box (and a little beyond), with and without padding
pts = [Vector3(mn[0] + (mx[0] - mn[0]) * (i + .37) / 17, mn[1] + (mx[1] - mn[1]) * (j + .29) / 23,
               mn[2] + (mx[2] - mn[2]) * (k + .41) / 19) for i in range(-1, 18) for j in range(-1, 24) for k in range(-1, 20)]
out['horse_inside'] = ''.join('01'[pred(p, 0)] for p in pts)  # the points: i, j, k nested, k fastest
out['horse_inside_pad'] = ''.join('01'[pred(p, 0.004)] for p in pts)
out['horse_regularHexa'] = len(pack.regularHexa(pred, radius=(mx[0] - mn[0]) / 40., gap=(mx[0] - mn[0]) / 160.))
s2 = gts.Surface()
s2.copy(s)
s2.translate(0.04, 0, 0)
u = s.union(s2)
out['horse_union'] = dict(volume=u.volume(), closed=u.is_closed())
c = gts.cube()
out['cube'] = dict(volume=c.volume(), area=c.area(), Nvertices=c.Nvertices, Nfaces=c.Nfaces)
c.scale(2, 3, 4)
c.rotate(0, 0, 1, 0.5)
c.translate(1, 2, 3)
out['cube_transformed'] = dict(volume=c.volume(), vertices=sorted(tuple(round(x, 12) for x in v.coords()) for v in c.vertices()))
out['open_surface_pred'] = catch(lambda: pack.inGtsSurface(pack.sweptPolylines2gtsSurface([[Vector3(0, 0, 0), Vector3(1, 0, 0)], [Vector3(0, 1, 0), Vector3(1, 1, 0)]])))
# gts-random-pack.py's surface of revolution
from numpy import arange
thetas = arange(0, pi / 2, pi / 24)
poly = ((1e-2, 5e-2), (5e-2, 2e-2), (7e-2, -2e-2), (1e-2, -5e-2), (1e-2, 5e-2))
pts3 = pack.revolutionSurfaceMeridians([[(pt[0], pt[1] + 1e-2 * theta) for pt in poly] for theta in thetas], thetas,
                                       origin=Vector3(0, -.05, .1), orientation=Quaternion((1, 1, 0), pi / 4))
out['meridians'] = pts3[:3]
surf = pack.sweptPolylines2gtsSurface(pts3, capStart=True, capEnd=True, threshold=1e-4)
out['revolution'] = dict(closed=surf.is_closed(), volume=catch(surf.volume), Nvertices=surf.Nvertices, Nfaces=surf.Nfaces)
sw = pack.sweptPolylines2gtsSurface([[Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(1, 1, 0)], [Vector3(0, 0, 1), Vector3(1, 0, 1), Vector3(1, 1, 1)]])
out['swept'] = dict(Nvertices=sw.Nvertices, Nfaces=sw.Nfaces, area=sw.area(), closed=sw.is_closed())
planes = [((0, 0, 0), (2, 0, 0)), ((1, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, 1, 0), (0, -1, 0)), ((0, 0, 0), (0, 0, 1)),
          ((0, 0, 1), (0, 0, -1)), ((0, 0, 1.5), (-1, -1, -1))]
p = pack.inConvexPolyhedron(planes)
probe = [((0.5, 0.5, 0.5), 0.1), ((0.2, 0.2, 0.2), 0.1), ((0.5, 0.5, 0.5), 0.2), ((0.6, 0.6, 0.2), 0.05), ((0.6, 0.6, 0.2), 0.01),
         ((0.9, 0.1, 0.1), 0.05), ((1.1, 0.5, 0.5), 0)]
out['convex'] = dict(aabb=p.aabb(), probes=[[pt, pad, p(pt, pad)] for pt, pad in probe])
out['convex_unbounded'] = catch(lambda: pack.inConvexPolyhedron([((0, 0, 0), (1, 0, 0))]))
# rotating-cylinder.py's surface: a swept cylinder, then copy() adds a square's faces to it
import numpy
thetas = numpy.linspace(0, 2 * pi, 24, endpoint=True)
base = [Vector3(cos(th), sin(th), -1) for th in thetas]
cyl = pack.sweptPolylines2gtsSurface([base, [p + Vector3(0, 0, 2) for p in base]])
vv = [gts.Vertex(1, 1, 0), gts.Vertex(-1, 1, 0), gts.Vertex(-1, -1, 0), gts.Vertex(1, -1, 0)]
ee = [gts.Edge(vv[0], vv[1]), gts.Edge(vv[1], vv[2]), gts.Edge(vv[2], vv[3]), gts.Edge(vv[3], vv[0]), gts.Edge(vv[0], vv[2])]
sq = gts.Surface()
sq.add(gts.Face(ee[0], ee[1], ee[4]))
sq.add(gts.Face(ee[2], ee[3], ee[4]))
sq.translate(0, 0, -1)
cyl.copy(sq)
cyl.scale(.2, .2, .5)
cyl.rotate(1, 0, 0, -pi / 4)
fs = pack.gtsSurface2Facets(cyl)
out['rotating_cylinder'] = dict(Nfaces=cyl.Nfaces, Nvertices=cyl.Nvertices, area=cyl.area(), facets=len(fs),
                                vertex_sum=sum((b.state.pos + v for b in fs for v in b.shape.vertices), Vector3.Zero))
dump('ymport', out)
