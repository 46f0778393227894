"""granum starts and runs where Linux-only modules and optional packages are missing: without ``fcntl``
(as on Windows) and without SciPy (compiled code must not need its LAPACK); the closed-form 3x3
determinant and inverse the kernels use instead agree with NumPy's LU-based ones."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from granum.physics.vec import det3, inv3

#: a periodic scene (the periodic collider inverts the cell) driven by PeriTriaxController (cell volume),
#: run with the modules named on the command line made unimportable
_SCENE = """
import sys
for name in sys.argv[1:]:
    sys.modules[name] = None          # `import name` now raises ImportError
from granum.yade import *
O.periodic = True
O.cell.hSize = Matrix3(1, .1, 0, 0, 1, 0, 0, 0, 1)
sp = pack.SpherePack()
sp.makeCloud((0, 0, 0), (1, 1, 1), .08, .2, 60, True, seed=1)
sp.toSimulation()
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             PeriTriaxController(goal=(-1e4, -1e4, -1e4), stressMask=7, maxUnbalanced=.1),
             NewtonIntegrator(damping=.2)]
O.dt = .5 * PWaveTimeStep()
O.run(200, True)
print('MODULES', sorted(m for m in ('fcntl', 'scipy') if sys.modules.get(m)))
print('ITER', O.iter, len(O.interactions) > 0, O.cell.volume > 0)
"""


def test_a_periodic_scene_runs_without_fcntl_and_without_scipy(tmp_path):
    # a cache of its own: without fcntl, filelock falls back to a lock *file*, which the lock files that
    # fcntl locks leave behind in a shared cache would hold forever (Windows has msvcrt's locks instead)
    env = {**os.environ, "GRANUM_CACHE_DIR": str(tmp_path / "cache")}
    r = subprocess.run([sys.executable, "-c", _SCENE, "fcntl", "scipy"], capture_output=True, text=True, timeout=900,
                       env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "MODULES []" in r.stdout
    assert "ITER 200 True True" in r.stdout


@pytest.mark.parametrize("seed", range(20))
def test_det3_and_inv3_agree_with_numpys_lu(seed):
    m = np.random.default_rng(seed).normal(size=(3, 3)) * 10.0 ** (seed % 5 - 2)
    assert det3(m) == pytest.approx(np.linalg.det(m), rel=1e-12, abs=1e-14 * np.abs(m).max() ** 3)
    assert np.allclose(inv3(m) @ m, np.eye(3), atol=1e-10 * np.linalg.cond(m))
    assert np.allclose(inv3(m), np.linalg.inv(m), rtol=1e-10, atol=1e-12 * np.abs(np.linalg.inv(m)).max())


def test_det3_is_exact_for_a_diagonal_cell_and_inv3_of_a_singular_one_is_not_finite():
    h = np.diag([0.1, 3.0, 7.0])
    assert det3(h) == 0.1 * (3.0 * 7.0)  # the cofactor order, no LU rounding
    inverse = inv3(h)
    assert np.count_nonzero(inverse - np.diag(np.diag(inverse))) == 0
    assert np.allclose(np.diag(inverse), [1 / 0.1, 1 / 3.0, 1 / 7.0], rtol=2 * np.finfo(float).eps, atol=0)
    assert not np.isfinite(inv3(np.ones((3, 3)))).all()
