"""The engines of YADE's standard step: ForceResetter, InsertionSortCollider,
InteractionLoop, NewtonIntegrator and GravityEngine.

Each only translates its YADE attributes into the named parameters of a compiled
stage (see :mod:`granum.kernels`); dispatch tables for the InteractionLoop are built
here from the listed functors and the type hierarchies of the registry.
"""

from __future__ import annotations

import functools

import numpy as np

from granum.core.attrs import Attr, edit_token, instance_of, note_assignment, only_default, to_bool, to_float, to_int
from granum.core.contacts import TOTALS, contact_width, shared_columns
from granum.core.shapes import ShapeKind
from granum.engines.base import GlobalEngine
from granum.engines.functors import check_role, functor_table
from granum.kernels.collider import ColliderParams
from granum.kernels.dispatch import code_of, functors
from granum.kernels.forces import GravityParams
from granum.kernels.interaction import InteractionParams
from granum.kernels.newton import NewtonParams, aspherical_paths, vectorized
from granum.kernels.static import Static
from granum.mathtypes import Matrix3, Vector3, as_vec3
from granum.physics import registry

NKINDS = len(ShapeKind)


def to_vec3(owner, value):
    try:
        return Vector3(*as_vec3(value))
    except (TypeError, ValueError) as e:
        raise type(e)(f"{type(owner).__name__}: {e}") from None


class ForceResetter(GlobalEngine):
    """Reset forces and torques to their permanent values at the start of the step."""

    stage = "granum.kernels.forces:reset_stage"


class Dispatcher:
    """A list of functors of one role (YADE's ``Dispatcher``); see the named subclasses below.

    As in YADE, a functor serving the same types as one listed before it replaces that one (in its
    place): ``LawDispatcher([law, law])`` holds one functor.
    """

    #: the functor role this dispatcher holds ("bound", "geom", "phys", "law")
    role = ""
    #: in YADE a dispatcher is an engine; in granum it is a part of its collider or InteractionLoop
    yade_parent = "Engine"

    def __init__(self, functors=(), owner: str = ""):
        self._owner = owner or type(self).__name__
        self.functors = functors

    @property
    def functors(self) -> list:
        return list(self._functors)

    @functors.setter
    def functors(self, items) -> None:
        by_types: dict = {}
        for f in items:
            check_role(f, self.role, self._owner)
            by_types[f.spec.types] = f   # dict order: the first place, the last functor
        self._functors = list(by_types.values())
        note_assignment()   # the engine's parameters kept on the assignment stamp are made of these

    def dispMatrix(self, names: bool = True) -> dict:
        """Which functor serves which pair of types."""
        return {f.spec.types: type(f).__name__ for f in self._functors}

    def __repr__(self) -> str:
        return f"<{type(self).__name__} with {len(self._functors)} functors>"


class BoundDispatcher(Dispatcher):
    """The bound functors (``Bo1_*``) of a collider."""

    role = "bound"


class IGeomDispatcher(Dispatcher):
    """The geometry functors (``Ig2_*``) of an InteractionLoop."""

    role = "geom"


class IPhysDispatcher(Dispatcher):
    """The physics functors (``Ip2_*``) of an InteractionLoop."""

    role = "phys"


class LawDispatcher(Dispatcher):
    """The constitutive-law functors (``Law2_*``) of an InteractionLoop."""

    role = "law"


def _no_callbacks(owner, value):
    if list(value):
        raise NotImplementedError("InteractionLoop.callbacks are not supported by granum")
    return []


