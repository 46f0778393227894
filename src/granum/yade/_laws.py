"""What a script reads from a law functor about the current scene's contacts: the accumulators and counts
of ``Law2_ScGeom_MindlinPhys_Mindlin`` (YADE's ``frictionDissipation``, ``ratioSlidingContacts()``...), the
elastic energy of ``Law2_ScGeom_CpmPhys_Cpm``.

They are added to the classes generated from the registry (:mod:`granum.engines.functors`) and computed
with NumPy from the contacts of ``O``'s scene that this law handles. The energies are sums of the
per-contact accumulators the compiled law keeps (:mod:`granum.physics.mindlin`, with ``calcEnergy``) over
the live contacts, plus the shares of the contacts that ended (the pool's ``ended`` totals,
:func:`granum.core.contacts.register_totals`), as YADE's accumulators keep them.
"""

from __future__ import annotations

import numpy as np

from granum.core.contacts import C_CONTACTS, F_KN, F_KS, F_PEN, FLAG_ALIVE, I_FLAGS, I_LAW
from granum.engines.functors import CLASSES
from granum.kernels.dispatch import code_of
from granum.physics import cpm, mindlin, mindlin_cdm
from granum.yade.interactions import PHYS_VIEWS

MINDLIN = CLASSES["Law2_ScGeom_MindlinPhys_Mindlin"]


def _rows(law_name: str, width: int = mindlin.F_MINDLIN + 27) -> np.ndarray:
    """The ``con_f`` rows of the current scene's live contacts handled by ``law_name`` (0 rows if the pool
    is narrower than ``width``: it has no such contact)."""
    from granum.yade.omega import O

    C = O._scene.contacts
    n = int(C.ctr[C_CONTACTS])
    ci = C.con_i[:n]
    live = (ci[:, I_FLAGS] & FLAG_ALIVE != 0) & (ci[:, I_LAW] == code_of(law_name))
    f = C.con_f[:n][live]
    return f if f.shape[1] >= width else f[:0, :0]


def _column_sum(col: int):
    def get(self) -> float:
        from granum.yade.omega import O

        f = _rows(type(self).__name__)
        ended = O._scene.contacts.ended
        return (float(f[:, col].sum()) if f.size else 0.0) + (float(ended[col]) if len(ended) > col else 0.0)
    return property(get, doc=f"Sum over the live contacts (column {col} of the pool) and the ended ones [J]")


MINDLIN.frictionDissipation = _column_sum(mindlin.F_FRICT_DISSIP)
MINDLIN.shearEnergy = _column_sum(mindlin.F_SHEAR_ENERGY)
MINDLIN.normDampDissip = _column_sum(mindlin.F_NDAMP_DISSIP)
MINDLIN.shearDampDissip = _column_sum(mindlin.F_SDAMP_DISSIP)


def _ratio_sliding(self) -> float:
    """Fraction of this law's contacts that slide (NaN without contacts, as YADE's 0/0) [-]."""
    f = _rows(type(self).__name__)
    return float(f[:, mindlin.F_SLIDING].sum() / f.shape[0]) if f.size else float("nan")


def _contacts_adhesive(self) -> float:
    """Number of this law's contacts whose normal force pulls (includeAdhesion) [-]."""
    f = _rows(type(self).__name__)
    return float(f[:, mindlin.F_ADHESIVE].sum()) if f.size else 0.0


def _norm_elast_energy(self) -> float:
    """Normal elastic energy of this law's contacts, sum of 2/5 kno delta^(5/2) [J] (with includeAdhesion,
    less the work of the adhesion force, adhesionForce delta)."""
    f = _rows(type(self).__name__)
    if not f.size:
        return 0.0
    pen = np.maximum(f[:, F_PEN], 0.0)
    e = 0.4 * f[:, mindlin.F_KNO] * pen ** 2.5
    if self.includeAdhesion:
        e = e - f[:, mindlin.F_ADH] * pen
    return float(e.sum())


def _get_ratcheting(self) -> bool:
    """YADE's deprecated alias of ``nothing`` (no effect)."""
    return self.nothing


def _set_ratcheting(self, value) -> None:
    self.nothing = value


MINDLIN.ratioSlidingContacts = _ratio_sliding
MINDLIN.contactsAdhesive = _contacts_adhesive
MINDLIN.normElastEnergy = _norm_elast_energy
MINDLIN.preventGranularRatcheting = property(_get_ratcheting, _set_ratcheting, doc=_get_ratcheting.__doc__)


def _cpm_elastic_energy(self) -> float:
    """Elastic energy of the concrete law's contacts, sum of Fn^2 / (2 kn (1 - omega)) + |Fs|^2 / (2 ks) [J]
    (YADE 2023.02a's: the normal term divides by the damaged stiffness, also in compression; a contact with
    omega = 1 makes it infinite)."""
    f = _rows(type(self).__name__, cpm.CPM_E + cpm.CPM_WIDTH)
    if not f.size:
        return 0.0
    fs = f[:, cpm.CPM_FS:cpm.CPM_FS + 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        normal = 0.5 * f[:, cpm.CPM_FN] ** 2 / (f[:, F_KN] * (1.0 - f[:, cpm.CPM_OMEGA]))
        shear = 0.5 * (fs * fs).sum(axis=1) / f[:, F_KS]
    return float((normal + shear).sum())


CLASSES["Law2_ScGeom_CpmPhys_Cpm"].elasticEnergy = _cpm_elastic_energy


def _func_g(kappaD, epsCrackOnset, epsFracture, neverDamage=False, damLaw=1) -> float:
    """Damage omega of the concrete law for the largest equivalent strain kappaD (YADE's CpmPhys.funcG) [-]."""
    return float(cpm.damage(float(kappaD), float(epsCrackOnset), float(epsFracture), bool(neverDamage), damLaw == 0))


def _func_g_inv(omega, epsCrackOnset, epsFracture, neverDamage=False, damLaw=1) -> float:
    """kappaD whose damage is omega (YADE's CpmPhys.funcGInv) [-]."""
    return cpm.damage_inverse(float(omega), float(epsCrackOnset), float(epsFracture), bool(neverDamage), int(damLaw))


PHYS_VIEWS["CpmPhys"].funcG = staticmethod(_func_g)
PHYS_VIEWS["CpmPhys"].funcGInv = staticmethod(_func_g_inv)


CDM = CLASSES["Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM"]


def _ratio_yielding(self) -> float:
    """Fraction of this law's contacts that are being crushed (isYielding; NaN without contacts, as YADE's
    0/0) [-]."""
    f = _rows(type(self).__name__, mindlin_cdm.F_CDM + 9)
    return float(f[:, mindlin_cdm.F_YIELDING].sum() / f.shape[0]) if f.size else float("nan")


CDM.ratioSlidingContacts = _ratio_sliding
CDM.ratioYieldingContacts = _ratio_yielding
