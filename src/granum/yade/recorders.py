"""Text recorders: ``Recorder`` (YADE's base: a file opened for appending) and ``TriaxialStateRecorder``."""

from __future__ import annotations

import math
import os

from granum.core.attrs import Attr, to_bool, to_str
from granum.engines.base import PeriodicEngine
from granum.engines.triaxial import TriaxialStressController
from granum.yade import utils


def _number(x: float) -> str:
    """A value as YADE's recorders write it (17 significant digits, ``-nan`` for a negative NaN)."""
    if math.isnan(x):
        return "-nan" if math.copysign(1.0, x) < 0 else "nan"
    return f"{x:.17g}"


class Recorder(PeriodicEngine):
    """Engine that appends lines to a text file (YADE ``Recorder``); ``truncate`` empties it at the first run."""

    _attrs = {
        "file": Attr("", "Name of the file written", to_str("file")),
        "truncate": Attr(False, "Empty the file at the first run instead of appending to it", to_bool),
        "addIterNum": Attr(False, "Append the step number to the file name", to_bool),
    }

    def __init__(self, **kw):
        kw.setdefault("initRun", True)
        super().__init__(**kw)
        object.__setattr__(self, "_opened", None)

    def _path(self, omega) -> str:
        if not self.file:
            raise ValueError(f"{type(self).__name__}.file is empty: give the name of the file to write")
        return f"{self.file}{omega._scene.iter}" if self.addIterNum else self.file

    def write(self, omega, line: str, header: str = "") -> None:
        """Append ``line`` (and, to a new or emptied file, ``header`` first)."""
        path = self._path(omega)
        mode = "a"
        if self._opened != path:
            if self.truncate:
                mode = "w"
            object.__setattr__(self, "_opened", path)
        with open(path, mode) as f:
            if header and (mode == "w" or not os.path.exists(path) or os.path.getsize(path) == 0):
                f.write(header + "\n")
            f.write(line + "\n")


class TriaxialStateRecorder(Recorder):
    """Write the state of the TriaxialStressController in O.engines every ``iterPeriod`` steps, one line of
    ``iteration s11 s22 s33 e11 e22 e33 unb_force porosity kineticE`` (YADE's columns): the stresses on the
    right, top and front walls [Pa], the strains [-], utils.unbalancedForce(), the controller's porosity and
    utils.kineticEnergy() [J]."""

    HEADER = "iteration s11 s22 s33 e11 e22 e33 unb_force porosity kineticE"

    @property
    def porosity(self) -> float:
        """The porosity written last [-] (1 before the first line)."""
        return getattr(self, "_porosity", 1.0)

    def run_python(self, omega) -> None:
        triax = [e for e in omega._scene.engines if isinstance(e, TriaxialStressController)]
        if not triax:
            raise RuntimeError("TriaxialStateRecorder: no TriaxialStressController in O.engines to record")
        t = triax[0]
        object.__setattr__(self, "_porosity", t.porosity)
        values = [t.stress(1)[0], t.stress(3)[1], t.stress(5)[2],
                  *t.strain, utils.unbalancedForce(), t.porosity, utils.kineticEnergy()]
        self.write(omega, " ".join([str(omega._scene.iter)] + [_number(float(v)) for v in values]), self.HEADER)
