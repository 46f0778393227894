"""Which bodies may form a potential interaction, and how many partners a body's first search keeps (shared by
the aperiodic and periodic broad phases)."""

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


@jit
def scratch_width(pairs_before, nb):
    """Partners per body kept by the first pass of a broad phase's search (a body with more is searched again):
    twice the mean of the last run plus 8, at most 64 (4 bytes each, 16 with a periodic image's shift)."""
    return min(64, 2 * pairs_before // max(nb, 1) + 8)
