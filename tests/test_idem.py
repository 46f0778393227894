"""Impulse-based DEM (granum.idem): the article's verification cases against their analytic
solutions, conservation laws, and unit tests of the PCA normals, the K matrix, the contact
search and the termination of the iteration.

Durations are shortened where the physics allows it (each case is stopped shortly after the
events it checks: the impacts happen at known times, and the sliding speed is exact at every
step, so 0.25 s of sliding tests the acceleration as well as the article's 1 s).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from granum import idem
from granum.idem import analytic, cases
from granum.idem import impulse as imp
from granum.idem.broadphase import candidate_pairs
from granum.idem.pca import jacobi_eigh3, pca_normal
from granum.idem.rigid import k_matrix

G = 9.81
DT = 5e-4


def contact_work(solver):
    """Kinetic energy given to the bodies by the contacts in each step [J]: released - stored + friction."""
    h = solver.history
    return h[:, imp.ST_W_REL] + h[:, imp.ST_FRICTION] - h[:, imp.ST_W_COMP]


# ----------------------------------------------------------------------------- acceptance: V3, V4
def test_two_body_collision_final_velocities_momentum_energy():
    """V3: equal masses, v_A = 2, v_B = 0, e = 0.5 -> V_A = 0.5, V_B = 1.5 (1-D impact law)."""
    run = cases.two_body(e=0.5, mu=0.0, alpha0=150.0, dt=DT, v0=2.0, gap=0.1, duration=0.08)
    va, vb = analytic.collision_velocities(1.0, 1.0, 2.0, 0.0, 0.5)
    assert (va, vb) == (0.5, 1.5)
    assert run["vA"][-1] == pytest.approx(va, rel=0.02)
    assert run["vB"][-1] == pytest.approx(vb, rel=0.02)
    # before the impact (t < gap / v0 = 0.05 s) nothing happens
    assert np.all(run["vA"][run["t"] < 0.0495] == 2.0)
    p0 = run["p0"]
    assert np.abs(run["p"] - p0).max() <= 1e-9 * np.linalg.norm(p0)
    assert np.abs(run["L"] - run["L0"]).max() <= 1e-9 * np.linalg.norm(run["L0"]) + 1e-9
    ke = np.concatenate([[run["ke0"]], run["ke"]])
    assert np.all(np.diff(ke) <= 1e-12 * ke[0])  # energy never increases
    # dissipated = (1 - e^2) W_comp with W_comp = 1/2 m_red v^2 = 1/2 (M/2) 2^2
    s = run["solver"]
    m = s.bodies[0].mass
    assert s.energy()["dissipated"] == pytest.approx((1 - 0.25) * 0.5 * (m / 2) * 4.0, rel=1e-4)
    assert ke[0] - ke[-1] == pytest.approx(s.energy()["dissipated"], rel=1e-9)


def test_cradle_last_box_leaves_first_stops_momentum_energy():
    """V4: ten equal boxes, e = 1: the striker stops and the last box leaves at v0."""
    run = cases.cradle(n=10, e=1.0, mu=0.0, alpha0=150.0, dt=DT, v0=1.0, gap=0.1, duration=0.12)
    final = run["v"][-1]
    expected = analytic.cradle_velocities(10, 1.0)
    assert final[-1] == pytest.approx(expected[-1], rel=0.05)
    assert abs(final[0]) < 0.05
    assert np.all(np.abs(final[1:-1]) < 0.05)
    p0 = run["p0"]
    assert np.abs(run["p"] - p0).max() <= 1e-9 * np.linalg.norm(p0)
    ke = np.concatenate([[run["ke0"]], run["ke"]])
    assert np.all(np.diff(ke) <= 1e-12 * ke[0])
    assert ke[-1] == pytest.approx(ke[0], rel=0.01)  # e = 1: kinetic energy kept (to the tolerance)
    assert run["solver"].totals["capped"] == 0


def test_cradle_simultaneous_mode_spreads_the_momentum():
    """[A6] choice: with every pair joining the compression at once, the row shares the impact (a
    multi-contact impact, not the cradle's sequence of binary impacts); momentum still exact."""
    run = cases.cradle(n=4, e=1.0, alpha0=15.0, dt=DT, v0=1.0, gap=0.1, duration=0.102, impact="simultaneous")
    final = run["v"][-1]
    assert np.abs(run["p"] - run["p0"]).max() <= 1e-9 * np.linalg.norm(run["p0"])
    assert final[-1] < 0.95 and np.count_nonzero(np.abs(final) > 0.05) >= 3


# ----------------------------------------------------------------------------- acceptance: V2
@pytest.mark.parametrize("mu", [0.0, 0.1, 0.3, 0.5])
def test_slope_speed_follows_coulomb_sliding(mu):
    """V2: on a 30 degree slope, v = g (sin 30 - mu cos 30) t within 3 % at every step."""
    theta = math.radians(30.0)
    run = cases.slope(mu, theta=theta, e=0.0, alpha0=15.0, dt=DT, duration=0.25)
    t, v = run["t"], run["v"]
    exact = analytic.slope_speed(t, theta, mu)
    a = G * (math.sin(theta) - mu * math.cos(theta))
    assert np.all(np.abs(v - exact) <= 0.03 * a * t)
    assert np.abs(run["vn"]).max() < 1e-3 * a * t[-1]  # e = 0: stays on the slope
    assert run["wmax"].max() < 1e-6  # no tipping
    assert np.all(contact_work(run["solver"]) <= 1e-9)


# ----------------------------------------------------------------------------- acceptance: V1
def test_falling_box_restitution_rest_and_energy():
    """V1: every rebound leaves at e x the impact speed, the first at e sqrt(2 g h); the box comes to
    rest; the contacts never add energy."""
    e, h = 0.5, 0.6
    run = cases.falling_box(e=e, alpha0=15.0, dt=DT, h=h, duration=1.3)
    t, vz = run["t"], run["vz"]
    kick = G * DT
    hits = [n for n in range(1, len(vz)) if vz[n] > 0 and vz[n] - vz[n - 1] > 3 * kick]
    impact = np.array([kick - vz[n - 1] for n in hits])  # approach speed when the impulses act
    rebound = np.array([vz[n] for n in hits])
    big = impact > 10 * kick  # beyond, a bounce lasts a few steps: the discrete micro-bounce regime
    assert big.sum() >= 5
    assert np.all(np.abs(rebound[big] / impact[big] - e) <= 0.05 * e)
    times, speeds = analytic.bounce_impacts(h, e)
    assert rebound[0] == pytest.approx(e * speeds[0], rel=0.05)
    assert t[hits[0]] == pytest.approx(times[0], abs=2 * DT)
    # at rest after the impacts accumulate (t_inf = 1.049 s): velocity at the level of one gravity
    # kick, resting on the floor (no position correction [A10]: only round-off-level sinking)
    late = t > 1.15
    assert np.abs(vz[late]).max() <= 2 * kick
    assert np.abs(run["z"][late]).max() < 1e-4
    assert run["wmax"].max() < 1e-9
    # energy: contacts never add energy; the discrete total energy (velocity-level impulses, no
    # position correction) may rise by at most M g^2 dt^2 e / (1 - e) in one step (the maximum
    # over impact speeds of the energy error of one impact, see test_energy_bound_of_one_impact)
    s = run["solver"]
    assert np.all(contact_work(s) <= 1e-9 * s.energy()["compression"])
    m = s.bodies[1].mass
    bound = m * (G * DT) ** 2 * e / (1 - e)
    assert np.diff(run["energy"]).max() <= bound * (1 + 1e-6) + 1e-9 * run["energy"][0]
    rest = m * G * 0.5 * cases.BOX[2]  # centre of the box at half its height
    assert abs(run["energy"][-1] - rest) < m * (G * DT) ** 2  # left: the micro-bounce of one kick


def test_energy_bound_of_one_impact():
    """The energy change of a single-contact impact step at approach speed u after the gravity kick,
    1/2 M [(e^2 - 1) u^2 + 2 (1 + e) u g dt - g^2 dt^2], peaks at u = g dt / (1 - e) with the value
    M g^2 dt^2 e / (1 - e): the bound used above."""
    e = 0.5
    u = np.linspace(0.0, 1.0, 200001)
    de = 0.5 * ((e * e - 1) * u ** 2 + 2 * (1 + e) * u * G * DT - (G * DT) ** 2)
    assert de.max() == pytest.approx((G * DT) ** 2 * e / (1 - e), rel=1e-6)
    assert u[de.argmax()] == pytest.approx(G * DT / (1 - e), rel=1e-3)


def test_tilted_box_settles_on_a_face_without_creating_energy():
    """A box dropped on an edge: asymmetric contacts, friction, rotation. The contacts never add
    energy, the linear momentum only changes by impulses from the floor (vertical and frictional),
    and the box ends at rest on a face."""
    s = idem.IDEMSolver(e=0.3, mu=0.5, alpha0=15.0, dt=DT)
    s.add(idem.plane_body((0, 0, 0), (4, 4), 0.25))
    b = s.bodies[s.add(idem.box_body((0, 0, 0.9), (1.0, 0.5, 1.0), 0.25, ori=((1, 2, 0.5), 0.4)))]
    s.run(4000)
    assert np.all(contact_work(s) <= 1e-9 * max(1.0, s.energy()["compression"]))
    assert s.totals["capped"] == 0 and s.totals["overshoot"] == 0.0
    assert np.linalg.norm(b.vel) < 3 * G * DT and np.linalg.norm(b.angVel) < 0.05
    up = np.abs(b.normals()[b.surface] @ (0, 0, 1.0)).max()
    assert up == pytest.approx(1.0, abs=1e-3)  # a face normal is vertical: lying on a face
    assert b.pos[2] in (pytest.approx(0.25, abs=2e-3), pytest.approx(0.5, abs=2e-3))


# ----------------------------------------------------------------------------- the iteration
@pytest.mark.parametrize("alpha0", [1.0, 15.0, 150.0])
def test_single_pair_iterations_terminate_with_exact_restitution(alpha0):
    """Two point bodies head on: compression takes exactly ceil(ln tol / ln(1 - 1/alpha0)) iterations
    (v_n decays by 1 - 1/alpha0 per iteration, [A7]) and the release gives back e^2 W_comp: the
    1-D impact law holds to the tolerance."""
    e, tol = 0.5, 1e-6
    s = idem.IDEMSolver(e=e, alpha0=alpha0, tol=tol, gravity=(0, 0, 0), dt=DT)
    a = s.bodies[s.add(idem.body_from_particles([[0.0, 0, 0]], masses=2.0, normals=[[1.0, 0, 0]], spacing=0.1))]
    b = s.bodies[s.add(idem.body_from_particles([[0.0004, 0, 0]], masses=1.0, normals=[[-1.0, 0, 0]],
                                                spacing=0.1))]
    a.vel = (1.0, 0, 0)
    s.step()  # a moves by 5e-4 m: the points now overlap (C_p < 0)
    assert s.stats["contacts"] == 0
    s.step()
    st = s.stats
    assert st["contacts"] == 1 and st["rounds"] == 1
    if alpha0 > 1:
        expected = math.ceil(math.log(tol) / math.log(1 - 1 / alpha0))
        assert abs(st["compression_iterations"] - expected) <= 1
    else:
        assert st["compression_iterations"] == 1  # alpha0 = 1: everything at once
    assert st["release_iterations"] > 0
    va, vb = analytic.collision_velocities(2.0, 1.0, 1.0, 0.0, e)
    assert a.vel[0] == pytest.approx(va, abs=1e-5) and b.vel[0] == pytest.approx(vb, abs=1e-5)
    assert st["W_comp"] == pytest.approx(0.5 * (2.0 / 3.0) * 1.0, rel=1e-5)  # 1/2 m_red v^2
    assert st["W_rel"] == pytest.approx(e * e * st["W_comp"], rel=1e-5)


@pytest.mark.parametrize("impact", ["sequential", "simultaneous"])
@pytest.mark.parametrize("e", [0.0, 1.0])
def test_a_small_pile_terminates(impact, e):
    """Eight boxes dropped in a column with random tilts: every step ends within the safeguards,
    the contacts never add energy, and the momentum changes only through the fixed floor."""
    rng = np.random.default_rng(7)
    s = idem.IDEMSolver(e=e, mu=0.5, alpha0=15.0, dt=DT, impact=impact)
    s.add(idem.plane_body((0, 0, 0), (3, 3), 0.1))
    for k in range(8):
        axis = rng.normal(size=3)
        s.add(idem.box_body((rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), 0.15 + 0.25 * k), (0.2, 0.2, 0.2), 0.1,
                            ori=(axis, rng.uniform(0, 1))))
    s.run(600)
    assert s.totals["capped"] == 0
    assert s.history[:, imp.ST_CONTACTS].max() > 0
    assert np.all(contact_work(s) <= 1e-9 * max(1.0, s.energy()["compression"]))


