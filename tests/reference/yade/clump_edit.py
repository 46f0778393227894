# clump_edit: clump mass properties (discretization grid), addToClump, releaseFromClump,
# updateClumpProperties, deleteClumpMember/deleteClumpBody, erase of clumps and members,
# getRoundness, and the errors of misuse (each error case in its own `yade -n -x` child, since
# some crash YADE).
# Every clump is recorded as: mass, pos (centre of mass), the principal inertia, the inertia
# tensor about the centre in the global frame (R diag(I) R^T, independent of the eigenvector
# choice), the member ids and the members' global positions.
# Regenerate: cd tests/reference/yade && yade -n -x clump_edit.py
# YADE 2023.02a
import sys; import os; import json; import re; import subprocess; import tempfile; import warnings
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson


def clump(cid):
    b = O.bodies[cid]
    if b is None:
        return None
    R = b.state.ori.toRotationMatrix()
    I = b.state.inertia
    D = Matrix3(I[0], 0, 0, 0, I[1], 0, 0, 0, I[2])
    # converted now: state vectors are references into the live state, which later edits change
    return tojson({'mass': b.state.mass, 'pos': b.state.pos, 'inertia': I, 'tensor': R * D * R.transpose(),
                   'members': sorted(b.shape.members.keys()),
                   'member_pos': [O.bodies[i].state.pos for i in sorted(b.shape.members.keys())]})


def standalone(ids):
    return [None if O.bodies[i] is None else {'clumpId': O.bodies[i].clumpId, 'isStandalone': O.bodies[i].isStandalone}
            for i in ids]


out = {}

# --- the grid integration of overlapping members -----------------------------------------------
grid = {}
for d in [0, 1, 2, 5, 10, 20]:
    O.reset()
    cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((1, 0, 0), 1)], discretization=d)
    grid['two_overlapping_d%d' % d] = clump(cid)
O.reset()
cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1)], discretization=2)
grid['two_touching_d2'] = clump(cid)  # distance = r1 + r2: no overlap, the sum is used
for d in [0, 10]:
    O.reset()
    cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((1.5, .3, 0), .5), sphere((0, 2.5, 0), .4)],
                                      discretization=d)
    grid['three_apart_d%d' % d] = clump(cid)
O.reset()
cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((1, 0, 0), 1), sphere((0, 1, 0), 1)], 10)
grid['three_overlapping_d10'] = clump(cid)
O.bodies.releaseFromClump(ids[2], cid, 5)
grid['three_overlapping_d10_release_d5'] = clump(cid)
O.reset()
cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), .3), sphere((.2, .1, -.05), .25), sphere((.1, -.2, .1), .2)], 7)
grid['three_unequal_d7'] = clump(cid)
for order in ['light_first', 'heavy_first']:
    O.reset()
    m1 = O.materials.append(FrictMat(density=1000))
    m2 = O.materials.append(FrictMat(density=3000))
    a, b = (m1, m2) if order == 'light_first' else (m2, m1)
    cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1, material=a), sphere((1, 0, 0), 1, material=b)], 2)
    grid['densities_%s_d2' % order] = clump(cid)
# a member whose mass and inertia were edited: spheres are weighed from radius and density
O.reset()
a = O.bodies.append(sphere((0, 0, 0), 1))
b = O.bodies.append(sphere((3, 0, 0), 1))
O.bodies[a].state.mass = 100.
O.bodies[a].state.inertia = (5, 5, 5)
cid = O.bodies.clump([a, b])
grid['edited_member_mass_d0'] = clump(cid)
out['grid'] = grid

# --- addToClump / releaseFromClump ---------------------------------------------------------------
edit = {}
O.reset()
cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1)])
s = O.bodies.append(sphere((0, 2, 0), 1))
edit['before_add'] = clump(cid)
O.bodies.addToClump([s], cid)
edit['add_sphere'] = clump(cid)
edit['add_sphere_member'] = {'clumpId': O.bodies[s].clumpId, 'isClumpMember': O.bodies[s].isClumpMember}
O.bodies.releaseFromClump(s, cid)
edit['release_it_again'] = clump(cid)
edit['released'] = standalone([s])
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter('always')
    O.bodies.releaseFromClump(ids[0], cid)
    edit['release_from_two_members'] = {'clump': clump(cid), 'warnings': [str(x.message) for x in w],
                                        'member': standalone([ids[0]])}