class InsertionSortCollider(GlobalEngine):
    """Broad-phase collision detection keeping the potential interactions up to date.

    Bounds from the ``Bo1`` functors are enlarged by ``verletDist`` (negative: that
    fraction of the smallest sphere radius) so that the collider only reruns when a
    body has moved farther than that. Any algorithm that yields the pairs of bodies
    with overlapping bounds is acceptable; granum uses a uniform grid.
    """

    stage = "granum.kernels.collider:collider_stage"
    key_from_edits = True   # params_key: edit tokens and scene values only (Engine.key_from_edits)
    _attrs = {
        "verletDist": Attr(-0.5, "Bound enlargement [m]; negative: fraction of the smallest sphere radius",
                           to_float("verletDist")),
        "sortAxis": Attr(0, "Accepted for compatibility", to_int("sortAxis")),
        "allowBiggerThanPeriod": Attr(False, "Accept bodies wider than half the periodic cell (each pair is then "
                                             "taken through its nearest image)", to_bool),
        "sortThenCollide": Attr(False, "Accepted for compatibility", to_bool),
        "targetInterv": Attr(100, "Accepted for compatibility (granum's Verlet distance is uniform)",
                             to_int("targetInterv")),
        "overlapTolerance": Attr(1e-7, "Accepted for compatibility", to_float("overlapTolerance")),
        "updatingDispFactor": Attr(-1.0, "Accepted for compatibility", to_float("updatingDispFactor")),
        "minSweepDistFactor": Attr(0.1, "Accepted for compatibility", to_float("minSweepDistFactor")),
        "avoidSelfInteractionMask": Attr(0, "Bodies whose masks share these bits do not interact",
                                         to_int("avoidSelfInteractionMask")),
        "numReinit": Attr(0, "Number of full collider runs", readonly=True),
        "numAction": Attr(0, "Number of times the pair list was rebuilt", readonly=True),
        "fastestBodyMaxDist": Attr(0.0, "Accepted for compatibility", to_float("fastestBodyMaxDist")),
        "doSort": Attr(False, "Accepted for compatibility", to_bool),
        "keepListsShort": Attr(False, "Accepted for compatibility", to_bool),
        "smartInsertErase": Attr(False, "Accepted for compatibility", to_bool),
        "newton": Attr(None, "Accepted for compatibility"),
        "boundDispatcher": Attr(None, "The bound functors",
                                instance_of(BoundDispatcher, "a BoundDispatcher", "boundDispatcher")),
    }

    #: options of older YADE versions that YADE 2023 no longer has, refused by name (stale scripts use them)
    RETIRED = {
        "nBins": "the binned sort of old YADE versions",
        "binCoeff": "the binned sort of old YADE versions",
        "binOverlap": "the binned sort of old YADE versions",
        "maxRefRelStep": "the binned sort of old YADE versions",
        "histInterval": "the binned sort of old YADE versions",
        "sweepLength": "the sweep distance of old YADE versions (see verletDist)",
    }

    def __init__(self, boundFunctors=(), **kw):
        for name in kw:
            if name in self.RETIRED:
                raise AttributeError(f"InsertionSortCollider.{name}: {self.RETIRED[name]}; YADE 2023 has no such "
                                     f"option either (\"No such attribute: {name}\"): remove it from the script")
        super().__init__(**kw)
        self.boundDispatcher = BoundDispatcher(boundFunctors, "InsertionSortCollider")

    def functors(self) -> list:
        return list(self.boundDispatcher.functors)

    def params_key(self, scene, held: list) -> tuple | None:
        """The collider's parameters come from its attributes and bound functors and whether the cell is
        periodic; None with a functor that has a Python side (:func:`python_sided`)."""
        functors = self.boundDispatcher.functors
        if python_sided(functors):
            return None
        return (edit_token(self, held), tuple(edit_token(f, held) for f in functors), scene.periodic,
                registry.functor_generation)

    def params(self, scene, engines) -> ColliderParams:
        bound_code = np.full(NKINDS, -1, np.int32)
        for f in self.boundDispatcher.functors:
            bound_code[f.spec.types[0]] = f.code
        return ColliderParams(bound_code=bound_code, bound_tab=functor_table("bound", self.boundDispatcher.functors),
                              verlet_dist=float(self.verletDist), avoid_self=int(self.avoidSelfInteractionMask),
                              allow_bigger=bool(self.allowBiggerThanPeriod),
                              cell=Static(("cell", bool(scene.periodic))),
                              appends=Static(("appends", any(getattr(e, "adds_bodies", False) for e in engines))))


