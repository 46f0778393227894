# errors: exception class and message (plus C++ log lines and the process exit code)
# that YADE produces for common misuse: bad body/interaction indices, duplicate append,
# invalid radius, negative dt, unknown attributes/keywords, and stepping scenes whose
# dispatchers lack a functor (Ig2 / Ip2 / Law2) for a contact.
# Some of these crash YADE (segfault / std::terminate), so every case runs in its own
# `yade -n -x` child process; 'returncode' is that child's exit status (negative =
# killed by signal: -11 SIGSEGV, -6 SIGABRT).
# Regenerate: cd tests/reference/yade && yade -n -x errors.py
# YADE 2023.02a
import sys; import os; import re; import json; import subprocess; import tempfile; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

# common set-up of every child: engines with only the sphere-sphere/FrictMat chain,
# two FrictMat spheres: 0 at origin, 1 far away
PRELUDE = '''
import json, sys
sys.path.insert(0, %r)
from _common import tojson
O.engines = [ForceResetter(),
             InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb(), Bo1_Facet_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(gravity=(0, 0, -10), damping=0)]
O.dt = 1e-5
O.bodies.append([utils.sphere((0, 0, 0), .5), utils.sphere((5, 0, 0), .5)])
def intrs():
    return [{'id1': i.id1, 'id2': i.id2, 'isReal': i.isReal, 'geom': type(i.geom).__name__,
             'phys': type(i.phys).__name__} for i in O.interactions.all(onlyReal=False)]
def run():
%s
try:
    r = {'raised': False, 'value': tojson(run())}
except Exception as e:
    r = {'raised': True, 'exception': type(e).__name__, 'message': str(e)}
print('RESULT' + json.dumps(r))
''' % (os.path.dirname(os.path.abspath(sys.argv[0])), '%s')
BANNER = ('RESULT', 'Welcome', 'Using python', 'TCP python', 'XMLRPC', 'Running script')

def case(code):
    """code: body of run(); what it returns is recorded (or the exception it raises)."""
    body = '\n'.join('    ' + l for l in code.strip('\n').splitlines())
    path = os.path.join(tempfile.mkdtemp(), 'case.py')
    with open(path, 'w') as f:
        f.write(PRELUDE % body)
    p = subprocess.run(['yade', '-n', '-x', path], capture_output=True, text=True)
    res = [l[6:] for l in p.stdout.splitlines() if l.startswith('RESULT')]
    r = json.loads(res[0]) if res else {'result': None}
    r['returncode'] = p.returncode
    text = re.sub(r'\x1b\[[0-9;]*m', '', p.stdout + p.stderr)  # drop terminal colour codes
    r['output'] = [l for l in text.splitlines() if l.strip() and not l.startswith(BANNER)]
    r['code'] = code.strip('\n')
    return r

TWO_STEPS = '''
O.step(); O.step()
return {'intrs': intrs(), 'f0': O.forces.f(0), 'vel1': O.bodies[1].state.vel}
'''
def contact_scene(body0, mat0='FrictMat()', mat1='FrictMat()', ip2=None, law2=None, ig2=None):
    s = 'O.bodies.clear()\nm0 = O.materials.append(%s)\nm1 = O.materials.append(%s)\n' % (mat0, mat1)
    s += 'O.bodies.append([%s, utils.sphere((0, 0, .49), .5, material=m1)])\n' % body0
    il = 'O.engines[2]'  # the InteractionLoop
    if ig2 is not None: s += '%s.geomDispatcher.functors = %s\n' % (il, ig2)
    if ip2 is not None: s += '%s.physDispatcher.functors = %s\n' % (il, ip2)
    if law2 is not None: s += '%s.lawDispatcher.functors = %s\n' % (il, law2)
    return case(s + TWO_STEPS)

