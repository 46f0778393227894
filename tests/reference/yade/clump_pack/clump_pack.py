# Reference data for SpherePack clumps (makeClumpCloud, getClumps, toSimulation, fromSimulation),
# utils.clumpTemplate and O.bodies.replaceByClumps, recorded from real YADE 2023.02a:
#
#   cd tests/reference/yade/clump_pack && yade -n -x clump_pack.py     (writes clump_pack.json)
#
# Random clouds differ between implementations, so clouds are summarised by counts and
# statistics; the API facts (return values, tuple shapes, id orders, errors) are exact.
import json, math, os, sys, time
import numpy as np
from yade import pack, utils

out = {'yade_version': version if 'version' in dir() else '2023.02a'}
TPL06 = [((0, 0, 0), .03333), ((.03, 0, 0), .017), ((0, .03, 0), .017)]   # tutorial 06


def arrays(sp):
    L = sp.toList()
    c = np.array([list(x[0]) for x in L]).reshape(-1, 3)
    r = np.array([x[1] for x in L])
    k = np.array([x[2] if len(x) > 2 else -1 for x in L], dtype=int)
    return c, r, k


def n_overlaps(c, r, k, period=None):
    """Pairs of spheres of different clumps (or standalone) that overlap (min image if periodic)."""
    d = c[:, None, :] - c[None, :, :]
    if period is not None:
        d -= period * np.round(d / period)
    dist = np.sqrt((d ** 2).sum(-1))
    bad = dist < r[:, None] + r[None, :] - 1e-12
    same = (k[:, None] == k[None, :]) & (k[:, None] >= 0)
    bad &= ~same
    np.fill_diagonal(bad, False)
    return int(bad.sum() // 2)


def err(fn):
    try:
        return {'value': repr(fn())}
    except Exception as e:
        return {'exception': type(e).__name__, 'message': str(e)}


# --- tutorial 06 packing
c1 = pack.SpherePack(TPL06)
sp = pack.SpherePack()
t0 = time.time()
ret = sp.makeClumpCloud((0, 0, 0), (2, 2, 2), [c1], periodic=True, num=500)
wall = time.time() - t0
c, r, k = arrays(sp)
alone, groups = sp.getClumps()
out['tutorial06'] = dict(
    ret=ret, len=len(sp), isPeriodic=sp.isPeriodic, cellSize=list(sp.cellSize), hasClumps=sp.hasClumps(),
    getClumps_type=type(sp.getClumps()).__name__, n_standalone=len(alone), n_clumps=len(groups),
    clump_sizes=sorted(set(len(g) for g in groups)), first_clumps=groups[:3],
    item_len=len(sp[0]), item0_clumpId=sp[0][2], toList_item_len=len(sp.toList()[0]),
    iter_item_len=[len(x) for x in sp][:3], clump_ids_first=[int(x) for x in k[:9]],
    ext_min=list((c - r[:, None]).min(0)), ext_max=list((c + r[:, None]).max(0)),
    ref_min=list(c.min(0)), ref_max=list(c.max(0)),
    overlaps_min_image=n_overlaps(c, r, k, np.array([2., 2, 2])), seconds=wall)

# template of a single sphere, and the template pack itself
one = pack.SpherePack([((0, 0, 0), .05)])
s1 = pack.SpherePack()
out['single_sphere_template'] = dict(ret=s1.makeClumpCloud((0, 0, 0), (1, 1, 1), [one], num=5, seed=1),
                                     getClumps=s1.getClumps(), item=[len(s1[0]), s1[0][2]])
out['template_pack'] = dict(hasClumps=c1.hasClumps(), getClumps=c1.getClumps(), item_len=len(c1[0]))

# --- counts with num=-1 (stop after 200 failed attempts), unit box
counts = {}
dyad = pack.SpherePack([((-.02, 0, 0), .03), ((.02, 0, 0), .03)])
for name, tpl in (('tpl06', c1), ('dyad', dyad)):
    for per in (False, True):
        n, ov, inside = [], 0, True
        for seed in range(1, 11):
            s = pack.SpherePack()
            n.append(s.makeClumpCloud((0, 0, 0), (1, 1, 1), [tpl], periodic=per, num=-1, seed=seed))
            if seed <= 2:
                cc, rr, kk = arrays(s)
                ov += n_overlaps(cc, rr, kk, np.array([1., 1, 1]) if per else None)
                inside &= bool(((cc - rr[:, None]).min() >= 0) and ((cc + rr[:, None]).max() <= 1))
        counts[f'{name}_{"periodic" if per else "aperiodic"}'] = dict(
            counts=n, mean=float(np.mean(n)), std=float(np.std(n)), overlaps_seed12=ov, all_inside_box=inside)
out['counts_num_-1'] = counts

# num larger than what fits: returns what was placed (a warning is logged)
s = pack.SpherePack()
out['num_too_large'] = dict(ret=s.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], num=3000, seed=1), len=len(s))

# same seed -> same cloud
a, b = pack.SpherePack(), pack.SpherePack()
a.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], num=20, seed=5)
b.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], num=20, seed=5)
out['seed_repeats'] = a.toList() == b.toList()

