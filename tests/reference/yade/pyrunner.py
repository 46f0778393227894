# pyrunner: when PyRunners fire (iterPeriod, virtPeriod, initRun, nDo, firstIterRun),
# what O.iter/O.time they see, what replacing O.engines from inside a PyRunner does,
# O.pause() inside a PyRunner, O.stopAtIter, O.run(n, True), and engine labels as
# globals inside PyRunner commands. O.dt = 0.25 (exact in binary) everywhere.
# Regenerate: cd tests/reference/yade && yade -n -x pyrunner.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump

log = []   # PyRunner commands run in this (__main__) namespace and append to it
def P(name, **kw):
    return PyRunner(command='log.append(("%s", O.iter, O.time))' % name, label=name, **kw)

def fresh(engines):
    O.reset()
    del log[:]
    O.bodies.append(utils.sphere((0, 0, 0), .5))
    O.engines = engines
    O.dt = 0.25

out = {}
# 1. firing schedule over 20 steps (O.step() x 20)
runners = {
    'iter3': dict(iterPeriod=3),
    'iter3_initRun': dict(iterPeriod=3, initRun=True),
    'iter1_nDo5': dict(iterPeriod=1, nDo=5),
    'iter1_nDo1': dict(iterPeriod=1, nDo=1),
    'iter1_nDo1_initRun': dict(iterPeriod=1, nDo=1, initRun=True),
    'iter3_nDo2_initRun': dict(iterPeriod=3, nDo=2, initRun=True),
    'iter4_firstIterRun10': dict(iterPeriod=4, firstIterRun=10),
    'iter1_firstIterRun5': dict(iterPeriod=1, firstIterRun=5, nDo=3),
    'virt0p5': dict(virtPeriod=0.5),
    'virt0p6': dict(virtPeriod=0.6),
    'virt0p5_initRun': dict(virtPeriod=0.5, initRun=True),
    'iter0_virt0_real0': dict(),
}  # keys are labels: they must be Python identifiers (YADE executes '__builtins__.<label>=...')
fresh([ForceResetter(), P('before_newton', iterPeriod=1)] + [P(k, **v) for k, v in runners.items()]
      + [NewtonIntegrator(), P('after_newton', iterPeriod=1)])
for i in range(20):
    O.step()
out['schedule'] = {
    'setup': 'engines: ForceResetter, before_newton(iterPeriod=1), <runners in this order>, NewtonIntegrator, '
             'after_newton(iterPeriod=1); O.dt=0.25; 20 x O.step(); log entries are (label, O.iter, O.time) '
             'as seen inside the command',
    'runners': runners, 'log': list(log),
    'fired_at_iter': {k: [it for (n, it, t) in log if n == k] for k in ['before_newton', 'after_newton'] + list(runners)},
    'after': {e.label: {'nDone': e.nDone, 'iterLast': e.iterLast, 'virtLast': e.virtLast, 'nDo': e.nDo,
                        'dead': e.dead} for e in O.engines if isinstance(e, PyRunner)},
    'O.iter': O.iter, 'O.time': O.time}

# 2. replacing O.engines from inside a PyRunner (at iter 2)
fresh([ForceResetter(), P('a', iterPeriod=1),
       PyRunner(iterPeriod=1, label='changer', command='if O.iter == 2: log.append(("changer", O.iter, O.time)); '
                'O.engines = O.engines + [PyRunner(command="log.append((\'new\', O.iter, O.time))", iterPeriod=1)]'),
       P('b', iterPeriod=1), NewtonIntegrator()])
for i in range(5):
    O.step()
out['engines_appended_inside_pyrunner'] = {
    'setup': 'engines a, changer, b (all iterPeriod=1); at O.iter==2 changer sets O.engines = O.engines + [new]; 5 O.step()',
    'log': list(log), 'engines_after': [type(e).__name__ + ':' + e.label for e in O.engines]}
fresh([ForceResetter(), P('a', iterPeriod=1),
       PyRunner(iterPeriod=1, label='changer', command='if O.iter == 2: log.append(("changer", O.iter, O.time)); '
                'O.engines = [PyRunner(command="log.append((\'new\', O.iter, O.time))", iterPeriod=1)] + O.engines[:1]'),
       P('b', iterPeriod=1), NewtonIntegrator()])
