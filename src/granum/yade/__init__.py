"""The YADE scripting layer: everything a YADE script finds without importing.

``from granum.yade import *`` gives an ordinary Python program the namespace of a
YADE script: ``O``, the engine, functor, shape and material classes, the
``yade.utils`` functions, the math types and everything from :mod:`math`. Scripts
run by the ``granum`` launcher get it automatically, and there ``import yade`` and
``from yade import pack, plot, ...`` resolve to this package.
"""

from __future__ import annotations

import argparse as _argparse
import doctest as _doctest
import itertools as _itertools
import math as _math
import os as _os
import random as _random
import sys as _sys
import time as _time
import warnings as _warnings

import numpy as _numpy
from future import standard_library as _standard_library

from granum import idem
from granum.engines import triaxial_engines as _triaxial_engines
from granum.engines.base import Engine, GlobalEngine, PartialEngine, PeriodicEngine
from granum.engines.controllers import PeriIsoCompressor, PeriTriaxController
from granum.engines.cpm import CpmStateUpdater
from granum.engines.domain import DomainLimiter
from granum.engines.factory import BoxFactory, CircularFactory, SpheresFactory
from granum.engines.fields import (
    AxialGravityEngine,
    CentralConstantAccelerationEngine,
    DragEngine,
    ForceEngine,
    InterpolatingDirectedForceEngine,
    LinearDragEngine,
    StepDisplacer,
    TorqueEngine,
)
from granum.engines.functors import CLASSES as _FUNCTORS
from granum.engines.functors import BoundFunctor, Functor, IGeomFunctor, IPhysFunctor, LawFunctor
from granum.engines.kinematic import (
    BicyclePedalEngine,
    CombinedKinematicEngine,
    HarmonicMotionEngine,
    HarmonicRotationEngine,
    HelixEngine,
    InterpolatingHelixEngine,
    KinematicEngine,
    RotationEngine,
    ServoPIDController,
    TranslationEngine,
)
from granum.engines.parallel import ParallelEngine
from granum.engines.peri3d import Peri3dController
from granum.engines.pipeline import (
    BoundDispatcher,
    Dispatcher,
    ForceResetter,
    GravityEngine,
    IGeomDispatcher,
    InsertionSortCollider,
    InteractionLoop,
    IPhysDispatcher,
    LawDispatcher,
    NewtonIntegrator,
)
from granum.engines.pyrunner import PyRunner
from granum.engines.runner import SimulationError
from granum.engines.simple_shear import (
    KinemCNDEngine,
    KinemCNLEngine,
    KinemCNSEngine,
    KinemCTDEngine,
    KinemSimpleShearBox,
)
from granum.engines.strainer import UniaxialStrainer
from granum.engines.timestepper import GlobalStiffnessTimeStepper, TimeStepper
from granum.engines.triaxial import TriaxialStressController
from granum.engines.triaxial_engines import ThreeDTriaxialEngine, TriaxialCompressionEngine
from granum.idem import IDEMSolver
from granum.mathtypes import Matrix3, Quaternion, Vector2, Vector2i, Vector3, Vector3i, Vector6, Vector6i
from granum.physics.matchmaker import MatchMaker
from granum.yade import (  # noqa: F401 - the yade.X modules (_laws: the law classes' accumulators and counts)
    _laws,
    bodiesHandling,
    config,
    export,
    geom,
    gts,
    libVersions,
    linterpolation,
    log,
    math,
    minieigenHP,
    pack,
    plot,
    post2d,
    qt,
    timing,
    utils,
    ymport,
)
from granum.yade.batch import readParamsFromTable, runningInBatch, waitIfBatch
from granum.yade.bodies import SHAPE_CLASSES, Aabb, Body, CpmState, Shape, State
from granum.yade.cell import Cell
from granum.yade.interactions import GEOM_VIEWS as _GEOMS
from granum.yade.interactions import PHYS_VIEWS as _PHYSS
from granum.yade.interactions import Interaction
from granum.yade.materials import CLASSES as _MATERIALS
from granum.yade.omega import O, Omega
from granum.yade.preprocessors import FileGenerator, SimpleShear, TriaxialTest
from granum.yade.recorders import Recorder, TriaxialStateRecorder
from granum.yade.snapshot import SnapshotEngine
from granum.yade.utils import *  # noqa: F403
from granum.yade.utils import __all__ as _utils_all
from granum.yade.video import makeVideo
from granum.yade.vtk import VTKRecorder


class _GlMeta(type):
    """Class-level attributes of display functors (``Gl1_Sphere.stripes = True``) are accepted."""


def _gl(name: str) -> type:
    return _GlMeta(name, (), {"__doc__": f"Display functor {name} (accepted; granum draws no OpenGL).",
                              "yade_parent": "Functor" if name.startswith("Gl1_") else None,
                              "__init__": lambda self, **kw: self.__dict__.update(kw)})


_GL_NAMES = ("Gl1_Sphere", "Gl1_Facet", "Gl1_Wall", "Gl1_Box", "Gl1_Aabb", "Gl1_NormPhys", "Gl1_L3Geom",
             "Gl1_L6Geom", "Gl1_CpmPhys", "Gl1_Cylinder", "Gl1_ChainedCylinder", "Gl1_Polyhedra",
             "Gl1_PFacet", "Gl1_GridConnection", "GlExtra_LawTester", "OpenGLRenderer")