# several templates: chosen with equal chances, once per clump
ta, tb = pack.SpherePack([((0, 0, 0), .02)]), pack.SpherePack([((0, 0, 0), .02), ((.03, 0, 0), .02)])
tc = pack.SpherePack([((0, 0, 0), .02), ((.03, 0, 0), .02), ((0, .03, 0), .02)])
s = pack.SpherePack()
s.makeClumpCloud((0, 0, 0), (5, 5, 5), [ta, tb, tc], periodic=True, num=3000, seed=1)
out['template_choice_sizes'] = [int(x) for x in np.bincount([len(g) for g in s.getClumps()[1]], minlength=4)[1:]]

# orientation statistics: R recovered from a centred tetrahedral template
T = np.array([[0, 0, 0], [.4, 0, 0], [0, .4, 0], [0, 0, .4]])
tet = pack.SpherePack([(tuple(p), .01) for p in T - T.mean(0)])
s = pack.SpherePack()
s.makeClumpCloud((0, 0, 0), (10, 10, 10), [tet], periodic=True, num=20000, seed=1)
C = np.array([list(x[0]) for x in s]).reshape(-1, 4, 3)
Q = np.stack([(C[:, 1] - C[:, 0]) / .4, (C[:, 2] - C[:, 0]) / .4, (C[:, 3] - C[:, 0]) / .4], axis=-1)
tr = np.trace(Q, axis1=1, axis2=2)
out['orientation'] = dict(n=len(Q), mean_trace=float(tr.mean()), mean_trace2=float((tr ** 2).mean()),
                          mean_R=Q.mean(0).tolist(),
                          note='uniform rotations (Haar) give mean_trace 0, mean_trace2 1, mean_R 0')

# mixed pack: existing spheres kept and avoided, clump ids, second cloud, makeCloud after
m = pack.SpherePack()
m.makeCloud((0, 0, 0), (1, 1, 1), rMean=.1, num=5, seed=1)
ret = m.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], num=4, seed=2)
cc, rr, kk = arrays(m)
out['mixed'] = dict(ret=ret, len=len(m), getClumps=m.getClumps(), item_lens=[len(x) for x in m.toList()],
                    overlaps=n_overlaps(cc, rr, kk))
ret2 = m.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], num=2, seed=3)
out['second_cloud'] = dict(ret=ret2, clump_ids=[x[2] if len(x) > 2 else -1 for x in m.toList()],
                           getClumps=m.getClumps())
m2 = pack.SpherePack()
m2.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], num=2, seed=2)
out['makeCloud_after'] = dict(ret=m2.makeCloud((0, 0, 0), (1, 1, 1), rMean=.1, num=3, seed=1),
                              clump_ids=[x[2] if len(x) > 2 else -1 for x in m2.toList()])
f = pack.SpherePack([((0, 0, 0), .1, 5), ((1, 0, 0), .1, 2), ((2, 0, 0), .1, -1), ((3, 0, 0), .1, 5),
                     ((4, 0, 0), .1, 7)])
out['fromList_ids'] = dict(getClumps=f.getClumps(), item_lens=[len(x) for x in f.toList()])
p = pack.SpherePack()
p.makeCloud((0, 0, 0), (1, 1, 1), rMean=.05, num=3, periodic=True, seed=1)
p.makeClumpCloud((0, 0, 0), (4, 4, 4), [c1], num=3, seed=1, periodic=True)
out['periodic_flags'] = dict(after_periodic_makeCloud_then_clumps=[p.isPeriodic, list(p.cellSize)])
q = pack.SpherePack()
q.cellSize = (1, 1, 1)
out['periodic_flags']['cellSize_setter_sets_isPeriodic'] = q.isPeriodic

# save/load keep clump ids
path = os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), '_tmp_clumps.txt')
m.save(path)
lines = open(path).read().splitlines()
l2 = pack.SpherePack()
l2.load(path)
os.remove(path)
out['save_load'] = dict(last_line_fields=len(lines[-1].split()), getClumps_after_load=l2.getClumps())

# --- toSimulation: ids (spheres in pack order, then one clump per id in increasing order)
O.reset()
ids = f.toSimulation(color=(0, 1, 0))
out['toSimulation_ids'] = dict(ret=ids, bodies=[dict(id=b.id, isClump=b.isClump, clumpId=b.clumpId,
                                                     pos=list(b.state.pos)) for b in O.bodies])
O.reset()
s = pack.SpherePack()
s.makeClumpCloud((0, 0, 0), (1, 1, 1), [c1], periodic=True, num=3, seed=1)
ids = s.toSimulation()
out['toSimulation_clumps'] = dict(
    ret=ids, O_periodic=O.periodic, n_bodies=len(O.bodies),
    clump_mass=[O.bodies[i].state.mass for i in ids if O.bodies[i].isClump],
    member_mass_sum=[sum(O.bodies[j].state.mass for j in ids if O.bodies[j].clumpId == i and not O.bodies[j].isClump)
                     for i in ids if O.bodies[i].isClump],
    member_clumpIds=[O.bodies[i].clumpId for i in ids if not O.bodies[i].isClump])
