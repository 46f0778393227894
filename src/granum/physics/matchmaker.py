"""YADE's MatchMaker: the value of an Ip2 functor's parameter for each pair of materials.

A MatchMaker (``Ip2_FrictMat_FrictMat_FrictPhys(frictAngle=MatchMaker(matches=((0, 1, .1),), algo='min'))``)
returns the value given in ``matches`` for a pair of material ids (either order), or else one computed by
``algo`` from the two values the functor supplies (the materials' friction angles, for example):

- ``avg``: (v1 + v2)/2; ``min``, ``max``; ``harmAvg``: 2 v1 v2/(v1 + v2);
- ``val``: the constant ``val``; ``zero``: 0 (these two need no values).

Some functors supply no values (YADE 2023.02a calls ``tc``, ``en``, ``et`` of ViscElPhys, the cohesions of
CohFrictPhys and ``en``... of MindlinPhys without them): a pair without a match then has no value; YADE
stops with an uncaught C++ exception, granum stops the run naming the parameter and the materials
(:func:`pair_value` returns NaN and the functor sets ``STATUS_NO_PAIR_VALUE``).

Compiled code reads a MatchMaker as a table in the functor's parameter row ``prm`` (no Python call in the
step loop): the parameter's own slot holds the offset of its table (> 0, after the parameters), or 0 when the
parameter is not given (None, the functor's own rule applies; a row of zeros gives none). The table is
``[M, algo code, val, v(0,0), v(0,1), ...]``, M the number of the scene's material rows (``S.material``
indexes them) and ``v(a, b)`` the matched value of rows a, b (NaN: no match). The functor's Python side
builds the tables from the scene's materials before each run (:meth:`granum.engines.functors.Functor.prepare`).

Reference: YADE class reference, MatchMaker; behaviour checked against YADE 2023.02a
(tests/reference/yade/viscel_pairs.py).
"""

from __future__ import annotations

import math

from granum._jit import jit
from granum.core.attrs import Attr, Attributed, as_number, to_float
from granum.core.contacts import C_ERR_A, C_ERR_B, C_STATUS, STATUS_NO_PAIR_VALUE
from granum.mathtypes import Vector3

#: YADE's algorithms, in the order of their codes in compiled tables
ALGOS = ("avg", "min", "max", "harmAvg", "val", "zero")
#: the algorithms that compute from the two values a functor supplies
NEEDS_VALUES = ("avg", "min", "max", "harmAvg")
_NAN = float("nan")


@jit
def algo_value(code, val, v1, v2):
    """The fallback value of algorithm ``code`` (index in :data:`ALGOS`) for the values ``v1``, ``v2``
    (NaN when the functor supplies none: then NaN unless the algorithm needs no values)."""
    if code == 0:
        return 0.5 * (v1 + v2)
    if code == 1:
        return min(v1, v2) if v1 == v1 and v2 == v2 else math.nan
    if code == 2:
        return max(v1, v2) if v1 == v1 and v2 == v2 else math.nan
    if code == 3:
        return 2.0 * v1 * v2 / (v1 + v2)
    if code == 4:
        return val
    return 0.0


@jit
def given(prm, slot):
    """Whether the MatchMaker parameter at ``slot`` of ``prm`` is given (not None)."""
    return prm[slot] > 0.0


@jit
def pair_value(prm, slot, row1, row2, v1, v2):
    """The value of the MatchMaker parameter at ``slot`` for the material rows ``row1``, ``row2``: the
    matched one, else the algorithm's from ``v1``, ``v2`` (module docstring); NaN when there is none."""
    off = int(prm[slot])
    m = int(prm[off])
    x = prm[off + 3 + row1 * m + row2]
    if x == x:
        return x
    return algo_value(int(prm[off + 1]), prm[off + 2], v1, v2)


