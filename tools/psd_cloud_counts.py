# The spread of the sphere counts of YADE's examples/test/psd.py's free clouds (makeCloud without num or seed):
# each is a random draw, so the tolerances of tools/yade_examples.toml's n0, n3 and n4 cover the range that
# the counts take over many draws, in YADE and in granum.
#
#     yade -n -x tools/psd_cloud_counts.py       # real YADE
#     granum tools/psd_cloud_counts.py           # granum
#
# Prints, for each cloud, the least, median and largest count of DRAWS clouds (default 200).
import os

from yade import pack

draws = int(os.environ.get('DRAWS', '200'))
psdSizes, psdCumm = [.02, 0.04, 0.045, .05, .06, .08, .12], [0., 0.1, 0.3, 0.3, .3, .7, 1.]
clouds = {
    'n0': dict(psdSizes=psdSizes, psdCumm=psdCumm, distributeMass=True),
    'n3': dict(rMean=0.03, rRelFuzz=2 / 3., distributeMass=False),
    'n4': dict(rMean=0.03, rRelFuzz=2 / 3., distributeMass=True),
}
for name, kw in clouds.items():
    counts = []
    for _ in range(draws):
        sp = pack.SpherePack()
        sp.makeCloud((0, 0, 0), (1, 1, 1), **kw)
        counts.append(len(sp))
    counts.sort()
    print(f'{name}: {draws} clouds, least {counts[0]}, median {counts[draws // 2]}, largest {counts[-1]}')
