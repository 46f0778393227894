"""Which bodies may form a potential interaction, and how many partners a body's first search keeps (shared by
the aperiodic and periodic broad phases)."""

from __future__ import annotations

from granum._jit import jit


@jit(inline="always")  # per candidate pair: no call
def may_collide(S, i, j, avoid_self):
    """YADE's collision filter: masks share a bit, not two members of one clump, and not two
    bodies of the same mask sharing bits with ``avoidSelfInteractionMask``.

    Pairs whose shapes have no geometry functor are kept, as in YADE: they are
    potential interactions that never become real. Written without a branch: a loop over candidates that
    calls it need not branch on it.
    """
    mi = S.mask[i]
    mj = S.mask[j]
    ci = S.clump_id[i]
    return ((mi & mj) != 0) & ((mi != mj) | ((mi & avoid_self) == 0)) & ((ci < 0) | (ci != S.clump_id[j]))


@jit
def masks_may_refuse(S, nb, avoid_self):
    """Whether :func:`may_collide` may refuse a pair of the live bodies 0..nb-1: unless they all have one mask
    that shares no bit with ``avoid_self`` (YADE's avoidSelfInteractionMask) and none is a clump's member. Dead
    bodies are not looked at: the broad phase bounds them first, and their bound is empty (never a candidate)."""
    first = -1
    for i in range(nb):
        if not S.alive[i]:
            continue
        if first < 0:
            first = i
        if S.mask[i] != S.mask[first] or S.clump_id[i] >= 0:
            return True
    return first >= 0 and (S.mask[first] == 0 or (S.mask[first] & avoid_self) != 0)


@jit
def scratch_width(pairs_before, nb):
    """Slots per body of the first pass of a broad phase's search (a body with more partners than it keeps is
    searched again; the aperiodic search keeps one slot less, its spare): twice the mean of the last run plus 8,
    at most 64 (4 bytes each, 16 with a periodic image's shift)."""
    return min(64, 2 * pairs_before // max(nb, 1) + 8)
