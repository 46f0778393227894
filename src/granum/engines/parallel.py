"""ParallelEngine: groups of engines YADE may run in parallel with each other.

YADE runs the groups of ``slaves`` on different threads, and the engines of a group in order. The groups
must be independent of each other, so running all of them in order is a correct schedule: the runner's
plan puts the slaves in the engine's place (:meth:`ParallelEngine.in_place`).
"""

from __future__ import annotations

from granum.core.attrs import Attr
from granum.engines.base import Engine


def _is_engine(e) -> bool:
    """An engine in YADE's sense: a dispatcher is one there too (granum runs it inside its collider or
    InteractionLoop, and refuses it on its own in a step: :meth:`ParallelEngine.in_place`)."""
    return isinstance(e, Engine) or getattr(e, "yade_parent", None) == "Engine"


def _slaves(owner, value) -> list:
    groups = []
    for g in value:
        members = g if isinstance(g, list | tuple) else [g]
        if not all(_is_engine(e) for e in members):
            raise TypeError(f"{type(owner).__name__}.slaves: each element must be an engine or a list of engines "
                            f"run one after another, got {g!r}")
        groups.append(list(g) if isinstance(g, list | tuple) else g)
    return groups


class ParallelEngine(Engine):
    """Run ``slaves`` (YADE ``ParallelEngine(slaves)``): each element is an engine or a list of engines run
    in order; the elements are independent of each other and run one after another here."""

    _attrs = {"slaves": Attr([], "Engines, or lists of engines run in order, independent of each other", _slaves)}

    def __init__(self, slaves=(), **kw):
        super().__init__(slaves=slaves, **kw)

    def in_place(self) -> list:
        if self.dead:
            return []
        members = [e for g in self.slaves for e in (g if isinstance(g, list) else [g])]
        for e in members:
            if not isinstance(e, Engine):
                raise TypeError(f"ParallelEngine.slaves: {type(e).__name__} does not run on its own in granum "
                                f"(a dispatcher is part of its collider or InteractionLoop)")
        return [s for e in members for s in e.in_place()]