for d in [0, 10]:
    O.reset()
    cid, ids = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1)])
    s = O.bodies.append(sphere((1, 1, 0), 1))
    O.bodies.addToClump([s], cid, d)
    edit['add_overlapping_d%d' % d] = clump(cid)
O.bodies.releaseFromClump(s, cid, 10)
edit['release_overlapping_d10'] = clump(cid)
for what in ['clump', 'member']:
    O.reset()
    c1, i1 = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1)])
    c2, i2 = O.bodies.appendClumped([sphere((0, 3, 0), 1), sphere((2, 3, 0), 1)])
    O.bodies.addToClump([c2 if what == 'clump' else i2[0]], c1)
    # YADE leaves the clumpId of the moved members at -1 (the next step then fails an assertion)
    edit['add_%s_of_other_clump' % what] = {'clump': clump(c1), 'other_clump': clump(c2), 'len': len(O.bodies)}
# the documentation's examples (addToClump-example.py): a sphere then a whole clump
O.reset()
mat = O.materials.append(FrictMat(young=1e6, poisson=0.3, density=1000, frictionAngle=1))
c1, _ = O.bodies.appendClumped([sphere([0, 0, 1], material=mat, radius=0.5), sphere([0.2, 0, 1], material=mat, radius=0.5)])
c2, _ = O.bodies.appendClumped([sphere([3, 1, 2], material=mat, radius=0.5), sphere([3.2, 1, 2], material=mat, radius=0.5)])
s = O.bodies.append(sphere([0, 0.2, 1], material=mat, radius=0.5))
O.bodies.addToClump([s], c1)
edit['example_add_sphere'] = clump(c1)
O.bodies.addToClump([c2], c1)
edit['example_add_clump'] = clump(c1)
out['edit'] = edit

# --- erase, deleteClumpMember, deleteClumpBody, updateClumpProperties ------------------------------
upd = {}
O.reset()
c1, i1 = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1), sphere((0, 2, 0), .5)])
O.bodies.erase(i1[2])
upd['erase_member'] = {'clump': clump(c1), 'erased': O.bodies[i1[2]] is None, 'len': len(O.bodies)}
O.bodies.erase(c1)
upd['erase_clump'] = {'clump': clump(c1), 'members': standalone(i1[:2])}
O.reset()
c1, i1 = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1), sphere((0, 2, 0), .5)])
O.bodies.deleteClumpMember(O.bodies[c1], O.bodies[i1[2]])
upd['deleteClumpMember'] = {'clump': clump(c1), 'erased': O.bodies[i1[2]] is None}
O.bodies.deleteClumpBody(O.bodies[c1])
upd['deleteClumpBody'] = {'clump': clump(c1), 'members': standalone(i1)}
O.reset()
c1, i1 = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((1, 0, 0), 1), sphere((0, 2, 0), .5)])
c2, i2 = O.bodies.appendClumped([sphere((5, 0, 0), 1), sphere((6, 0, 0), 1)])
O.bodies.updateClumpProperties()
upd['default'] = [clump(c1), clump(c2)]
O.bodies.updateClumpProperties([c2], 20)
upd['exclude_c2_d20'] = [clump(c1), clump(c2)]
O.bodies.updateClumpProperties(discretization=0)
upd['d0'] = [clump(c1), clump(c2)]
O.bodies[i1[0]].shape.radius = 1.5
O.bodies.updateClumpProperties(discretization=0)
upd['d0_after_radius_1.5'] = [clump(c1), clump(c2)]
out['update'] = upd

# --- getRoundness ----------------------------------------------------------------------------------
rc = {}
rc['clumps'] = {'none': O.bodies.getRoundness(), 'exclude_c1': O.bodies.getRoundness([c1]),
                'exclude_members_of_c1': O.bodies.getRoundness(i1), 'exclude_both': O.bodies.getRoundness([c1, c2])}
