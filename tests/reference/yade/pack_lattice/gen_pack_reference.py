"""Record real YADE's yade.pack behaviour for granum's tests/test_pack.py.

Run with YADE 2023.02a (black box, nothing of YADE is copied):
    cd tests/reference/yade/pack_lattice && yade -n -x gen_pack_reference.py
Writes pack_reference.json next to this script: lattice centres (regularOrtho/regularHexa),
predicate answers on fixed points, makeCloud statistics over several seeds.
"""
import json
import os

import numpy as np
import yade
from yade import pack

P = pack


def make_pred(spec):
    """Build a predicate from a JSON spec: [name, args] or [op, specA, specB]."""
    ops = {"&": lambda a, b: a & b, "|": lambda a, b: a | b, "-": lambda a, b: a - b, "^": lambda a, b: a ^ b}
    if spec[0] in ops:
        return ops[spec[0]](make_pred(spec[1]), make_pred(spec[2]))
    return getattr(P, spec[0])(*spec[1])


def vec(v):
    return [float(v[0]), float(v[1]), float(v[2])]


R = .5 / 23.658
LATTICES = [
    ("hexa_sphere", "hexa", ["inSphere", [[0, 0, 0], .5]], R, .5 * R),
    ("ortho_box", "ortho", ["inAlignedBox", [[0, 0, 0], [1, 1, 1]]], .05, 0.),
    ("hexa_cylinder", "hexa", ["inCylinder", [[0, 0, 0], [0, 0, 1], .3]], .04, .005),
    ("ortho_cylinder", "ortho", ["inCylinder", [[0, 0, 0], [0, 0, 1], .3]], .04, .005),
    ("hexa_oblique_cylinder", "hexa", ["inCylinder", [[0, 0, 0], [1, 1, .5], .2]], .05, .01),
    ("hexa_box_tutorial04", "hexa", ["inAlignedBox", [[0, 0, 0], [2, 2, 2]]], .1, 0.),
    ("hexa_box_exact", "hexa", ["inAlignedBox", [[0, 0, 0], [1, 1, 1]]], .125, 0.),
    ("ortho_box_exact", "ortho", ["inAlignedBox", [[0, 0, 0], [1, 1, 1]]], .125, 0.),
    ("ortho_box_offset", "ortho", ["inAlignedBox", [[-1, .3, 2], [.5, 1, 3]]], .07, .02),
    ("hexa_box_offset", "hexa", ["inAlignedBox", [[-1, .3, 2], [.5, 1, 3]]], .07, .02),
    ("hexa_box_fraction", "hexa", ["inAlignedBox", [[0, 0, 0], [1, 1, 1]]], .2, 0.),
    ("ortho_box_negative_gap", "ortho", ["inAlignedBox", [[0, 0, 0], [.1, .1, .1]]], .01, -1e-8),
    ("ortho_sphere", "ortho", ["inSphere", [[1, 1, 1], .5]], .06, .01),
    ("hexa_ellipsoid", "hexa", ["inEllipsoid", [[.1, .2, .3], [.5, .3, .4]]], .04, 0.),
    ("hexa_box_minus_cylinder", "hexa",
     ["-", ["inAlignedBox", [[-2, -2, -2], [2, 2, 2]]], ["inCylinder", [[0, -2, 0], [0, 2, 0], 1]]], .2, 0.),
]

PREDICATES = {
    "box": ["inAlignedBox", [[0, 0, 0], [1, 1, 1]]],
    "sphere": ["inSphere", [[1, 2, 3], .5]],
    "cylinder_z": ["inCylinder", [[0, 0, 0], [0, 0, 1], .3]],
    "cylinder_oblique": ["inCylinder", [[0, 0, 0], [1, 1, 0], .2]],
    "ellipsoid": ["inEllipsoid", [[0, 0, 0], [1, 2, 3]]],
    "hyperboloid": ["inHyperboloid", [[0, 0, -.1], [0, 0, .1], .05, .03]],
    "notch": ["notInNotch", [[0, 0, 0], [0, 0, 1], [0, 1, 0], .1]],
    "notch_oblique": ["notInNotch", [[1, 2, 3], [1, 1, 0], [0, 1, 2], .2]],
    "parallelepiped": ["inParallelepiped", [[0, 0, 0], [1, 0, 0], [.5, 1, 0], [0, 0, 1]]],
    "union": ["|", ["inSphere", [[0, 0, 0], 1]], ["inAlignedBox", [[0, 0, 0], [3, .5, .5]]]],
    "intersection": ["&", ["inSphere", [[0, 0, 0], 1]], ["inAlignedBox", [[0, 0, 0], [3, .5, .5]]]],
    "difference": ["-", ["inAlignedBox", [[0, 0, 0], [3, .5, .5]]], ["inSphere", [[0, 0, 0], 1]]],
    "symmetric_difference": ["^", ["inSphere", [[0, 0, 0], 1]], ["inAlignedBox", [[0, 0, 0], [3, .5, .5]]]],
}
POINTS = [(0, 0, 0), (1, 1, 1), (.5, .5, .5), (1, 1, 1.0000001), (.9, .5, .5), (1, 2, 3), (1.5, 2, 3),
          (1.4, 2, 3), (0, 0, .5), (.3, 0, .5), (.2, 0, .5), (0, 0, 1), (0, 0, 1.01), (0, .29, 0),
          (.5, .5, 0), (.5, .6, 0), (1, 0, 0), (0, 2, 0), (0, 0, 3), (.7, 1.2, 0), (.6, 1.2, 1.5),
          (0, .04, 0), (0, .03, 0), (.04, 0, .1), (0, .05, 0), (0, -.05, 0), (0, .06, .5), (1, .04, 0),
          (-1, .04, 0), (0, .04, -3), (2, .3, .3), (.2, .2, .2), (.8, 0, 0), (.75, .5, .5),
          (.25, .75, .5), (1.1, .25, .25), (1.3, .25, .25), (.04, .085, 0), (.04, .075, 0), (-.5, .09, 0),
          (-.5, .11, 0), (.06, 0, 0), (.04, 0, 0), (-.5, .049, 0), (-.5, .05, 0), (.03, .09, 0),
          (2, 2, 3), (1, 1, 3), (1, 3, 3), (1, 2, 2), (1.5, 2.5, 3.1), (.5, 1.8, 3.3), (.049, 0, .1),
          (.049, 0, .09), (.04, 0, .05), (.035, 0, .05), (.033, 0, .05), (.03, 0, 0), (.029, 0, 0),
          (0, 0, .1), (0, 0, .095), (0, .03, -.05), (0, 0, -.1)]