_namespace: dict = {name: getattr(_math, name) for name in dir(_math) if not name.startswith("_")}
_namespace.update({name: _gl(name) for name in _GL_NAMES})
_namespace.update(_FUNCTORS)
_namespace.update(_MATERIALS)
_namespace.update(_GEOMS)
_namespace.update(_PHYSS)
_namespace.update({cls.__name__: cls for cls in SHAPE_CLASSES.values()})
_namespace.update({name: getattr(utils, name) for name in _utils_all})
_namespace.update(
    O=O, Omega=Omega, Engine=Engine, GlobalEngine=GlobalEngine, PartialEngine=PartialEngine,
    PeriodicEngine=PeriodicEngine, Functor=Functor, BoundFunctor=BoundFunctor, IGeomFunctor=IGeomFunctor,
    IPhysFunctor=IPhysFunctor, LawFunctor=LawFunctor, ForceResetter=ForceResetter, GravityEngine=GravityEngine,
    InsertionSortCollider=InsertionSortCollider, InteractionLoop=InteractionLoop, NewtonIntegrator=NewtonIntegrator,
    PyRunner=PyRunner, PeriTriaxController=PeriTriaxController, PeriIsoCompressor=PeriIsoCompressor,
    Peri3dController=Peri3dController,
    Dispatcher=Dispatcher,
    BoundDispatcher=BoundDispatcher, IGeomDispatcher=IGeomDispatcher, IPhysDispatcher=IPhysDispatcher,
    LawDispatcher=LawDispatcher, TimeStepper=TimeStepper, GlobalStiffnessTimeStepper=GlobalStiffnessTimeStepper,
    TriaxialStressController=TriaxialStressController, Recorder=Recorder,
    TriaxialStateRecorder=TriaxialStateRecorder, TriaxialCompressionEngine=TriaxialCompressionEngine,
    ThreeDTriaxialEngine=ThreeDTriaxialEngine, UniaxialStrainer=UniaxialStrainer, FileGenerator=FileGenerator,
    TriaxialTest=TriaxialTest, SimpleShear=SimpleShear, KinemSimpleShearBox=KinemSimpleShearBox,
    KinemCTDEngine=KinemCTDEngine, KinemCNDEngine=KinemCNDEngine, KinemCNLEngine=KinemCNLEngine,
    KinemCNSEngine=KinemCNSEngine,
    ForceEngine=ForceEngine, TranslationEngine=TranslationEngine, RotationEngine=RotationEngine,
    KinematicEngine=KinematicEngine, HelixEngine=HelixEngine, CombinedKinematicEngine=CombinedKinematicEngine,
    DomainLimiter=DomainLimiter, MatchMaker=MatchMaker, SpheresFactory=SpheresFactory,
    CircularFactory=CircularFactory, BoxFactory=BoxFactory,
    ParallelEngine=ParallelEngine, HarmonicMotionEngine=HarmonicMotionEngine,
    HarmonicRotationEngine=HarmonicRotationEngine, InterpolatingHelixEngine=InterpolatingHelixEngine,
    BicyclePedalEngine=BicyclePedalEngine, ServoPIDController=ServoPIDController, TorqueEngine=TorqueEngine,
    InterpolatingDirectedForceEngine=InterpolatingDirectedForceEngine, StepDisplacer=StepDisplacer,
    DragEngine=DragEngine, LinearDragEngine=LinearDragEngine, AxialGravityEngine=AxialGravityEngine,
    CentralConstantAccelerationEngine=CentralConstantAccelerationEngine,
    CpmStateUpdater=CpmStateUpdater, CpmState=CpmState,
    SimulationError=SimulationError, Body=Body, State=State, Shape=Shape, Aabb=Aabb, Cell=Cell,
    Interaction=Interaction, Vector2=Vector2, Vector2i=Vector2i, Vector3=Vector3,
    Vector3i=Vector3i, Vector6=Vector6, Vector6i=Vector6i, Matrix3=Matrix3, Quaternion=Quaternion,
    readParamsFromTable=readParamsFromTable, waitIfBatch=waitIfBatch, runningInBatch=runningInBatch,
    utils=utils, geom=geom, pack=pack, plot=plot, qt=qt, timing=timing, ymport=ymport, export=export,
    gts=gts,  # PyGTS: YADE's scripts find it without importing
)
_triaxial_engines.scene_source = lambda: O._scene  # setContactProperties acts on O's scene
#: YADE's command-line options as its launcher parses them (``opts.threads``...); granum's launcher fills in
#: ``threads``, ``script`` and ``args``
opts = _argparse.Namespace(version=False, threads=None, cores=None, updateScripts=None, nice=None, exitAfter=True,
                           verbosity=None, nogui=True, test=False, check=False, checkall=False, performance=False,
                           quickperformance=False, stdperformance=None, script=None, args=[], impLibraries=None,
                           mpi_mode=False)
# the modules and names YADE's launcher leaves in a script's namespace
_namespace.update(sys=_sys, os=_os, time=_time, math=_math, random=_random, numpy=_numpy, argparse=_argparse,
                  itertools=_itertools, warnings=_warnings, doctest=_doctest, standard_library=_standard_library,
                  arange=_numpy.arange, opts=opts, args=opts.args)
_namespace.update({name: getattr(pack, name) for name in pack.__all__ if not name.endswith("Centers")})
_namespace.update(VTKRecorder=VTKRecorder, SnapshotEngine=SnapshotEngine, makeVideo=makeVideo,
                  idem=idem, IDEMSolver=IDEMSolver, yade=_sys.modules[__name__])
_namespace.update(features=config.features)
globals().update(_namespace)
__all__ = sorted(_namespace)
# yade.math and yade.log are the modules of those names; scripts get Python's math and math.log, as in YADE
for _module in ("math", "log"):
    globals()[_module] = _sys.modules[f"{__name__}.{_module}"]
    __all__.remove(_module)


def namespace() -> dict:
    """A fresh copy of the script namespace (what a YADE script sees without imports)."""
    return dict(_namespace)
