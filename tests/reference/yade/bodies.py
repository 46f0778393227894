# bodies: what the utils body constructors (sphere, box, facet, wall, aabbWalls,
# geom.facetBox) produce: state (pos, ori, mass, inertia, blockedDOFs, ...),
# shape attributes, mask, bound, colour behaviour.
# Regenerate: cd tests/reference/yade && yade -n -x bodies.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
from yade import geom


def describe(b):
    s = b.state
    d = {'id': b.id, 'shape_class': type(b.shape).__name__, 'shape': b.shape.dict(),
         'color_type': type(b.shape.color).__name__,
         'state_class': type(s).__name__,
         'pos': s.pos, 'ori': s.ori, 'refPos': s.refPos, 'refOri': s.refOri,
         'vel': s.vel, 'angVel': s.angVel,
         'mass': s.mass, 'inertia': s.inertia, 'blockedDOFs': s.blockedDOFs,
         'dynamic': b.dynamic, 'isDamped': s.isDamped, 'aspherical': b.aspherical,
         'mask': b.mask, 'bound_is_None': b.bound is None,
         'bound_class': type(b.bound).__name__, 'material_id': b.material.id,
         'material_class': type(b.material).__name__}
    return d

out = {}
ctors = {
    'sphere((1,2,3),.5)': lambda: utils.sphere((1, 2, 3), .5),
    'sphere((1,2,3),.5,fixed=True)': lambda: utils.sphere((1, 2, 3), .5, fixed=True),
    'box((0,0,0),(1,2,3))': lambda: utils.box((0, 0, 0), (1, 2, 3)),
    'box((0,0,0),(1,2,3),fixed=True)': lambda: utils.box((0, 0, 0), (1, 2, 3), fixed=True),
    'facet([(0,0,0),(1,0,0),(0,1,0)])': lambda: utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)]),
    'facet([(1,1,1),(3,1,1),(1,4,2)])': lambda: utils.facet([(1, 1, 1), (3, 1, 1), (1, 4, 2)]),
    'wall(1.5,axis=2)': lambda: utils.wall(1.5, axis=2),
    'wall((0,0,1),axis=1,sense=-1)': lambda: utils.wall((0, 0, 1), axis=1, sense=-1),
}
for name, f in ctors.items():
    try:
        b = f()
        O.bodies.append(b)
        out[name] = describe(b)
    except Exception as e:
        out[name] = {'exception': type(e).__name__, 'message': str(e)}
# facet: global vertices = pos + ori*local vertex
f = O.bodies[4]
out['facet([(0,0,0),(1,0,0),(0,1,0)])']['global_vertices'] = [f.state.pos + f.state.ori * v for v in f.shape.vertices]
f = O.bodies[5]
out['facet([(1,1,1),(3,1,1),(1,4,2)])']['global_vertices'] = [f.state.pos + f.state.ori * v for v in f.shape.vertices]

# colours: default (random?) colours for consecutive spheres, and explicit color
out['sphere_colors_consecutive'] = [utils.sphere((0, 0, 0), 1).shape.color for _ in range(3)]
out['sphere_color_explicit'] = utils.sphere((0, 0, 0), 1, color=(1, 0, 0)).shape.color
out['box_colors_consecutive'] = [utils.box((0, 0, 0), (1, 1, 1)).shape.color for _ in range(2)]
out['facet_colors_consecutive'] = [utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)]).shape.color for _ in range(2)]
out['wall_colors_consecutive'] = [utils.wall(0, axis=2).shape.color for _ in range(2)]
out['sphere_wire_default'] = utils.sphere((0, 0, 0), 1).shape.wire
out['sphere_wire=True'] = utils.sphere((0, 0, 0), 1, wire=True).shape.wire
out['sphere_mask=5'] = utils.sphere((0, 0, 0), 1, mask=5).mask
out['bound_after_O.step'] = None  # filled below

O.bodies.clear()
ws = utils.aabbWalls([(0, 0, 0), (1, 1, 1)])
out['aabbWalls([(0,0,0),(1,1,1)])'] = [
    {'shape_class': type(w.shape).__name__, 'pos': w.state.pos, 'ori': w.state.ori,
     'extents': catch(lambda: w.shape.extents), 'dynamic': w.dynamic, 'mass': w.state.mass,
     'inertia': w.state.inertia, 'wire': w.shape.wire} for w in ws]
ws2 = utils.aabbWalls([(0, 0, 0), (1, 1, 1)], thickness=0.1)
out['aabbWalls([(0,0,0),(1,1,1)],thickness=0.1)'] = [
    {'pos': w.state.pos, 'extents': w.shape.extents} for w in ws2]

fb = geom.facetBox((0, 0, 0), (1, 2, 3), wallMask=31)
out['facetBox((0,0,0),(1,2,3),wallMask=31)'] = {
    'n_facets': len(fb),
    'facets': [{'pos': b.state.pos, 'ori': b.state.ori, 'normal': b.shape.normal,
                'area': b.shape.area, 'dynamic': b.dynamic,
                'global_vertices': [b.state.pos + b.state.ori * v for v in b.shape.vertices]}
               for b in fb]}
out['facetBox((0,0,0),(1,2,3)) default wallMask n_facets'] = len(geom.facetBox((0, 0, 0), (1, 2, 3)))

# does bound exist after a step? (bounds are created by the collider)
O.bodies.clear()
O.bodies.append([utils.sphere((0, 0, 0), .5), utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)]),
                 utils.wall(0, axis=2), utils.box((3, 3, 3), (1, 1, 1))])
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Wall_Aabb(), Bo1_Box_Aabb()]),
             NewtonIntegrator()]
O.dt = 1e-6
O.step()
out['bound_after_O.step'] = [{'bound_class': type(b.bound).__name__, 'min': b.bound.min, 'max': b.bound.max}
                             if b.bound else None for b in O.bodies]
dump('bodies', out)