SPH = 'utils.sphere((0, 0, -.5), .5, material=m0)'
out = {
 'O.bodies[1000]': case('return O.bodies[1000]'),
 'O.bodies[-1]': case('return O.bodies[-1].id'),
 'O.interactions[0,1] (absent)': case('return O.interactions[0, 1]'),
 'O.interactions.has(0,1) (absent)': case('return O.interactions.has(0, 1)'),
 'O.interactions[0,1000]': case('return O.interactions[0, 1000]'),
 'append same Body twice': case('''
b = utils.sphere((0, 0, 3), .5)
ids = [O.bodies.append(b)]
ids.append(O.bodies.append(b))
return {'ids': ids, 'len': len(O.bodies)}'''),
 'append same Body twice (record after first)': case('''
b = utils.sphere((0, 0, 3), .5)
first = O.bodies.append(b)
try:
    O.bodies.append(b)
except Exception as e:
    return {'first': first, 'exception': type(e).__name__, 'message': str(e), 'len': len(O.bodies), 'b.id': b.id}'''),
 'O.bodies.erase(1000)': case('return O.bodies.erase(1000)'),
 'O.bodies.erase(1) twice': case('return [O.bodies.erase(1), O.bodies.erase(1)]'),
 'O.bodies[1] after erase(1)': case('O.bodies.erase(1)\nreturn {"body": repr(O.bodies[1]), "len": len(O.bodies)}'),
 'utils.sphere(radius=-1)': case('s = utils.sphere((0, 0, 0), -1)\nreturn {"mass": s.state.mass, "inertia": s.state.inertia, "radius": s.shape.radius}'),
 'utils.sphere(radius=0)': case('s = utils.sphere((0, 0, 0), 0)\nreturn {"mass": s.state.mass, "inertia": s.state.inertia, "radius": s.shape.radius}'),
 'Sphere(radius=-1)': case('return Sphere(radius=-1).radius'),
 'O.step() with a radius-0 and a radius-(-1) sphere': case('''
O.bodies.append([utils.sphere((0, 0, 2), 0), utils.sphere((0, 0, 3), -1)])
O.step()
return {'pos': [b.state.pos for b in O.bodies], 'vel': [b.state.vel for b in O.bodies], 'intrs': intrs()}'''),
 'O.dt = -1': case('O.dt = -1\nreturn O.dt'),
 'O.dt = 0': case('O.dt = 0\nreturn O.dt'),
 'O.dt = 0 then O.step()': case('O.dt = 0\nO.step()\nreturn {"pos": O.bodies[0].state.pos, "time": O.time, "iter": O.iter}'),
 'O.dt = -1 with a GlobalStiffnessTimeStepper in O.engines': case('''
O.engines = O.engines + [GlobalStiffnessTimeStepper()]
O.dt = -1
return {'dt': O.dt, 'dynDt': O.dynDt}'''),
 'Sphere(radius=1).nonexistentAttr = 1, then read': case('s = Sphere(radius=1)\ns.nonexistentAttr = 1\nreturn s.nonexistentAttr'),
 'Sphere(radius=1).nonexistentAttr (read)': case('return Sphere(radius=1).nonexistentAttr'),
 'Sphere(radius=1, nonexistentAttr=1)': case('return Sphere(radius=1, nonexistentAttr=1).dict()'),
 'NewtonIntegrator(dampin=0.1)': case('return NewtonIntegrator(dampin=0.1).dict()'),
 'NewtonIntegrator(damping="abc")': case('return NewtonIntegrator(damping="abc").dict()'),
 'Sphere(radius=1).radius = "abc"': case('s = Sphere(radius=1)\ns.radius = "abc"\nreturn s.radius'),
 'NewtonIntegrator().gravity = (0, 0)': case('n = NewtonIntegrator()\nn.gravity = (0, 0)\nreturn n.gravity'),
 'utils.sphere((0,0),1) (2-vector centre)': case('return utils.sphere((0, 0), 1).state.pos'),
 'isinstance(ViscElMat(), FrictMat)': case('return isinstance(ViscElMat(), FrictMat)'),
 # stepping with missing functors; body 0 is the first argument, body 1 a sphere r=.5 at (0,0,.49)
 'step: control sphere+sphere, all functors present': contact_scene(SPH),
 'step: Box+Sphere, no Ig2_Box_Sphere': contact_scene('utils.box((0, 0, -1), (1, 1, 1), fixed=True, material=m0)'),
 'step: ViscElMat+FrictMat, only Ip2_FrictMat_FrictMat_FrictPhys': contact_scene(
     SPH, mat0='ViscElMat(tc=1e-3, en=.3, et=.3)'),
 'step: ViscElMat+FrictMat, only Ip2_ViscElMat_ViscElMat_ViscElPhys + its Law2': contact_scene(
     SPH, mat0='ViscElMat(tc=1e-3, en=.3, et=.3)', ip2='[Ip2_ViscElMat_ViscElMat_ViscElPhys()]',
     law2='[Law2_ScGeom_ViscElPhys_Basic()]'),
 'step: FrictPhys contact, only Law2_ScGeom_ViscElPhys_Basic': contact_scene(SPH, law2='[Law2_ScGeom_ViscElPhys_Basic()]'),
 'step: FrictPhys contact, empty Law2 list': contact_scene(SPH, law2='[]'),
 'step: FrictMat+FrictMat, empty Ip2 list': contact_scene(SPH, ip2='[]'),
 'step: empty Ig2 list': contact_scene(SPH, ig2='[]'),
}
dump('errors', out)