@jit
def refuse_pair(C, id1, id2):
    """Stop the run: the functor has no value for the materials of bodies ``id1``, ``id2`` (the runner names
    the parameter: :func:`granum.engines.status.status_message`)."""
    C.ctr[C_STATUS] = STATUS_NO_PAIR_VALUE
    C.ctr[C_ERR_A] = id1
    C.ctr[C_ERR_B] = id2


def _matches(owner, value):
    out = []
    for item in value:
        xs = list(item) if hasattr(item, "__len__") else None
        if xs is None or len(xs) != 3:
            raise TypeError(f"MatchMaker.matches: each item must be (id1, id2, value), got {item!r}")
        out.append(Vector3(*(as_number(x, "MatchMaker.matches") for x in xs)))
    return out


def _algo(owner, value):
    if value not in ALGOS:
        raise ValueError(f"MatchMaker.algo {value!r} not recognized (possible values: {', '.join(ALGOS)})")
    return value


class MatchMaker(Attributed):
    """YADE's MatchMaker (module docstring). ``MatchMaker(matches=((id1, id2, value), ...), algo='avg',
    val=nan)``; called as ``mm(id1, id2, val1=nan, val2=nan)``. A number given where an Ip2 expects a
    MatchMaker becomes ``MatchMaker(algo='val', val=number)``, as YADE's converter does."""

    _attrs = {
        "matches": Attr([], "Items (id1, id2, value): the value for materials id1 and id2, in either order",
                        _matches),
        "algo": Attr("avg", "Value when no item matches: 'avg', 'min', 'max', 'harmAvg' of the two values the "
                            "functor supplies, 'val' (the constant val) or 'zero'", _algo),
        "val": Attr(_NAN, "The constant of algo 'val'", to_float("val")),
    }

    def matched(self, id1: int, id2: int) -> float | None:
        """The value of ``matches`` for materials ``id1``, ``id2`` (either order; the first item), or None."""
        for a, b, v in self.matches:
            if (a, b) in ((id1, id2), (id2, id1)):
                return float(v)
        return None

    def computeFallback(self, val1: float, val2: float) -> float:
        """The value of :attr:`algo` for ``val1``, ``val2``."""
        return float(algo_value.py_func(ALGOS.index(self.algo), self.val, float(val1), float(val2)))

    def __call__(self, id1: int, id2: int, val1: float = _NAN, val2: float = _NAN) -> float:
        """The value for materials ``id1``, ``id2``: matched, else :attr:`algo` of ``val1``, ``val2``;
        ValueError when there is no match and the algorithm needs values that are not given (YADE's)."""
        x = self.matched(int(id1), int(id2))
        if x is not None:
            return x
        if self.algo in NEEDS_VALUES and (math.isnan(val1) or math.isnan(val2)):
            raise ValueError(f"MatchMaker: no match for ({int(id1)},{int(id2)}), and values required for algo "
                             f"computation {self.algo!r} not specified.")
        return self.computeFallback(val1, val2)

    def values(self) -> list[float]:
        """The values this MatchMaker may return without computing: the matched ones, and ``val`` with
        algo 'val' (what a functor checks against its parameter's range before a run)."""
        out = [float(v) for _, _, v in self.matches]
        return out + [self.val] if self.algo == "val" else out

    def table(self, material_ids) -> list[float]:
        """The compiled table over the scene's material rows, whose YADE ids are ``material_ids``
        (module docstring)."""
        m = len(material_ids)
        cells = []
        for a in material_ids:
            for b in material_ids:
                x = self.matched(a, b)
                cells.append(_NAN if x is None else x)
        return [float(m), float(ALGOS.index(self.algo)), self.val] + cells


def as_matchmaker(name: str):
    """Converter of a MatchMaker parameter ``name`` of a functor: None, a MatchMaker, or a number (made a
    MatchMaker of algo 'val', as YADE's converter does); anything else is refused naming it."""

    def convert(owner, value):
        if value is None or isinstance(value, MatchMaker):
            return value
        x = as_number(value, f"{type(owner).__name__}.{name} (a MatchMaker or a number)")
        return MatchMaker(algo="val", val=x)

    return convert

