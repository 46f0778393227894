# The spread of what YADE's examples/test/psd.py draws at random: the sphere counts of its free clouds
# (makeCloud without num or seed) and the PSDs the harness compares. Each cloud is a random draw, so the
# tolerances of tools/yade_examples.toml's n0, n3, n4, psd0, psd3n and psd4m cover the range these values take
# over many draws, in YADE and in granum.
#
#     yade -n -x tools/psd_cloud_spread.py       # real YADE
#     granum tools/psd_cloud_spread.py           # granum
#
# Prints, for each cloud, the least, median and largest count of DRAWS clouds (default 200), and for each PSD
# point the least, median and largest value.
import os

from yade import pack

draws = int(os.environ.get('DRAWS', '200'))
psdSizes, psdCumm = [.02, 0.04, 0.045, .05, .06, .08, .12], [0., 0.1, 0.3, 0.3, .3, .7, 1.]
# name: makeCloud's arguments, and the PSD the harness probes (bins, mass)
clouds = {
    'n0': (dict(psdSizes=psdSizes, psdCumm=psdCumm, distributeMass=True), ('psd0', 10, True)),
    'n3': (dict(rMean=0.03, rRelFuzz=2 / 3., distributeMass=False), ('psd3n', 6, False)),
    'n4': (dict(rMean=0.03, rRelFuzz=2 / 3., distributeMass=True), ('psd4m', 6, True)),
}


def spread(values):
    """least, median, largest of ``values``"""
    values = sorted(values)
    return values[0], values[len(values) // 2], values[-1]


for name, (kw, (psd_name, bins, mass)) in clouds.items():
    counts, psds = [], []
    for _ in range(draws):
        sp = pack.SpherePack()
        sp.makeCloud((0, 0, 0), (1, 1, 1), **kw)
        counts.append(len(sp))
        psds.append(list(sp.psd(bins=bins, mass=mass)[1]))
    least, median, largest = spread(counts)
    print(f'{name}: {draws} clouds, least {least}, median {median}, largest {largest}')
    for k in range(len(psds[0])):
        least, median, largest = spread([p[k] for p in psds])
        print(f'  {psd_name}[{k}]: least {least:.4f}, median {median:.4f}, largest {largest:.4f}')