def test_safeguard_caps_are_reported():
    """With max_iter = 1 the phases stop early and the step says so; the step still completes."""
    run = cases.two_body(duration=0.052, max_iter=1)
    assert run["solver"].totals["capped"] & 2  # bit 2: the iteration limit


# ----------------------------------------------------------------------------- PCA normals
def test_jacobi_eigen_decomposition():
    rng = np.random.default_rng(1)
    for _ in range(20):
        A = rng.normal(size=(3, 3))
        S = A + A.T
        w, V = jacobi_eigh3(S)
        assert np.allclose(w, np.linalg.eigvalsh(S), atol=1e-12)
        assert np.allclose(S @ V, V * w, atol=1e-12)
        assert np.allclose(V.T @ V, np.eye(3), atol=1e-12)


def test_pca_normal_of_a_plane_of_points():
    """Points of a plane (any orientation, irregular) give its normal, with zero surface variation."""
    rng = np.random.default_rng(2)
    for _ in range(10):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        u = np.cross(n, rng.normal(size=3))
        u /= np.linalg.norm(u)
        v = np.cross(n, u)
        pts = rng.normal(size=3) + rng.uniform(-1, 1, (12, 1)) * u + rng.uniform(-1, 1, (12, 1)) * v
        got, sigma = pca_normal(pts)
        assert abs(got @ n) == pytest.approx(1.0, abs=1e-12)
        assert sigma < 1e-12


