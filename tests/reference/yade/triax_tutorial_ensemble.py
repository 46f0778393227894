# triax_tutorial_ensemble: the spread of YADE 2023.02a's results on the triax tutorial with its stages enabled
# (examples/triax-tutorial/script-session1-stages.py), to judge granum's statistically: the runs are chaotic, so
# one run of one packing is one draw. For makeCloud seeds 1-25 (`yade -n -j1`) and seed 1 under -j2, -j3, -j4
# (other summation orders, the same packing), per run: the porosity after confinement (iter 8000) and after
# compaction (18000), the peak deviator max(s22 - s11), the final porosity, and the mean deviator in the axial
# strain bins [0, .01), [.01, .02), [.02, .03), [.04, .05), [.08, .09).
# Regenerate (about 25 min): cd tests/reference/yade && python3 triax_tutorial_ensemble.py
# (it runs YADE once per entry in a temporary folder; `--from DIR` summarises runs already made in DIR/<name>/).
import json
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', '..', '..', 'examples', 'triax-tutorial', 'script-session1-stages.py')
RUNS = [('s%d_j1' % s, s, 1) for s in range(1, 26)] + [('s1_j%d' % j, 1, j) for j in (2, 3, 4)]
BINS = (0.0, 0.01, 0.02, 0.04, 0.08)


def summarise(folder):
    log = open(os.path.join(folder, 'log.txt')).read()
    with open(os.path.join(folder, 'results_triax_base_')) as f:
        names = f.readline().lstrip('#').split()
        rows = [dict(zip(names, map(float, line.split()))) for line in f if line.strip()]
    q = [r['s22'] - r['s11'] for r in rows]
    e = [r['e22'] for r in rows]
    binned = []
    for lo in BINS:
        sel = [qq for qq, ee in zip(q, e) if lo <= ee < lo + 0.01]
        binned.append(sum(sel) / len(sel))
    return {'porosity_confined': float(re.search(r'confined:.*porosity (\S+)', log).group(1)),
            'porosity_compacted': float(re.search(r'compacted:.*porosity (\S+)', log).group(1)),
            'peak_deviator': max(q), 'porosity_final': rows[-1]['porosity'], 'deviator_bins': binned}


def main():
    src = sys.argv[sys.argv.index('--from') + 1] if '--from' in sys.argv else None
    out = {'bins_lower_e22': list(BINS), 'runs': {}}
    for name, seed, j in RUNS:
        if src:
            folder = os.path.join(src, name)
        else:
            folder = tempfile.mkdtemp(prefix='triax_' + name)
            with open(os.path.join(folder, 'log.txt'), 'w') as log:
                subprocess.run(['yade', '-n', '-j%d' % j, '-x', SCRIPT], cwd=folder, stdout=log,
                               stderr=subprocess.STDOUT, env=dict(os.environ, TRIAX_SEED=str(seed)), check=True)
        out['runs'][name] = dict(seed=seed, threads=j, **summarise(folder))
    with open(os.path.join(HERE, 'triax_tutorial_ensemble.json'), 'w') as f:
        json.dump(out, f, indent=1)
    print('wrote triax_tutorial_ensemble.json')


if __name__ == '__main__':
    main()
