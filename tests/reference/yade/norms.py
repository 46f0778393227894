# YADE 2023.02a reference for the norms of minieigen's types: squaredNorm() and norm() of seeded random Vector2,
# Vector3, Vector6, Matrix3 values and norm() of Quaternion values (components spread over ten orders of magnitude), with the
# components as YADE holds them; toAxisAngle() of 100 non-unit quaternions. Run: yade -n -x norms.py  (writes norms.json)
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump  # noqa: E402

rng = random.Random(20261205)


def numbers(k):
    return [rng.gauss(0.0, 1.0) * 10 ** rng.uniform(-5.0, 5.0) for _ in range(k)]


def case(value):
    out = {'value': value, 'norm': value.norm()}
    if hasattr(value, 'squaredNorm'):   # minieigen's Quaternion has norm() only
        out['squaredNorm'] = value.squaredNorm()
    return out


out = {
    'Vector2': [case(Vector2(*numbers(2))) for _ in range(100)],
    'Vector3': [case(Vector3(*numbers(3))) for _ in range(100)],
    'Vector6': [case(Vector6(*numbers(6))) for _ in range(100)],
    'Matrix3': [case(Matrix3(*numbers(9))) for _ in range(100)],
    'Quaternion': [case(Quaternion(*numbers(4))) for _ in range(100)],
}


def axis_angle(value):
    axis, angle = value.toAxisAngle()
    return {'value': value, 'axis': axis, 'angle': angle}


# toAxisAngle() of quaternions that are not unit: its axis is the vector part over its norm
out['toAxisAngle'] = [axis_angle(Quaternion(*[rng.gauss(0.0, 1.0) for _ in range(4)])) for _ in range(100)]
dump('norms', out)