def python_sided(functors) -> bool:
    """Whether one of ``functors`` has a Python side (``registry.Functor.python``): its ``prepare`` may act on the
    scene and on its own state before every chunk (the cohesive Ip2's setCohesionNow lasts one step, the concrete
    model's reads the bodies' materials), so an engine listing it builds its parameters anew every time."""
    return any(f.spec.python for f in functors)


def law_totals() -> np.ndarray:
    """Per Law2 functor code, the running totals its contacts keep after ending: (first column, count)
    (:attr:`granum.kernels.interaction.InteractionParams.law_totals`), (law functors, 2) int64."""
    out = np.zeros((len(functors("law")), 2), np.int64)
    for code, spec in enumerate(functors("law")):
        for g in spec.history:
            if g in TOTALS:
                out[code] = TOTALS[g]
    return out


class InteractionLoop(GlobalEngine):
    """For every interaction: geometry (Ig2), physics once (Ip2), then the law (Law2).

    ``InteractionLoop([Ig2...], [Ip2...], [Law2...])``. A combination that the listed
    functors do not cover stops the run with an error naming the two types.
    """

    stage = "granum.kernels.interaction:interaction_stage"
    key_from_edits = True   # params_key: edit tokens and scene values only (Engine.key_from_edits)
    _attrs = {
        "geomDispatcher": Attr(None, "The IGeom functors",
                               instance_of(IGeomDispatcher, "an IGeomDispatcher", "geomDispatcher")),
        "physDispatcher": Attr(None, "The IPhys functors",
                               instance_of(IPhysDispatcher, "an IPhysDispatcher", "physDispatcher")),
        "lawDispatcher": Attr(None, "The law functors", instance_of(LawDispatcher, "a LawDispatcher", "lawDispatcher")),
        "callbacks": Attr([], "Interaction callbacks (not supported: must stay empty)", _no_callbacks),
        "loopOnSortedInteractions": Attr(False, "Accepted for compatibility (granum's order is always fixed)",
                                         to_bool),
    }

    def __init__(self, geoms=(), physs=(), laws=(), **kw):
        super().__init__(**kw)
        self.geomDispatcher = IGeomDispatcher(geoms, "InteractionLoop (IGeom functors)")
        self.physDispatcher = IPhysDispatcher(physs, "InteractionLoop (IPhys functors)")
        self.lawDispatcher = LawDispatcher(laws, "InteractionLoop (Law functors)")

    def functors(self) -> list:
        return self.geomDispatcher.functors + self.physDispatcher.functors + self.lawDispatcher.functors

    def tables(self, scene) -> dict:
        """Dispatch tables from the listed functors (see :func:`interaction_stage`); fresh arrays."""
        key = tuple(tuple(type(f) for f in d.functors) for d in (self.geomDispatcher, self.physDispatcher,
                                                                   self.lawDispatcher))
        return {name: a.copy() for name, a in _dispatch_tables(*key, len(registry.MATERIALS)).items()}

    def params_key(self, scene, held: list) -> tuple | None:
        """The loop's parameters come from its functors (and their MatchMakers), the scene's materials, the
        functors of its existing contacts and whether energies are tracked: registrations aside, nothing else;
        None with a functor that has a Python side (:func:`python_sided`)."""
        functors = self.functors()
        if python_sided(functors):
            return None
        held.extend(scene.materials)
        return (edit_token(self, held), tuple(edit_token(f, held) for f in functors),
                tuple((id(m), m.version) for m in scene.materials),
                tuple(scene.contact_functors(role) for role in ("geom", "phys", "law")), scene.track_energy,
                registry.functor_generation, len(registry.MATERIALS))

    def params(self, scene, engines) -> InteractionParams:
        for f in self.functors():
            f.prepare(scene)
        t = self.tables(scene)
        self.check_contact_columns(scene, t)
        geom_tab = functor_table("geom", self.geomDispatcher.functors, scene.contact_functors("geom"))
        # pairs skip detection on budgets computed with these functors (see interaction.detect_pair)
        scene.detection_uses(t["geom_code"].tobytes() + t["geom_swap"].tobytes() + geom_tab[1].tobytes())
        return InteractionParams(
            geom_code=t["geom_code"], geom_swap=t["geom_swap"], geom_tab=geom_tab, geom_type=t["geom_type"],
            phys_code=t["phys_code"], phys_swap=t["phys_swap"],
            phys_tab=functor_table("phys", self.physDispatcher.functors, scene.contact_functors("phys")),
            phys_type=t["phys_type"], law_code=t["law_code"],
            law_tab=functor_table("law", self.lawDispatcher.functors, scene.contact_functors("law")),
            pair_ok=t["pair_ok"], width=contact_width(self.contact_groups(scene)), law_totals=law_totals())

    def check_contact_columns(self, scene, t) -> None:
        """Refuse a plan in which one contact's functors (geometry, physics and the law they dispatch to, the
        listed ones and those of existing contacts) would use two history groups that share a column
        (:func:`granum.core.contacts.register_history`), naming them."""
        geoms = {f.code for f in self.geomDispatcher.functors} | set(scene.contact_functors("geom"))
        physs = {f.code for f in self.physDispatcher.functors} | set(scene.contact_functors("phys"))
        specs = {role: functors(role) for role in ("geom", "phys", "law")}
        for g in geoms:
            for p in physs:
                law = int(t["law_code"][t["geom_type"][g], t["phys_type"][p]])
                used = [specs["geom"][g], specs["phys"][p]] + ([specs["law"][law]] if law >= 0 else [])
                clash = shared_columns(h for f in used for h in f.history)
                if clash:
                    raise ValueError(f"InteractionLoop: a contact of {', '.join(f.yade_name for f in used)} would keep "
                                     f"the histories {clash[0]!r} and {clash[1]!r}, which share contact columns in "
                                     f"granum: these functors cannot act on one contact")

    def contact_groups(self, scene) -> set[str]:
        """The ``con_f`` column groups this loop's contacts need: the history its functors declare, and
        the energy columns while O.trackEnergy."""
        groups = {g for f in self.functors() for g in f.spec.history}
        return (groups | {"energy"}) if scene.track_energy else groups


