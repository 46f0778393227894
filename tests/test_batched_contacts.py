"""The batched update of sphere-sphere Cundall-Strack contacts (granum.kernels.batch) gives the scalar path's results
to the bit: a stirred lattice whose contacts slip, end and begin, beside walls whose contacts stay on the scalar path
in the same blocks, is stepped with and without batches and every state array compared bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines

import granum.kernels.interaction as interaction
from granum.core.contacts import C_CONTACTS, F_FN, F_FS, F_PEN, F_TANPHI, FLAG_ALIVE, I_FLAGS

N = 11  # N³ = 1,331 spheres: above interaction.BATCHED_BODIES


def _stirred_lattice(y, never_erase=False):
    """N³ unit-spaced spheres of radius 0.55 (each overlaps its neighbours), a box of walls around them, random
    velocities and spins (seeded): shear forces build up, contacts slip, end and begin."""
    y.O.engines = frict_engines(y, gravity=(0, 0, -10), damping=0)
    y.O.engines[2].lawDispatcher.functors[0].neverErase = never_erase
    y.O.dt = 2e-4
    y.O.bodies.append([y.sphere((i, j, k), 0.55) for k in range(N) for j in range(N) for i in range(N)])
    for axis in range(3):
        for side, at in ((1, -0.6), (-1, N - 0.4)):
            y.O.bodies.append(y.wall(tuple(at if a == axis else 0 for a in range(3)), axis=axis, sense=side))
    rng = np.random.default_rng(7)
    for b in y.O.bodies:
        if isinstance(b.shape, y.Sphere):
            b.state.vel = tuple(rng.normal(0.0, 0.4, 3))
            b.state.angVel = tuple(rng.normal(0.0, 20.0, 3))


def _run(y, batched: bool, never_erase: bool, monkeypatch) -> dict:
    monkeypatch.setattr(interaction, "BATCHED_BODIES", 1024 if batched else 10**9)
    y.O.reset()
    _stirred_lattice(y, never_erase)
    loop = y.O.engines[2]
    y.O.step()
    assert loop.params(y.O._scene, y.O.engines).batched.value == ("batched", batched)
    y.O.run(150, True)
    scene = y.O._scene
    C = scene.contacts
    n = int(C.ctr[C_CONTACTS])
    out = {name: np.array(getattr(scene.bodies, name)) for name in ("pos", "vel", "ang_vel", "force", "torque")}
    out["con_f"], out["con_i"] = np.array(C.con_f[:n]), np.array(C.con_i[:n])
    # the Python views read the pool in either memory order (F order when batched)
    assert C.con_f.flags.f_contiguous != C.con_f.flags.c_contiguous and C.con_f.flags.f_contiguous == batched
    walked = {(i.id1, i.id2): (tuple(i.phys.normalForce), i.geom.penetrationDepth) for i in y.O.interactions}
    live = out["con_i"][:, I_FLAGS] & FLAG_ALIVE != 0
    assert walked == {(a, b): (tuple(f[F_FN:F_FN + 3]), f[F_PEN])
                      for (a, b), f in zip(out["con_i"][live][:, :2].tolist(), out["con_f"][live], strict=True)}
    return out


@pytest.mark.parametrize("never_erase", [False, True])
def test_batched_update_gives_the_scalar_results_to_the_bit(yade, monkeypatch, never_erase):
    scalar = _run(yade, False, never_erase, monkeypatch)
    batched = _run(yade, True, never_erase, monkeypatch)
    for name, a in scalar.items():
        b = batched[name]
        assert a.shape == b.shape and a.tobytes() == b.tobytes(), name
    # the batches met what they must reproduce: slip, contacts ending (or kept at zero force), and wall contacts
    f, flags = scalar["con_f"], scalar["con_i"][:, I_FLAGS]
    live = flags & FLAG_ALIVE != 0
    fn = np.linalg.norm(f[:, F_FN:F_FN + 3], axis=1)
    fs = np.linalg.norm(f[:, F_FS:F_FS + 3], axis=1)
    slipping = live & (fn > 0) & (np.abs(fs - fn * f[:, F_TANPHI]) <= 1e-9 * fn)
    assert slipping.sum() > 100
    ids = scalar["con_i"][live][:, :2]
    pairs = {(min(a, b), max(a, b)) for a, b in ids.tolist()}
    lattice = {(i, i + step) for i in range(N**3) for step, axis in ((1, 0), (N, 1), (N * N, 2))
               if (i // step) % N < N - 1}  # the neighbours in contact at the start
    assert len({p for p in pairs if p[1] >= N**3}) > 50   # wall contacts began: blocks mix them with batched ones
    if never_erase:
        apart = live & (f[:, F_PEN] < 0)
        assert apart.sum() > 100 and np.all(fn[apart] == 0) and np.all(fs[apart] == 0)
    else:
        assert len(lattice - pairs) > 100   # contacts ended (their rows compacted)


def test_an_unknown_llvm_is_left_alone_with_a_warning(monkeypatch):
    """LLVM ends the process on an option it does not know: granum sets its vectorizer limit only on the LLVM
    versions known to have it, and says so otherwise (the loops stay scalar)."""
    import llvmlite.binding as llvm

    from granum import _jit

    calls = []
    monkeypatch.setattr(llvm, "set_option", lambda *args: calls.append(args))
    monkeypatch.setattr(llvm, "llvm_version_info", (99, 0, 0))
    with pytest.warns(RuntimeWarning, match="LLVM 99"):
        _jit.allow_vectorize_checks()
    assert calls == []
    monkeypatch.setattr(llvm, "llvm_version_info", (22, 1, 0))
    _jit.allow_vectorize_checks()
    assert calls == [("granum", f"-vectorize-memory-check-threshold={_jit.VECTORIZE_MEMORY_CHECKS}")]