O.bodies.append(sphere((10, 0, 0), 1))
rc['with_sphere'] = {'none': O.bodies.getRoundness(), 'exclude_clumps': O.bodies.getRoundness([c1, c2])}
O.bodies.append(box((0, 0, -5), (1, 1, 1)))
rc['with_box'] = O.bodies.getRoundness()
O.reset()
O.bodies.append(sphere((10, 0, 0), 1))
rc['spheres_only'] = O.bodies.getRoundness()
O.reset()
rc['empty'] = O.bodies.getRoundness()
O.reset()
cid = O.bodies.clump([O.bodies.append(box((0, 0, -5), (1, 1, 1))), O.bodies.append(sphere((0, 0, -7), 1))])
rc['box_sphere_clump'] = {'clump': clump(cid), 'rc': O.bodies.getRoundness()}
out['roundness'] = rc

# --- misuse, one child process each ------------------------------------------------------------------
PRELUDE = '''
import json, sys
sys.path.insert(0, %r)
from _common import tojson
c1, i1 = O.bodies.appendClumped([sphere((0, 0, 0), 1), sphere((2, 0, 0), 1), sphere((0, 2, 0), .5)])
c2, i2 = O.bodies.appendClumped([sphere((5, 0, 0), 1), sphere((7, 0, 0), 1)])
s = O.bodies.append(sphere((0, -3, 0), 1))
def state():
    return [None if b is None else [b.state.mass, b.state.pos, b.clumpId,
            sorted(b.shape.members.keys()) if b.isClump else None] for b in O.bodies]
def run():
%s
try:
    r = {'raised': False, 'value': tojson(run())}
except Exception as e:
    r = {'raised': True, 'exception': type(e).__name__, 'message': str(e)}
r['state'] = tojson(state())
print('RESULT' + json.dumps(r))
''' % (os.path.dirname(os.path.abspath(sys.argv[0])), '%s')
BANNER = ('RESULT', 'Welcome', 'Using python', 'TCP python', 'XMLRPC', 'Running script')


def case(code):
    body = '\n'.join('    ' + l for l in code.strip('\n').splitlines())
    path = os.path.join(tempfile.mkdtemp(), 'case.py')
    with open(path, 'w') as f:
        f.write(PRELUDE % body)
    p = subprocess.run(['yade', '-n', '-x', path], capture_output=True, text=True)
    res = [l[6:] for l in p.stdout.splitlines() if l.startswith('RESULT')]
    r = json.loads(res[0]) if res else {'result': None}
    r['returncode'] = p.returncode
    text = re.sub(r'\x1b\[[0-9;]*m', '', p.stdout + p.stderr)
    r['output'] = [l for l in text.splitlines() if l.strip() and not l.startswith(BANNER)]
    r['code'] = code.strip('\n')
    return r


out['errors'] = {
    'add own member': case('O.bodies.addToClump([i1[0]], c1)'),
    'add clump to itself': case('O.bodies.addToClump([c1], c1)'),
    'add unknown id': case('O.bodies.addToClump([999], c1)'),
    'add to a non-clump': case('O.bodies.addToClump([s], i2[0])'),
    'add to unknown clump': case('O.bodies.addToClump([s], 999)'),
    'add an int': case('O.bodies.addToClump(s, c1)'),
    'add good and unknown': case('O.bodies.addToClump([s, 999], c1)'),
    'release non-member': case('O.bodies.releaseFromClump(s, c1)'),
    'release member of other clump': case('O.bodies.releaseFromClump(i2[0], c1)'),
    'release from unknown clump': case('O.bodies.releaseFromClump(i1[0], 999)'),
    'release unknown body': case('O.bodies.releaseFromClump(999, c1)'),
    'deleteClumpMember non-member': case('O.bodies.deleteClumpMember(O.bodies[c1], O.bodies[s])'),
    'updateClumpProperties unknown exclude': case('O.bodies.updateClumpProperties([999])'),
    'getRoundness unknown exclude': case('return O.bodies.getRoundness([999])'),
}

dump('clump_edit', out)