@functools.lru_cache(maxsize=64)
def _dispatch_tables(geoms, physs, laws, nmaterials) -> dict:
    """The dispatch tables of an InteractionLoop listing functors of the classes ``geoms``, ``physs`` and
    ``laws`` (they depend on nothing else: the registry is fixed once the kernels are imported; ``nmaterials``
    keys the material classes registered). Computed once per combination: the runner asks at every chunk."""
    geom_code = np.full((NKINDS, NKINDS), -1, np.int32)
    geom_swap = np.zeros((NKINDS, NKINDS), np.uint8)
    for f in geoms:
        a, b = f.spec.types
        geom_code[a, b], geom_swap[a, b] = code_of(f.spec.yade_name), 0
        if geom_code[b, a] < 0:
            geom_code[b, a], geom_swap[b, a] = code_of(f.spec.yade_name), 1
    pair_ok = np.zeros((NKINDS, NKINDS), np.int8)
    for spec in functors("geom"):
        a, b = spec.types
        pair_ok[a, b] = pair_ok[b, a] = 2
    pair_ok[geom_code >= 0] = 1
    geom_type = np.array([registry.GEOM_TYPES[s.produces].code for s in functors("geom")], np.int32)

    mats = list(registry.MATERIALS)
    phys_code = np.full((len(mats), len(mats)), -1, np.int32)
    phys_swap = np.zeros((len(mats), len(mats)), np.uint8)
    for i, m1 in enumerate(mats):
        for j, m2 in enumerate(mats):
            f, swapped = registry.best_match([p.spec for p in physs],
                                             registry.material_ancestry(m1), registry.material_ancestry(m2))
            if f is not None:
                phys_code[i, j], phys_swap[i, j] = code_of(f.yade_name), swapped
    phys_type = np.array([registry.PHYS_TYPES[s.produces].code for s in functors("phys")], np.int32)

    gtypes, ptypes = list(registry.GEOM_TYPES), list(registry.PHYS_TYPES)
    law_code = np.full((len(gtypes), len(ptypes)), -1, np.int32)
    for i, g in enumerate(gtypes):
        for j, p in enumerate(ptypes):
            chain_g, chain_p = registry.geom_ancestry(g), registry.phys_ancestry(p)
            best, best_d = None, None
            for law in laws:
                tg, tp = law.spec.types
                if tg in chain_g and tp in chain_p:
                    d = chain_g.index(tg) + chain_p.index(tp)
                    if best_d is None or d < best_d:
                        best, best_d = law, d
            if best is not None:
                law_code[i, j] = code_of(best.spec.yade_name)
    return dict(geom_code=geom_code, geom_swap=geom_swap, geom_type=geom_type, pair_ok=pair_ok,
                phys_code=phys_code, phys_swap=phys_swap, phys_type=phys_type, law_code=law_code)


