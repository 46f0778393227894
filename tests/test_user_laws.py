"""Laws written outside granum (granum.yade.userlaws): same bits as the built-in law they copy, the
closed-form restitution of a user's spring-dashpot, checkpoints, the cache key, and refused input."""

from __future__ import annotations

import math
import pathlib
import sys

import numpy as np
import pytest
from conftest import frict_engines

from granum.kernels.dispatch import functor_set
from granum.physics import registry

ROOT = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture
def user_cundall_strack():
    """The Cundall-Strack law written as a user's law (the dense-lattice benchmark's BENCH_LAW=user)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        import user_cundall_strack
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
    return user_cundall_strack.Law2_ScGeom_FrictPhys_UserCundallStrack


def _lattice(y, law, n=5, steps=150):
    """A slightly overlapping n^3 lattice in a facet box, the dense-lattice benchmark's set-up; positions
    and angular velocities after ``steps``."""
    r, s = 0.01, 2 * 0.01 * (1 - 1e-3)
    mat = y.O.materials.append(y.FrictMat(young=1e8, poisson=0.3, frictionAngle=math.radians(30), density=2600))
    y.O.bodies.append([y.sphere((r + i * s, r + j * s, r + k * s), r * (1 + 0.02 * ((i + j + k) % 3)), material=mat)
                       for k in range(n) for j in range(n) for i in range(n)])
    half, c = 0.5 * (n - 1) * s + r * (1 - 1e-3), r + 0.5 * (n - 1) * s
    y.O.bodies.append(y.geom.facetBox((c, c, c), (half, half, half), material=mat))
    y.O.engines = frict_engines(y, gravity=(0, 0, -9.81), damping=0.2)
    y.O.engines[2].lawDispatcher.functors = [law]
    y.O.dt = 0.5 * y.PWaveTimeStep()
    y.O.run(steps, True)
    return np.array([[*b.state.pos, *b.state.angVel] for b in y.O.bodies if isinstance(b.shape, y.Sphere)])


def test_user_law_gives_the_bits_of_the_builtin_law_it_copies(yade, user_cundall_strack):
    builtin = _lattice(yade, yade.Law2_ScGeom_FrictPhys_CundallStrack())
    yade.O.reset()
    user = _lattice(yade, user_cundall_strack())
    assert np.abs(builtin[:, 3:]).max() > 0          # the contacts did turn the spheres
    assert builtin.tobytes() == user.tobytes()


def test_user_law_checkpoint_resumes_bit_for_bit(yade, user_cundall_strack):
    _lattice(yade, user_cundall_strack(), steps=40)
    yade.O.saveTmp("half")
    yade.O.run(40, True)
    straight = np.array([list(b.state.pos) for b in yade.O.bodies])
    yade.O.loadTmp("half")
    assert type(yade.O.engines[2].lawDispatcher.functors[0]) is user_cundall_strack
    yade.O.run(40, True)
    resumed = np.array([list(b.state.pos) for b in yade.O.bodies])
    assert straight.tobytes() == resumed.tobytes()


def test_spring_dashpot_example_restitution_and_rolling_moment(yade, capsys):
    """examples/user_law.py: a user's material, physics type, physics and law with a contact moment.
    A linear spring-dashpot collision rebounds with e_n exactly (half period of the damped oscillator),
    up to the integrator's error, O((omega dt)^2) ~ 1e-4 here; the rolling moment grows as k_r w t,
    k_r = alpha_r k_s R*^2, up to eta_r R* F_N, and reaches body 2's torque beside the lever arm's."""
    ns = yade.namespace()
    exec(compile((ROOT / "examples" / "user_law.py").read_text(), "user_law.py", "exec"), ns)
    out = capsys.readouterr().out
    assert float(out.split("restitution: ")[1].split()[0]) == pytest.approx(0.5, abs=1e-3)
    r_eff, kn, delta = 0.01 / 2, 1e7 * 0.01, 1e-4              # R*, k_n = E r, the pressed overlap
    kr, limit = 1.0 * 0.3 * kn * r_eff ** 2, 0.1 * r_eff * kn * delta
    i = yade.O.interactions[0, 1]
    assert i.phys.kr == pytest.approx(kr, rel=1e-12)
    first = out.split("rolling moment after ")[1]
    t, moment = float(first.split(" s:")[0]), float(first.split(": ")[1].split()[0])
    assert kr * t < limit and moment == pytest.approx(kr * t, rel=1e-2)   # t printed to 3 digits
    assert -i.phys.rollMoment[0] == pytest.approx(limit, rel=1e-12)
    arm = yade.Vector3(0, 0, -(0.01 - delta / 2))              # body 2's radial lever arm (sphericalBodies)
    torque = yade.O.forces.t(1) - arm.cross(yade.O.forces.f(1))
    assert (torque - i.phys.rollMoment).norm() <= 1e-12 * limit


def _digest_of(source: str, **globs) -> str:
    ns = dict(globs)
    exec(compile(source, "<law>", "exec"), ns)
    return registry.code_digest(ns["Law2_ScGeom_FrictPhys_Probe"])


PROBE = "def Law2_ScGeom_FrictPhys_Probe(c, id1, id2, S, C, prm):\n    return helper(C.con_f[c, 6]) > K\n"


def test_code_digest_follows_code_constants_and_helpers_not_lines():
    def helper(x):
        return 2.0 * x

    def other_helper(x):
        return 3.0 * x

    base = _digest_of(PROBE, K=0.0, helper=helper)
    assert _digest_of("\n\n\n" + PROBE, K=0.0, helper=helper) == base          # moved in the file
    assert _digest_of(PROBE, K=1.0, helper=helper) != base                     # a constant Numba freezes
    assert _digest_of(PROBE, K=0.0, helper=other_helper) != base               # a function it calls
    assert _digest_of(PROBE.replace(">", ">="), K=0.0, helper=helper) != base  # its own code


def test_kernels_are_keyed_by_the_user_law_digest(user_cundall_strack):
    spec = user_cundall_strack.spec
    value = functor_set("law", [user_cundall_strack().code]).value
    assert value[-1] == f"{user_cundall_strack().code}:{spec.digest}"
    builtin = functor_set("law", [0]).value
    assert builtin == ("functors", "law", (0,))     # granum's own laws: keyed by granum's sources alone


def test_registering_again_keeps_the_code_and_takes_the_new_function(yade):
    from granum.yade.userlaws import law

    def make(limit):
        def Law2_ScGeom_FrictPhys_Again(c, id1, id2, S, C, prm):
            return C.con_f[c, 6] > limit
        return Law2_ScGeom_FrictPhys_Again

    first = law(("ScGeom", "FrictPhys"))(make(0.0))
    second = law(("ScGeom", "FrictPhys"))(make(1.0))
    assert first().code == second().code
    assert first.spec.digest != second.spec.digest
    assert registry.FUNCTORS["Law2_ScGeom_FrictPhys_Again"].function is second.spec.function
    with pytest.raises(ValueError, match="registered before"):
        law(("ScGeom", "ViscElPhys"))(make(0.0))


def _law(c, id1, id2, S, C, prm):
    return True


@pytest.mark.parametrize("name, types, params, error, message", [
    ("Law2_ScGeom_FrictPhys_CundallStrack", ("ScGeom", "FrictPhys"), (), ValueError, "granum's own functor"),
    ("MyLaw", ("ScGeom", "FrictPhys"), (), ValueError, "starts with 'Law2_'"),
    ("Law2_X_Y_Z", ("NoGeom", "FrictPhys"), (), ValueError, "unknown geometry type 'NoGeom'"),
    ("Law2_X_Y_Z", ("ScGeom", "NoPhys"), (), ValueError, "unknown physics type 'NoPhys'"),
    ("Law2_X_Y_Z", ("ScGeom", "FrictPhys"), {"mode": "fast"}, TypeError, "must be a number"),
])
def test_bad_laws_are_refused_naming_what_is_wrong(name, types, params, error, message):
    from granum.yade.userlaws import law

    _law.__name__ = name
    with pytest.raises(error, match=message):
        law(types, params)(_law)


def test_wrong_signature_and_bad_materials_are_refused():
    from granum.yade.userlaws import material, phys, phys_type

    def Ip2_FrictMat_FrictMat_Short(c, id1, id2):
        pass

    with pytest.raises(TypeError, match=r"takes \(c, id1, id2, S, C, prm\)"):
        phys(("FrictMat", "FrictMat"), "FrictPhys")(Ip2_FrictMat_FrictMat_Short)
    with pytest.raises(ValueError, match="one of granum's materials"):
        material("FrictMat", "ElastMat", {"x": 1.0})
    with pytest.raises(ValueError, match="unknown parent material 'NoMat'"):
        material("MyMat", "NoMat")
    with pytest.raises(ValueError, match="width is 1, 3 or 9"):
        phys_type("BadPhys", "FrictPhys", {"k": 2})


def test_loading_a_checkpoint_before_its_law_is_defined_says_so(yade, user_cundall_strack, monkeypatch, tmp_path):
    from granum.io.checkpoint import CheckpointError

    _lattice(yade, user_cundall_strack(), n=2, steps=2)
    yade.O.save(str(tmp_path / "user.yade"))
    monkeypatch.delitem(yade._namespace, user_cundall_strack.__name__)   # as in a script that did not define it
    with pytest.raises(CheckpointError, match="defined before O.load"):
        yade.O.load(str(tmp_path / "user.yade"))
    assert len(yade.O.bodies) == 2 ** 3 + 12                             # the scene is kept