s2 = pack.SpherePack()
s2.fromSimulation()
out['fromSimulation'] = dict(clump_ids=[x[2] if len(x) > 2 else -1 for x in s2.toList()], getClumps=s2.getClumps())

# --- utils.clumpTemplate
t = utils.clumpTemplate([1, 1, 1], [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
out['clumpTemplate'] = dict(attrs={kk: repr(v) for kk, v in sorted(t.__dict__.items())}, errors={
    'defaults': err(lambda: utils.clumpTemplate()),
    'one_member': err(lambda: utils.clumpTemplate([1], [(0, 0, 0)])),
    'lengths_differ': err(lambda: utils.clumpTemplate([1, 2], [(0, 0, 0)])),
    'not_3d': err(lambda: utils.clumpTemplate([1, 1], [(0, 0), (1, 0)])),
    'equal_positions': err(lambda: utils.clumpTemplate([1, 1, 2], [(0, 0, 0), (0, 0, 0), (1, 1, 1)])),
    'negative_radius_accepted': err(lambda: utils.clumpTemplate([1, -1], [(0, 0, 0), (1, 0, 0)]).numCM)})


# --- O.bodies.replaceByClumps
def scene(n=10, radius=lambda i: .1 + .01 * i):
    O.reset()
    m0 = O.materials.append(FrictMat(density=1000, label='m0'))
    m1 = O.materials.append(FrictMat(density=2000, label='m1'))
    O.bodies.append(utils.wall((0, 0, 0), 2))
    for i in range(n):
        O.bodies.append(utils.sphere((i, 0, 0), radius(i), material=(m1 if i % 2 else m0)))


dy = utils.clumpTemplate([1, 1], [(.5, 0, 0), (-.5, 0, 0)])
tri = utils.clumpTemplate([1, .5, .5], [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
rep = {}
scene()
ret = O.bodies.replaceByClumps([dy], [.5])
rep['dyad_half'] = dict(ret=ret, erased=[i for i in range(len(O.bodies)) if O.bodies[i] is None], clumps=[
    dict(pos=list(O.bodies[cid].state.pos), member_radii=[O.bodies[i].shape.radius for i in mem],
         member_mean=list(np.mean([list(O.bodies[i].state.pos) for i in mem], axis=0)),
         member_materials=[O.bodies[i].material.label for i in mem], mass=O.bodies[cid].state.mass,
         member_mass_sum=sum(O.bodies[i].state.mass for i in mem)) for cid, mem in ret])
# YADE's volume estimate: (sphere radius / member radius)^3 / (sum... ) -> union volume in unit-sphere volumes
rep['dyad_scale_member_over_sphere_radius'] = rep['dyad_half']['clumps'][0]['member_radii'][0] / .1
for amounts in ([.3], [.25], [.1], [1.], [.7], [.05]):
    scene()
    O.bodies.replaceByClumps([dy], amounts)
    rep[f'replaced_{amounts[0]}'] = [i for i in range(1, 11) if O.bodies[i] is None]
for n, a in ((5, .5), (5, .3), (3, .5), (7, .5)):
    scene(n)
    O.bodies.replaceByClumps([dy], [a])
    rep[f'replaced_n{n}_{a}'] = [i for i in range(1, n + 1) if O.bodies[i] is None]
for amounts in ([.3, .3], [.2, .5], [.5, .5], [.1, .1]):
    scene()
    ret = O.bodies.replaceByClumps([dy, tri], amounts)
    # the mean of the member centres is the replaced sphere's centre, sphere i sits at x = i - 1
    rep[f'two_templates_{amounts}'] = dict(
        ret=ret, sizes=[len(m) for c, m in ret],
        replaced_per_clump=[int(round(np.mean([O.bodies[i].state.pos[0] for i in m]))) + 1 for c, m in ret])
scene()
tri_ret = O.bodies.replaceByClumps([tri], [.1])
cid, mem = tri_ret[0]
rep['triad_member_mean'] = list(np.mean([list(O.bodies[i].state.pos) for i in mem], axis=0))
scene(4)
O.bodies.clump([1, 2])
rep['existing_clump'] = O.bodies.replaceByClumps([dy], [1.])
O.reset()
rep['empty_scene'] = O.bodies.replaceByClumps([dy], [.5])
rep['errors'] = {}
for name, args in (('amounts_length', ([dy], [])), ('sum_above_1', ([dy, tri], [.6, .6])),
                   ('negative', ([dy], [-.1])), ('not_a_template', ([((0, 0, 0), 1)], [.5]))):
    scene()
    rep['errors'][name] = err(lambda: O.bodies.replaceByClumps(*args))
rep['zero_amount'] = 'not run: replaceByClumps([t], [a]) with round(a*N) == 0 kills YADE 2023.02a (SIGFPE)'
out['replaceByClumps'] = rep

with open(os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), 'clump_pack.json'), 'w') as fh:
    json.dump(out, fh, indent=1, default=repr)
print('wrote clump_pack.json')
