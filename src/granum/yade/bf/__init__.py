"""``yade.bf``: breakage functions (YADE's package layout: the functions live in ``yade.bf.bf`` and
the package re-exports them; scripts also ``from bf import ...``, as YADE's launcher allows).
See :mod:`granum.yade.bf.bf`."""

from granum.yade.bf import bf
from granum.yade.bf.bf import checkFailure, evalClump, growParticle, replaceSphere, stressTensor

__all__ = ["bf", "checkFailure", "evalClump", "growParticle", "replaceSphere", "stressTensor"]
