# qt.Renderer() clipping planes (clipPlaneSe3, clipPlaneActive): their defaults, and which bodies YADE's 3D
# view draws with planes on. Needs the Qt view: run with a display, not with -n:
#   cd tests/reference/yade && xvfb-run -a -s "-screen 0 1024x768x24" yade -x clip_planes.py
# Three spheres of radius 0.5 seen down -z: red centred at x=-0.3 and green at x=+0.3 (both cut by the plane
# x=0), blue at x=-2. A sphere is "drawn" when more than 200 pixels of the snapshot have its colour.
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[-1])))
from _common import dump, tojson
from PyQt5 import QtWidgets
from yade import qt, utils

O.bodies.append([utils.sphere((-0.3, 0, 0), 0.5, color=(1, 0, 0)), utils.sphere((0.3, 1.2, 0), 0.5, color=(0, 1, 0)),
                 utils.sphere((-2, 0, 0), 0.5, color=(0, 0, 1))])
r = qt.Renderer()
data = {"defaults": {"clipPlaneSe3": tojson(r.clipPlaneSe3), "clipPlaneActive": tojson(r.clipPlaneActive)}}
v = qt.View()
v.viewDir, v.upVector = (0, 0, -1), (0, 1, 0)
v.fitAABB((-3, -1, -1), (1, 2, 1))
identity = ((0, 0, 0), Quaternion((1, 0, 0), 0))
to_x, to_minus_x = Quaternion((0, 1, 0), math.pi / 2), Quaternion((0, 1, 0), -math.pi / 2)
cases = {
    "off": ([((0, 0, 0), to_x), identity, identity], [False, False, False]),
    "x_at_0": ([((0, 0, 0), to_x), identity, identity], [True, False, False]),
    "minus_x_at_0": ([((0, 0, 0), to_minus_x), identity, identity], [True, False, False]),
    "second_plane_minus_x_at_-1": ([identity, ((-1, 0, 0), to_minus_x), identity], [False, True, False]),
    "x_at_-2.4_and_minus_x_at_0.2": ([((-2.4, 0, 0), to_x), ((0.2, 0, 0), to_minus_x), identity],
                                     [True, True, False]),
}


def settle(seconds):
    for _ in range(int(seconds / 0.05)):
        QtWidgets.QApplication.processEvents()
        time.sleep(0.05)


def drawn(path):
    from PIL import Image
    import numpy as np
    a = np.asarray(Image.open(path).convert("RGB")).astype(int)
    r_, g, b = a[..., 0], a[..., 1], a[..., 2]
    return {"red": int(((r_ > g + 60) & (r_ > b + 60)).sum()) > 200,
            "green": int(((g > r_ + 60) & (g > b + 60)).sum()) > 200,
            "blue": int(((b > r_ + 60) & (b > g + 60)).sum()) > 200}


data["normals"] = {"to_x": tojson(to_x * Vector3(0, 0, 1)), "to_minus_x": tojson(to_minus_x * Vector3(0, 0, 1))}
data["cases"] = {}
for name, (se3, active) in cases.items():
    r.clipPlaneSe3, r.clipPlaneActive = se3, active
    settle(1.0)
    path = f"/tmp/clip_planes_{name}.png"
    v.saveSnapshot(path)
    settle(1.5)
    data["cases"][name] = {"clipPlaneSe3": tojson(r.clipPlaneSe3), "clipPlaneActive": tojson(r.clipPlaneActive),
                           "drawn": drawn(path)}
dump("clip_planes", data)