def test_box_normals_are_outward_faces_edges_corners():
    """PCA normals of a box lattice: exact face normals (also next to the edges), bisectors at the
    edges, trisectors at the corners, all outward."""
    b = idem.box_body((0, 0, 0), (2.0, 1.0, 2.0), 0.25)
    half = np.array([1.0, 0.5, 1.0])
    on = np.isclose(np.abs(b.r0), half)  # on which boundary planes each particle lies
    for i in np.nonzero(b.surface)[0]:
        expected = np.where(on[i], np.sign(b.r0[i]), 0.0)
        expected /= np.linalg.norm(expected)
        assert b.n0[i] == pytest.approx(expected, abs=1e-12)
        assert (b.sigma[i] < 1e-12) == (on[i].sum() == 1)
    assert not np.any(b.n0[~b.surface])


def test_body_from_particles_auto_surface_and_normals_of_a_ball():
    """A lattice ball given as a volume cloud: the surface is detected and its normals point away
    from the centre (within the discretisation)."""
    g = np.arange(-4, 5) * 0.25
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    pts = pts[np.linalg.norm(pts, axis=1) <= 1.0]
    b = idem.body_from_particles(pts + (5.0, 0, 0), density=2000.0, surface="auto")
    assert b.pos == pytest.approx((5.0, 0, 0), abs=1e-12)
    assert b.mass == pytest.approx(2000.0 * 0.25 ** 3 * len(pts))
    radial = b.r0[b.surface] / np.linalg.norm(b.r0[b.surface], axis=1)[:, None]
    cos = (radial * b.n0[b.surface]).sum(axis=1)
    assert cos.min() > 0.5 and np.median(cos) > 0.9
    assert np.all(np.linalg.norm(b.r0[~b.surface], axis=1) < 0.8)