class NewtonIntegrator(GlobalEngine):
    """Leapfrog integration of motion with gravity and YADE's non-viscous damping."""

    stage = "granum.kernels.newton:newton_stage"
    _attrs = {
        "damping": Attr(0.2, "Non-viscous damping coefficient lambda_d [-]", to_float("damping")),
        "gravity": Attr(Vector3(0, 0, 0), "Gravitational acceleration [m/s^2]", to_vec3),
        "maxVelocitySq": Attr(0.0, "Accepted for compatibility", to_float("maxVelocitySq")),
        "exactAsphericalRot": Attr(True, "Integrate aspherical bodies with Euler's equations (YADE's False, which "
                                         "turns them as spheres, is not implemented yet: only True)",
                                   only_default("exactAsphericalRot", True)),
        "warnNoForceReset": Attr(True, "Accepted for compatibility", to_bool),
        "kinSplit": Attr(False, "Kinetic energy split in translation and rotation (not implemented yet: only False)",
                         only_default("kinSplit", False)),
        "dampGravity": Attr(True, "Damping also acts on gravity (YADE's behaviour)", to_bool),
        "mask": Attr(-1, "Move only the bodies sharing a bit with this mask; <= 0: all (a body left out keeps its "
                         "velocity and position)", to_int("mask")),
        "prevVelGrad": Attr(Matrix3.Zero, "Velocity gradient of the periodic cell at the previous step [1/s]"),
    }

    def params_key(self, scene, held: list) -> tuple:
        """The integrator's parameters are its attributes' values (the gravity vector read, not its edit count: a
        vector changed in place counts too), whether the scene is large enough for the vectorized steps and
        whether it holds clumps or aspherical bodies."""
        return (self.damping, self.gravity._a.tolist(), self.dampGravity, self.mask,
                vectorized(scene.body_count).value, _aspherical_paths(scene).value)

    def params(self, scene, engines) -> NewtonParams:
        return NewtonParams(gravity=np.array(self.gravity._a, dtype=np.float64), damping=float(self.damping),
                            damp_gravity=bool(self.dampGravity), mask=int(self.mask),
                            vectorized=vectorized(scene.body_count), aspherical=_aspherical_paths(scene))


def _aspherical_paths(scene) -> Static:
    """:attr:`NewtonParams.aspherical <granum.kernels.newton.NewtonParams.aspherical>` of ``scene``."""
    bodies = scene.bodies
    return aspherical_paths(scene.shapes[ShapeKind.CLUMP].count, bodies.stored("aspherical")[:bodies.count])


class GravityEngine(GlobalEngine):
    """Apply m g to every body (deprecated in YADE in favour of NewtonIntegrator.gravity)."""

    stage = "granum.kernels.forces:gravity_stage"
    _attrs = {
        "gravity": Attr(Vector3(0, 0, 0), "Gravitational acceleration [m/s^2]", to_vec3),
        "mask": Attr(0, "Only bodies sharing a bit with this mask (0: all)", to_int("mask")),
        "warnOnce": Attr(True, "Accepted for compatibility", to_bool),
    }

    def params(self, scene, engines) -> GravityParams:
        return GravityParams(gravity=np.array(self.gravity._a, dtype=np.float64), mask=int(self.mask))