PSD = {"psdSizes": [.04, .06, .1], "psdCumm": [0, .3, 1]}
PADS = [0, .001, .005, .01, .05, .1, .2, .3]

SEEDS = list(range(1, 9))
CLOUDS = [
    ("tutorial02", [[0, 0, 0], [1, 1, 1]], {"rMean": .05, "rRelFuzz": .5}),
    ("monodisperse", [[0, 0, 0], [1, 1, 1]], {"rMean": .05}),
    ("periodic_tutorial04", [[0, 0, 0], [2, 2, 2]], {"rMean": .1, "rRelFuzz": .6, "periodic": True}),
    ("periodic_doc", [[1, 1, 1], [2, 2, 2]], {"rMean": .16, "periodic": True}),
    ("num_porosity_positional", [[0, 0, 0], [1, 1, 1], -1, .3333, 200, False, .95], {}),
    ("num_porosity_retry", [[0, 0, 0], [1, 1, 1]], {"rRelFuzz": .3333, "num": 200, "porosity": .5}),
    ("num_rmean", [[0, 0, 0], [1, 1, 1]], {"rMean": .05, "rRelFuzz": .5, "num": 100}),
    ("num_rmean_too_many", [[0, 0, 0], [1, 1, 1]], {"rMean": .05, "rRelFuzz": .5, "num": 2000}),
    ("num_periodic_doc", [[0, 0, 0], [5, 5, 5]], {"rMean": .5, "rRelFuzz": .5, "periodic": True, "num": 20}),
    ("flat_2d", [[0, 0, 0], [1, 1, 0]], {"rMean": .05, "rRelFuzz": .5}),
    ("psd_number", [[0, 0, 0], [1, 1, 1]], dict(PSD)),
    ("psd_mass", [[0, 0, 0], [1, 1, 1]], dict(PSD, distributeMass=True)),
    ("psd_number_num", [[0, 0, 0], [1, 1, 1]], dict(PSD, num=50)),
    ("psd_mass_num", [[0, 0, 0], [1, 1, 1]], dict(PSD, num=50, distributeMass=True)),
]


def main():
    out = {"yade_version": str(yade.config.version), "lattices": [], "clouds": []}
    for name, kind, spec, radius, gap in LATTICES:
        fn = P.regularHexa if kind == "hexa" else P.regularOrtho
        bodies = fn(make_pred(spec), radius=radius, gap=gap)
        out["lattices"].append({"name": name, "kind": kind, "pred": spec, "radius": radius, "gap": gap,
                                "centers": [vec(b.state.pos) for b in bodies]})
    preds = {}
    for name, spec in PREDICATES.items():
        p = make_pred(spec)
        mn, mx = p.aabb()
        preds[name] = {"pred": spec, "aabb": [vec(mn), vec(mx)], "center": vec(p.center()),
                       "dim": vec(p.dim()), "inside": [[bool(p(pt, pad)) for pad in PADS] for pt in POINTS]}
    out["predicates"] = {"points": POINTS, "pads": PADS, "cases": preds}
    for name, args, kw in CLOUDS:
        rec = {"name": name, "args": args, "kwargs": kw, "seeds": SEEDS, "returned": [], "count": [],
               "mean_radius": [], "min_radius": [], "max_radius": []}
        for seed in SEEDS:
            sp = P.SpherePack()
            ret = sp.makeCloud(*args, seed=seed, **kw)
            r = np.array([x[1] for x in sp.toList()])
            rec["returned"].append(int(ret))
            rec["count"].append(len(sp))
            rec["mean_radius"].append(float(r.mean()))
            rec["min_radius"].append(float(r.min()))
            rec["max_radius"].append(float(r.max()))
            if seed == SEEDS[0]:
                if len(r) <= 200:  # deterministic sizes (num given) are compared one by one
                    rec["radii_seed1"] = [float(x) for x in r]
                rec["cellSize"] = vec(sp.cellSize)
                rec["isPeriodic"] = bool(sp.isPeriodic)
                rec["appliedPsdScaling"] = float(sp.appliedPsdScaling)
        out["clouds"].append(rec)
    # seeds: negative (default) is random per call, any seed >= 0 (0 included) is reproducible
    def first(**kw):
        sp = P.SpherePack()
        sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=.05, rRelFuzz=.5, **kw)
        return vec(sp[0][0])
    out["seed_behaviour"] = {"default_seed_repeats": first() == first(),
                             "seed0_repeats": first(seed=0) == first(seed=0),
                             "seed1_repeats": first(seed=1) == first(seed=1)}
    here = os.getcwd()  # under "yade -x", __file__ is YADE's own launcher
    with open(os.path.join(here, "pack_reference.json"), "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")


main()