# ----------------------------------------------------------------------------- K matrix
def _random_body(rng, fixed=False):
    pts = rng.normal(size=(20, 3)) * (1.0, 0.5, 0.3)
    b = idem.body_from_particles(pts, masses=rng.uniform(0.5, 2.0, 20), normals=np.tile([0, 0, 1.0], (20, 1)),
                                 fixed=fixed)
    b.ori = (rng.normal(size=3), rng.uniform(0, 3))
    return b


@pytest.mark.parametrize("fixed_b", [False, True])
def test_k_matrix_matches_the_impulse_response(fixed_b):
    """K_AB e_k is the change of the pair's relative velocity under a unit impulse e_k (applied to A,
    its opposite to B), found by brute force; K is symmetric positive definite and equals the
    article's (1/M_A + 1/M_B) 1 - [r_A]x I_A^-1 [r_A]x - [r_B]x I_B^-1 [r_B]x."""
    rng = np.random.default_rng(3)
    s = idem.IDEMSolver(gravity=(0, 0, 0))
    s.add([_random_body(rng), _random_body(rng, fixed_b)])
    ra, rb = rng.normal(size=3), rng.normal(size=3)
    ba, bb = np.array([0]), np.array([1])
    lever = (ba, bb, ra.reshape(1, 3).copy(), rb.reshape(1, 3).copy())

    def rel_vel(vel, omg):
        return imp.contact_velocity(0, *lever, vel, omg)

    vel0, omg0 = rng.normal(size=(2, 3)), rng.normal(size=(2, 3))
    brute = np.empty((3, 3))
    for k in range(3):
        vel, omg = vel0.copy(), omg0.copy()
        imp.apply_impulse(0, tuple(np.eye(3)[k]), *lever, s._inv_mass, s._inv_inertia, vel, omg)
        brute[:, k] = np.subtract(rel_vel(vel, omg), rel_vel(vel0, omg0))
    K = k_matrix(s._inv_mass[0], s._inv_inertia[0], ra, s._inv_mass[1], s._inv_inertia[1], rb)
    assert np.allclose(K, brute, rtol=1e-12, atol=1e-12)

    def skew(r):
        return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])

    article = ((s._inv_mass[0] + s._inv_mass[1]) * np.eye(3) - skew(ra) @ s._inv_inertia[0] @ skew(ra)
               - skew(rb) @ s._inv_inertia[1] @ skew(rb))
    assert np.allclose(K, article, rtol=1e-12, atol=1e-12)
    assert np.allclose(K, K.T, atol=1e-12) and np.linalg.eigvalsh(K).min() > 0