for i in range(5):
    O.step()
out['engines_replaced_inside_pyrunner'] = {
    'setup': 'engines a, changer, b (all iterPeriod=1); at O.iter==2 changer sets O.engines = [new, ForceResetter] '
             '(drops a, changer, b and Newton); 5 O.step()',
    'log': list(log), 'engines_after': [type(e).__name__ + ':' + e.label for e in O.engines]}

# 3. O.pause() inside a PyRunner
fresh([ForceResetter(), PyRunner(iterPeriod=5, label='pauser', command='log.append(("pauser", O.iter, O.time)); O.pause()'),
       P('after_pauser', iterPeriod=1), NewtonIntegrator()])
O.run(); O.wait()
out['pause_in_pyrunner_O.run()'] = {'setup': 'pauser (iterPeriod=5, calls O.pause()), after_pauser (iterPeriod=1); O.run(); O.wait()',
                                    'O.iter_after_wait': O.iter, 'O.time': O.time, 'log': list(log)}
it0 = O.iter
O.run(); O.wait()
out['pause_in_pyrunner_O.run()']['second_O.run()_stops_at'] = O.iter
fresh([ForceResetter(), PyRunner(iterPeriod=5, label='pauser', command='log.append(("pauser", O.iter, O.time)); O.pause()'),
       P('after_pauser', iterPeriod=1), NewtonIntegrator()])
O.run(20, True)
out['pause_in_pyrunner_O.run(20,True)'] = {'O.iter': O.iter, 'O.stopAtIter': O.stopAtIter, 'log': list(log)}

# 4. O.stopAtIter and O.run(n, True); 'safety' pauses at O.iter>=200 (a run that would never stop)
SAFETY = 'if O.iter >= 200: O.pause()'
fresh([ForceResetter(), NewtonIntegrator(), PyRunner(iterPeriod=1, command=SAFETY, label='safety')])
r = {'O.stopAtIter_fresh': O.stopAtIter}
O.stopAtIter = 7
O.run(); O.wait()
r['after_stopAtIter=7_O.run()_O.wait()'] = {'O.iter': O.iter, 'O.stopAtIter': O.stopAtIter}
O.run(5, True)
r['after_O.run(5,True)'] = {'O.iter': O.iter, 'O.stopAtIter': O.stopAtIter, 'O.time': O.time}
O.run(5); O.wait()
r['after_O.run(5)_O.wait()'] = {'O.iter': O.iter, 'O.stopAtIter': O.stopAtIter}
O.step()
r['after_O.step()'] = {'O.iter': O.iter, 'O.stopAtIter': O.stopAtIter}
fresh([ForceResetter(), NewtonIntegrator(), PyRunner(iterPeriod=1, command=SAFETY, label='safety')])
O.run(5, True)
r['fresh_O.run(5,True)'] = {'O.iter': O.iter, 'O.time': O.time, 'O.stopAtIter': O.stopAtIter}
O.stopAtIter = 3
O.run(); O.wait()
r['stopAtIter=3_below_current_iter_then_O.run()_O.wait()'] = {'O.iter': O.iter, 'O.stopAtIter': O.stopAtIter,
    'note': 'O.iter==200 means it did not stop by itself (stopped by the safety PyRunner)'}
out['stopAtIter'] = r

# 5. labels
fresh([ForceResetter(), NewtonIntegrator(damping=0.123, label='foo'),
       PyRunner(iterPeriod=1, initRun=True, command='log.append(("label", foo.damping, type(foo).__name__))')])
O.step()
import builtins

out['labels'] = {'log': list(log), "'foo' in globals() (script)": 'foo' in globals(),
                 "hasattr(builtins, 'foo')": hasattr(builtins, 'foo'),
                 'foo.damping (script)': catch(lambda: foo.damping)}
O.engines = [ForceResetter(), NewtonIntegrator(damping=0.456, label='foo')]
out['labels']['foo.damping after reassigning O.engines with a new foo'] = catch(lambda: foo.damping)
dump('pyrunner', out)
