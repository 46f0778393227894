"""CpmStateUpdater: the per-body values of the concrete particle model (CpmState), from its contacts.

For each body with a CpmState, over its contacts of the concrete law (CpmPhys) and the ``numBrokenCohesive``
contacts the law has ended:

.. math::
    \\text{normDmg} = \\frac{\\sum_{\\text{cohesive}} (1 - \\rho) + n_b}{n_c + n_b}\\ (0 \\text{ if } n_c + n_b = 0),
    \\qquad
    \\boldsymbol\\sigma = \\frac{0.62}{\\frac43 \\pi r^3} \\sum \\frac{l_0}{2}\\,
        \\mathrm{sym}\\big((F_n \\mathbf n + \\mathbf F_s) \\otimes \\mathbf n\\big)

(rho: a contact's relative residual strength, n_c: its cohesive contacts, n_b: numBrokenCohesive, r: the
sphere's radius, l_0 the contact's refLength, F_n and F_s as CpmPhys holds them, tension positive; every CPM
contact counts in the stress, the cohesive ones only in the damage). ``avgRelResidual``: the mean of rho over
the cohesive contacts, the ended contacts counting as 0 (NaN without either); ``maxOmega`` stays NaN, and
``numContacts`` and ``epsVolumetric`` as they were, as in YADE 2023.02a. The engine runs in Python, with
NumPy over the contact pool, at its periods (YADE's examples run it every 0.5-1 s of wall-clock time or
every 50 steps). Checked against YADE 2023.02a: tests/reference/yade/cpm.py.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, to_bool, to_float
from granum.core.bodies import CPM_IS_STATE, CPM_NORM_DMG, CPM_STRESS
from granum.core.contacts import C_CONTACTS, F_NORMAL, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2, I_PHYS
from granum.core.shapes import ShapeKind
from granum.engines.base import PeriodicEngine
from granum.kernels.dispatch import code_of
from granum.physics import cpm

#: YADE's packing fraction for the volume a particle's stress is spread over [-]
PACKING_FRACTION = 0.62


class CpmStateUpdater(PeriodicEngine):
    """Update the CpmState of bodies from the concrete model's contacts (module docstring)."""

    _attrs = {
        "initRun": Attr(True, "Run at the first step too (YADE's default for this engine)", to_bool),
        "avgRelResidual": Attr(math.nan, "Mean relative residual strength at the last run [-]", to_float(
            "avgRelResidual")),
        "maxOmega": Attr(math.nan, "Largest damage at the last run (YADE 2023.02a leaves it NaN) [-]",
                         to_float("maxOmega")),
    }

    def run_python(self, omega) -> None:
        scene = omega._scene
        b = scene.bodies
        nb = b.count
        C = scene.contacts
        n = int(C.ctr[C_CONTACTS])
        ci = C.con_i[:n]
        mine = ((ci[:, I_FLAGS] & FLAG_ALIVE) != 0) & (ci[:, I_PHYS] == code_of("Ip2_CpmMat_CpmMat_CpmPhys"))
        f = C.con_f[:n][mine]
        ids = (ci[mine, I_ID1], ci[mine, I_ID2])
        broken = b.stored("cpm_broken")[:nb].astype(float)
        if broken.shape[0] < nb:
            broken = np.zeros(nb)
        cohesive = f[:, cpm.CPM_IS_COHESIVE] != 0.0 if f.size else np.zeros(0, bool)
        residual = f[:, cpm.CPM_REL_RESIDUAL] if f.size else np.zeros(0)
        count = broken.sum() / 2 + cohesive.sum()   # each ended contact was counted on both its bodies
        self.avgRelResidual = float(residual[cohesive].sum() / count) if count else math.nan
        state = b.stored("cpm_state")
        if state.shape[0] < nb:
            return   # no body has a CpmState
        damaged = np.zeros(nb)
        links = np.zeros(nb)
        stress = np.zeros((nb, 9))
        if f.size:
            normal = f[:, F_NORMAL:F_NORMAL + 3]
            force = f[:, cpm.CPM_FN, None] * normal + f[:, cpm.CPM_FS:cpm.CPM_FS + 3]
            outer = force[:, :, None] * normal[:, None, :]
            contrib = (0.25 * f[:, cpm.CPM_REF_LENGTH])[:, None] * (outer + outer.transpose(0, 2, 1)).reshape(-1, 9)
            for side in ids:   # np.add.at adds in contact order: the same bits at any thread count
                np.add.at(damaged, side[cohesive], 1.0 - residual[cohesive])
                np.add.at(links, side[cohesive], 1.0)
                np.add.at(stress, side, contrib)
        spheres = b.alive[:nb] & (b.shape_kind[:nb] == int(ShapeKind.SPHERE)) & (state[:nb, CPM_IS_STATE] != 0.0)
        rows = np.nonzero(spheres)[0]
        radius = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[rows]]
        total = links[rows] + broken[rows]
        state[rows, CPM_NORM_DMG] = np.where(total > 0, (damaged[rows] + broken[rows]) / np.where(total > 0, total, 1),
                                             0.0)
        volume = 4.0 / 3.0 * math.pi * radius ** 3 / PACKING_FRACTION
        state[rows, CPM_STRESS:CPM_STRESS + 9] = stress[rows] / volume[:, None]