# ----------------------------------------------------------------------------- contact search
def test_candidate_pairs_match_brute_force():
    """For each surface particle and each other body within the cut-off, the pair with that body's
    nearest particle (never two fixed bodies), as a brute-force search finds them."""
    rng = np.random.default_rng(4)
    s = idem.IDEMSolver(gravity=(0, 0, 0))
    s.add(idem.plane_body((0, 0, 0), (2, 2), 0.1))
    s.add(idem.plane_body((0, 0, 0.05), (1, 1), 0.1, ori=((1, 0, 0), 0.3)))
    for _ in range(12):
        s.add(idem.box_body(rng.uniform(-0.4, 0.4, 3) + (0, 0, 0.15), (0.3, 0.2, 0.2), rng.choice([0.1, 0.07]),
                            ori=(rng.normal(size=3), rng.uniform(0, 3))))
    factor = 0.8
    got = candidate_pairs(s._surf, s._x, s._pbody, s._pspacing, s._fixed, factor)
    expected = set()
    surf = s._surf
    for p in surf:
        for body in range(len(s.bodies)):
            if body == s._pbody[p] or (s._fixed[body] and s._fixed[s._pbody[p]]):
                continue
            q = surf[s._pbody[surf] == body]
            d = np.linalg.norm(s._x[q] - s._x[p], axis=1)
            ok = d <= factor * 0.5 * (s._pspacing[p] + s._pspacing[q])
            if ok.any():
                dmin = d[ok].min()
                best = q[ok][d[ok] == dmin].min()
                expected.add((min(p, best), max(p, best)))
    assert len(expected) > 50
    assert {tuple(x) for x in got} == expected
    assert np.all(np.diff(got[:, 0] * len(s._x) + got[:, 1]) > 0)  # sorted, unique


