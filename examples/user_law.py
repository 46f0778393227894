# A contact law written in this script: linear spring-dashpot spheres (granum.yade.userlaws).
#
# Normal force on body 2:  F_N = (k_n delta + c_n d(delta)/dt) n,   c_n = 2 zeta sqrt(m* k_n),
# zeta = -ln(e_n) / sqrt(pi^2 + ln(e_n)^2), m* = m1 m2 / (m1 + m2) (a fixed body counts as infinitely
# heavy); the shear force is Cundall-Strack's (k_s = poisson k_n, |F_T| <= |F_N| tan(phi)).
# The contact ends when the spheres separate, so a collision rebounds with the restitution e_n exactly
# (the damped oscillator's half period; Schaefer, Dippel & Wolf 1996, J. Phys. I France 6:5-20).
#
# Run:  granum examples/user_law.py
# It drops a sphere on a fixed one and prints the measured restitution next to e_n.
import math

from granum.core.bodies import DOF_ALL
from granum.physics.frict import law_cundall_strack, phys_frict
from granum.physics.scgeom import contact_shift, scgeom_incident_vel
from granum.physics.vec import dot
from granum.yade.userlaws import F_FN, F_KN, F_NORMAL, jit, law, material, material_column, phys, phys_type

SpringDashpotMat = material("SpringDashpotMat", "FrictMat", {"en": 0.5})  # e_n, normal coefficient of restitution [-]
SpringDashpotPhys = phys_type("SpringDashpotPhys", "FrictPhys", {"cn": 1})  # c_n [N s/m]
EN = material_column("en")


@jit
def inverse_mass(S, i):
    """1/m of body i, 0 for a body whose translations are all blocked [1/kg]."""
    return 0.0 if S.blocked[i] & DOF_ALL == DOF_ALL else 1.0 / S.mass[i]


@phys(("SpringDashpotMat", "SpringDashpotMat"), "SpringDashpotPhys")
def Ip2_SpringDashpotMat_SpringDashpotMat_SpringDashpotPhys(c, id1, id2, S, C, prm):
    """k_n, k_s, tan(phi) as FrictPhys; c_n = 2 zeta sqrt(m* k_n) from the smaller e_n of the two."""
    phys_frict(c, id1, id2, S, C, prm)
    en = min(S.mat[S.material[id1], EN], S.mat[S.material[id2], EN])
    zeta = -math.log(en) / math.sqrt(math.pi ** 2 + math.log(en) ** 2)
    m_eff = 1.0 / (inverse_mass(S, id1) + inverse_mass(S, id2))
    C.con_f[c, SpringDashpotPhys.cn] = 2.0 * zeta * math.sqrt(m_eff * C.con_f[c, F_KN])


@law(("ScGeom", "SpringDashpotPhys"), {"neverErase": False, "sphericalBodies": True})  # law_cundall_strack's
def Law2_ScGeom_SpringDashpotPhys_Linear(c, id1, id2, S, C, prm):
    """Cundall-Strack, plus the dashpot c_n v_n along the normal (v_n: approach speed)."""
    if not law_cundall_strack(c, id1, id2, S, C, prm):
        return False
    f = C.con_f
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    shift, shift_vel = contact_shift(c, S, C)
    approach = -dot(scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, False), n)
    for k in range(3):
        f[c, F_FN + k] += f[c, SpringDashpotPhys.cn] * approach * n[k]
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
print(f"restitution: measured {O.bodies[1].state.vel[2]:.4f} (rebound speed / impact speed 1 m/s), e_n = 0.5")
