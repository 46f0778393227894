"""Which bodies may form a potential interaction (shared by the aperiodic and periodic broad phases)."""

from __future__ import annotations

from granum._jit import jit


@jit(inline="always")  # per candidate pair: no call
def may_collide(S, i, j, avoid_self):
    """YADE's collision filter: masks share a bit, not two members of one clump, and not two
    bodies of the same mask sharing bits with ``avoidSelfInteractionMask``.

    Pairs whose shapes have no geometry functor are kept, as in YADE: they are
    potential interactions that never become real.
    """
    mi = S.mask[i]
    mj = S.mask[j]
    if (mi & mj) == 0 or (mi == mj and (mi & avoid_self) != 0):
        return False
    return not (S.clump_id[i] >= 0 and S.clump_id[i] == S.clump_id[j])