# ----------------------------------------------------------------------------- rigid motion
def test_free_rotation_keeps_angular_momentum_and_turns_at_omega():
    """No contact: rotation about a principal axis turns by w t exactly (quaternion increments
    compose); a general spin keeps the angular momentum L = I w (Euler, torque free)."""
    s = idem.IDEMSolver(gravity=(0, 0, 0), dt=1e-3)
    b = s.bodies[s.add(idem.box_body((0, 0, 0), (2.0, 1.0, 0.5), 0.25))]
    b.angVel = (0, 0, 2.0)
    s.run(500)
    q = np.asarray(b._row("ori"))
    assert 2 * math.atan2(q[3], q[0]) == pytest.approx(2.0 * 0.5, rel=1e-12)
    b.angVel = (0.3, 1.0, -0.5)
    L0 = s.angular_momentum()
    ke0 = s.kinetic()
    s.run(500)
    assert s.angular_momentum() == pytest.approx(L0, rel=1e-12, abs=1e-12)
    assert s.kinetic() == pytest.approx(ke0, rel=0.01)  # explicit rotation: small energy drift only


def test_box_mass_properties_are_the_particle_sums():
    """Article §2: M = sum m_i, I = sum m_i (r^2 1 - r r^T); for a lattice of n points over a length L,
    <x^2> = L^2 (n + 1) / (12 (n - 1))."""
    b = idem.box_body((1, 2, 3), (2.0, 1.0, 2.0), 0.25, density=500.0)
    m = 500.0 * 4.0
    assert b.mass == pytest.approx(m) and b.pos == pytest.approx((1, 2, 3))

    def var(length, n):
        return length ** 2 * (n + 1) / (12 * (n - 1))

    vx, vy, vz = var(2.0, 9), var(1.0, 5), var(2.0, 9)
    assert np.allclose(b.inertia0, m * np.diag([vy + vz, vx + vz, vx + vy]), rtol=1e-12, atol=1e-9)


def test_views_write_through_and_bodies_are_added_once():
    s = idem.IDEMSolver()
    b = idem.box_body((0, 0, 1), (1, 1, 1), 0.5)
    b.vel = (1, 0, 0)
    bid = s.add(b)
    assert s.bodies[bid] is b and b.vel[0] == 1.0
    b.vel[2] = -2.0
    assert s._vel[bid, 2] == -2.0
    b.pos = (0, 0, 5)
    assert s._x[s._pbody == bid, 2].min() == pytest.approx(4.5)
    with pytest.raises(ValueError, match="already in a solver"):
        s.add(b)


# ----------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("kw, msg", [
    ({"e": -0.1}, "restitution coefficient e must lie in"),
    ({"e": 1.5}, "restitution coefficient e must lie in"),
    ({"mu": -0.2}, "friction coefficient mu"),
    ({"alpha0": 0.0}, "alpha0 must be finite and > 0"),
    ({"alpha0": -15.0}, "alpha0 must be finite and > 0"),
    ({"tol": 0.0}, "tol must lie in"),
    ({"dt": 0.0}, "dt must be finite and > 0"),
    ({"impact": "both"}, "impact must be one of"),
])
def test_bad_parameters_are_refused(kw, msg):
    with pytest.raises(ValueError, match=msg):
        idem.IDEMSolver(**kw)


def test_bad_parameters_are_refused_on_assignment_too():
    s = idem.IDEMSolver()
    with pytest.raises(ValueError, match="restitution"):
        s.e = 2.0
    with pytest.raises(ValueError, match="alpha0"):
        s.alpha0 = float("nan")


def test_pca_normals_need_four_particles():
    pts = [[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0]]
    with pytest.raises(ValueError, match="at least 4 surface particles"):
        idem.body_from_particles(pts)
    body = idem.body_from_particles(pts, normals=[[0, 0, 1]] * 3)  # given normals need no PCA
    assert body.nParticles == 3


def test_bad_bodies_are_refused():
    with pytest.raises(ValueError, match="spacing"):
        idem.box_body((0, 0, 0), (1, 1, 1), 0.0)
    with pytest.raises(ValueError, match="box size"):
        idem.box_body((0, 0, 0), (1, -1, 1), 0.1)
    with pytest.raises(ValueError, match="masses must be finite and > 0"):
        idem.body_from_particles(np.eye(4)[:, :3], masses=[1, 1, -1, 1])
    with pytest.raises(ValueError, match="normals must have shape"):
        idem.body_from_particles(np.eye(4)[:, :3], normals=[[0, 0, 1]])
    with pytest.raises(TypeError, match="RigidBody"):
        idem.IDEMSolver().add("box")
