"""NewtonIntegrator's vectorized steps for blocks of plain bodies (granum.kernels.newton.plain_block) give the bits
of its steps body by body (translate, spin, sane, as newton_block takes them for such a body), on random states:
with and without damping, damping of gravity or not, bodies not damped, at rest, turning beyond the range of the
rotation's series, with orientations off unit on both sides of the renormalization's limit, and exploding."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from granum.core.shapes import ShapeKind
from granum.kernels.newton import TURN_NORM_MARGIN, all_plain, plain_block, sane, spin, translate
from granum.physics.vec import RENORM_SERIES_MAX


@numba.njit(error_model="numpy")
def body_by_body(lo, hi, pos, vel, ori, ang_vel, force, torque, mass, inertia, is_damped, gravity, dt, damping,
                 damp_gravity):
    """newton_block's per-body steps for a plain body (its branch for one), the first body not sane or -1."""
    still = (0.0, 0.0, 0.0)
    bad = -1
    for i in range(lo, hi):
        d = damping if is_damped[i] else 0.0
        translate(i, pos, vel, force, mass[i], gravity, dt, 0, d, damp_gravity, still, still, still, False, still)
        spin(i, ori, ang_vel, (torque[i, 0], torque[i, 1], torque[i, 2]), inertia, dt, 0, d, False, 0.0, False)
        if not sane(i, pos, vel, ang_vel) and bad < 0:
            bad = i
    return bad


def random_state(n, seed, spin_rate=30.0):
    """Positions, velocities, orientations, angular velocities, forces, torques, masses, inertias and damping
    flags of n bodies; every seventh at rest (no angular velocity, no torque), every fifth with a zero velocity
    component of either sign."""
    rng = np.random.default_rng(seed)
    ori = rng.normal(size=(n, 4))
    ori /= np.linalg.norm(ori, axis=1)[:, None]
    ang_vel = rng.normal(size=(n, 3)) * spin_rate
    torque = rng.normal(size=(n, 3))
    ang_vel[::7] = 0.0
    torque[::7] = 0.0
    vel = rng.normal(size=(n, 3))
    vel[::5, 0] = 0.0
    vel[1::5, 1] = -0.0
    return [rng.random((n, 3)), vel, ori, ang_vel, rng.normal(size=(n, 3)) * 10, torque,
            1.0 + rng.random(n), 0.1 + rng.random((n, 3)), rng.random(n) < 0.8]


def step_both(state, lo, hi, steps, gravity, dt, damping, damp_gravity):
    """The state after ``steps`` steps of bodies lo..hi-1 both ways, and what each returned at each step."""
    vectorized, reference = [a.copy() for a in state], [a.copy() for a in state]
    returned = []
    for _ in range(steps):
        returned.append((plain_block(lo, hi, *vectorized, gravity, dt, damping, damp_gravity),
                         body_by_body(lo, hi, *reference, gravity, dt, damping, damp_gravity)))
    return vectorized, reference, returned


def assert_same_bits(a, b):
    for x, y in zip(a, b, strict=True):
        assert x.tobytes() == y.tobytes()


@pytest.mark.parametrize("damping", [0.0, 0.2])
@pytest.mark.parametrize("damp_gravity", [False, True])
def test_plain_block_steps_as_the_per_body_steps(damping, damp_gravity):
    state = random_state(700, 1)
    gravity = np.array([0.0, -9.81, 1.5])
    for lo, hi in ((0, 512), (512, 700), (3, 4)):
        vectorized, reference, returned = step_both(state, lo, hi, 4, gravity, 1e-3, damping, damp_gravity)
        assert_same_bits(vectorized, reference)
        assert all(a == b == -1 for a, b in returned)
        assert not np.array_equal(vectorized[2][lo:hi], state[2][lo:hi])   # the orientations did turn


def test_a_turn_beyond_the_rotation_series_takes_the_per_body_turn():
    state = random_state(300, 2)
    state[3][17] = (800.0, -300.0, 50.0)   # |omega| dt > 0.1 rad at dt = 1e-4
    vectorized, reference, _ = step_both(state, 0, 300, 3, np.array([0.0, 0.0, -9.81]), 1e-4, 0.2, False)
    assert_same_bits(vectorized, reference)


@pytest.mark.parametrize("excess", [-2.0 * TURN_NORM_MARGIN, 0.0, 0.5 * TURN_NORM_MARGIN, 2.0 * TURN_NORM_MARGIN])
def test_orientations_off_unit_at_the_renormalization_limit(excess):
    """Orientations whose |q|^2 - 1 is just inside the renormalization's series limit, at it, just beyond it
    (the library's normalization), on both sides of the margin the vectorized turn keeps."""
    state = random_state(200, 3)
    for k, sign in ((11, 1.0), (12, -1.0)):
        e = sign * (RENORM_SERIES_MAX + excess)
        state[2][k] *= np.sqrt(1.0 + e)
    vectorized, reference, _ = step_both(state, 0, 200, 2, np.array([0.0, 0.0, -9.81]), 1e-3, 0.0, False)
    assert_same_bits(vectorized, reference)


@pytest.mark.parametrize("damping", [0.2, 0.0, -0.0])
def test_the_first_exploding_or_non_finite_body_is_returned(damping):
    """Also the bits of the non-finite values themselves, and of zeros of either sign (an angular velocity of -0.0,
    a torque of -0.0), with and without damping (undamped, the loops run with the damping a constant)."""
    state = random_state(100, 4)
    state[1][40] = (2e8, 0.0, 0.0)       # exploding
    state[0][30, 2] = np.nan             # not finite, and first
    state[3][50] = (-0.0, 0.0, -0.0)     # angular velocity
    state[5][50] = (0.0, -0.0, -0.0)     # torque
    state[5][60, 1] = np.inf
    vectorized, reference, returned = step_both(state, 0, 100, 1, np.array([0.0, 0.0, -9.81]), 1e-3, damping, False)
    assert returned == [(30, 30)]
    assert_same_bits(vectorized, reference)


def test_all_plain_refuses_what_the_plain_steps_do_not_cover():
    n = 10
    columns = dict(alive=np.ones(n, bool), clump_id=np.full(n, -1, np.int32), body_mask=np.ones(n, np.int64),
                   blocked=np.zeros(n, np.uint8), aspherical=np.zeros(n, bool),
                   shape_kind=np.full(n, ShapeKind.SPHERE, np.int8))

    def plain(mask=0, **changed):
        c = {k: v.copy() for k, v in columns.items()}
        for name, value in changed.items():
            c[name][4] = value
        return all_plain(0, n, c["alive"], c["clump_id"], c["body_mask"], mask, c["blocked"], c["aspherical"],
                         c["shape_kind"])

    assert plain()
    assert plain(mask=1) and plain(mask=-1, body_mask=0)
    assert not plain(alive=False)
    assert not plain(clump_id=2)              # a clump's member
    assert not plain(shape_kind=ShapeKind.CLUMP, clump_id=4)
    assert not plain(blocked=7)
    assert not plain(aspherical=True)
    assert not plain(mask=2, body_mask=1)     # left alone by a NewtonIntegrator with a mask
