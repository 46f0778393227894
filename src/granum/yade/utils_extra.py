"""The rest of ``yade.utils``, by theme; :mod:`granum.yade.utils` re-exports these names."""

from granum.yade.edits import *  # noqa: F403
from granum.yade.edits import __all__ as _edits
from granum.yade.formulas import *  # noqa: F403
from granum.yade.formulas import __all__ as _formulas
from granum.yade.measures import *  # noqa: F403
from granum.yade.measures import __all__ as _measures

__all__ = [*_edits, *_formulas, *_measures]
