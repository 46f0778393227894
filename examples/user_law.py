# A contact law written in this script (granum.yade.userlaws): linear spring-dashpot spheres with
# rolling resistance.
#
# Normal force on body 2:  F_N = (k_n delta + c_n d(delta)/dt) n,  c_n = 2 zeta sqrt(m* k_n),
#   zeta = -ln(e_n) / sqrt(pi^2 + ln(e_n)^2), m* = m1 m2 / (m1 + m2) (a fixed body: infinitely heavy).
#   The contact ends when the spheres separate, so a collision rebounds with e_n exactly (half period
#   of the damped oscillator; Schaefer, Dippel & Wolf 1996, J. Phys. I France 6:5-20).
# Shear force: Cundall-Strack's (k_s = poisson k_n, |F_T| <= |F_N| tan(phi)).
# Rolling moment on body 2 (elastic-plastic, model C of Ai et al. 2011, Powder Technol. 206:269-282):
#   M_r <- rot(M_r) - k_r dt (w2 - w1)_t,  |M_r| <= eta_r R* |F_N|,  k_r = alpha_r k_s R*^2,
#   R* = r1 r2 / (r1 + r2).
#
# Run:  granum examples/user_law.py
# It checks both against their closed forms: the restitution of a collision, then the rolling moment of
# a sphere pressed on a fixed one and turned at a constant rate (slope k_r w, then the bound eta_r R* F_N).
import math

from granum.core.arrays import S_DT
from granum.core.bodies import DOF_ALL
from granum.core.contacts import F_FN, F_KN, F_KS, F_MOMENT, F_NORMAL, F_R1, F_R2
from granum.physics.frict import law_cundall_strack, phys_frict
from granum.physics.scgeom import contact_shift, scgeom_incident_vel, scgeom_rotate_shear, tangential
from granum.physics.vec import dot, load3, norm, scale, sub
from granum.yade.userlaws import jit, law, material, material_column, phys, phys_type

SpringDashpotMat = material("SpringDashpotMat", "FrictMat", {
    "en": 0.5,       # e_n, normal coefficient of restitution [-]
    "alphaR": 1.0,   # alpha_r, rolling stiffness coefficient [-]
    "etaR": 0.1})    # eta_r, rolling friction coefficient [-]
Cols = phys_type("SpringDashpotPhys", "FrictPhys", {"cn": 1, "kr": 1, "maxRollPerFn": 1, "rollMoment": 3})
EN, ALPHA_R, ETA_R = material_column("en"), material_column("alphaR"), material_column("etaR")


@jit
def inverse_mass(S, i):
    """1/m of body i, 0 for a body whose translations are all blocked [1/kg]."""
    return 0.0 if S.blocked[i] & DOF_ALL == DOF_ALL else 1.0 / S.mass[i]


@phys(("SpringDashpotMat", "SpringDashpotMat"), "SpringDashpotPhys")
def Ip2_SpringDashpotMat_SpringDashpotMat_SpringDashpotPhys(c, id1, id2, S, C, prm):
    """k_n, k_s, tan(phi) as FrictPhys; c_n, k_r and eta_r R* from the smaller material values."""
    phys_frict(c, id1, id2, S, C, prm)
    f, m1, m2 = C.con_f, S.mat[S.material[id1]], S.mat[S.material[id2]]
    ln_en = math.log(min(m1[EN], m2[EN]))
    zeta = -ln_en / math.sqrt(math.pi ** 2 + ln_en ** 2)
    inv_mass = inverse_mass(S, id1) + inverse_mass(S, id2)      # 1/m*; 0 between two fixed bodies: no dashpot
    f[c, Cols.cn] = 2.0 * zeta * math.sqrt(f[c, F_KN] / inv_mass) if inv_mass > 0.0 else 0.0
    r = f[c, F_R1] * f[c, F_R2] / (f[c, F_R1] + f[c, F_R2])
    f[c, Cols.kr] = min(m1[ALPHA_R], m2[ALPHA_R]) * f[c, F_KS] * r * r
    f[c, Cols.maxRollPerFn] = min(m1[ETA_R], m2[ETA_R]) * r


@law(("ScGeom", "SpringDashpotPhys"), {"neverErase": False, "sphericalBodies": True},  # law_cundall_strack's
     history=("moment",))
def Law2_ScGeom_SpringDashpotPhys_Linear(c, id1, id2, S, C, prm):
    """Cundall-Strack, the dashpot c_n v_n along the normal (v_n: approach speed), the rolling moment."""
    if not law_cundall_strack(c, id1, id2, S, C, prm):
        return False
    f = C.con_f
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    shift, shift_vel = contact_shift(c, S, C)
    approach = -dot(scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, False), n)
    for k in range(3):
        f[c, F_FN + k] += f[c, Cols.cn] * approach * n[k]
    roll = tangential(sub(load3(S.ang_vel, id2), load3(S.ang_vel, id1)), n)
    moment = scgeom_rotate_shear(c, id1, id2, S, C, (f[c, Cols.rollMoment], f[c, Cols.rollMoment + 1],
                                                     f[c, Cols.rollMoment + 2]))
    moment = sub(tangential(moment, n), scale(roll, f[c, Cols.kr] * S.scal[S_DT]))
    limit = f[c, Cols.maxRollPerFn] * norm((f[c, F_FN], f[c, F_FN + 1], f[c, F_FN + 2]))
    if norm(moment) > limit:
        moment = scale(moment, limit / norm(moment))
    for k in range(3):
        f[c, Cols.rollMoment + k] = f[c, F_MOMENT + k] = moment[k]   # the law's state; the moment on body 2
    return True


mat = O.materials.append(SpringDashpotMat(young=1e7, poisson=0.3, frictionAngle=0.5, density=2600, en=0.5))
O.bodies.append([sphere((0, 0, 0), 0.01, fixed=True, material=mat), sphere((0, 0, 0.0205), 0.01, material=mat)])
O.bodies[1].state.vel = (0, 0, -1.0)
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_SpringDashpotMat_SpringDashpotMat_SpringDashpotPhys()],
                             [Law2_ScGeom_SpringDashpotPhys_Linear()]),
             NewtonIntegrator(damping=0)]
O.dt = 0.01 * PWaveTimeStep()
O.run(4000, True)
print(f"restitution: {O.bodies[1].state.vel[2]:.4f} (rebound speed / impact speed 1 m/s), e_n = 0.5")

# press the sphere on the fixed one (delta = 1e-4 m) and turn it about x at w = 1 rad/s
b = O.bodies[1]
b.state.pos, b.state.vel, b.state.angVel, b.state.blockedDOFs = (0, 0, 0.0199), (0, 0, 0), (1, 0, 0), 'xyzXYZ'
O.run(1, True)
i = O.interactions[0, 1]
kr, limit = i.phys.kr, i.phys.maxRollPerFn * i.phys.normalForce.norm()
for steps in (100, 5000):
    O.run(steps, True)
    t = (O.iter - i.iterMadeReal) * O.dt
    print(f"rolling moment after {t:.3g} s: {-i.phys.rollMoment[0]:.6g} N m, "
          f"closed form min(k_r w t, eta_r R* F_N) = {min(kr * t, limit):.6g} N m")
