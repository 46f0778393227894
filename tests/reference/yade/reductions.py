# YADE 2023.02a reference for minieigen's reductions and products, whose last bit depends on the order of the
# operations: dot(), sum(), prod(), mean() of Vector2/3/6, trace(), determinant() and inverse() of Matrix3,
# Matrix3 * Vector3 and Matrix3 * Matrix3, for seeded random values (components spread over six orders of
# magnitude). Run: yade -n -x reductions.py  (writes reductions.json)
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump  # noqa: E402

rng = random.Random(20261206)


def numbers(k):
    return [rng.gauss(0.0, 1.0) * 10 ** rng.uniform(-3.0, 3.0) for _ in range(k)]


def vectors(cls, k):
    out = []
    for _ in range(50):
        a, b = cls(*numbers(k)), cls(*numbers(k))
        out.append({'a': a, 'b': b, 'dot': a.dot(b), 'sum': a.sum(), 'prod': a.prod(), 'mean': a.mean()})
    return out


def matrices():
    out = []
    for _ in range(50):
        m, n, v = Matrix3(*numbers(9)), Matrix3(*numbers(9)), Vector3(*numbers(3))
        out.append({'m': m, 'n': n, 'v': v, 'trace': m.trace(), 'determinant': m.determinant(),
                    'inverse': m.inverse(), 'm_v': m * v, 'm_n': m * n})
    return out


dump('reductions', {'Vector2': vectors(Vector2, 2), 'Vector3': vectors(Vector3, 3), 'Vector6': vectors(Vector6, 6),
                    'Matrix3': matrices()})
