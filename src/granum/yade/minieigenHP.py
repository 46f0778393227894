"""``yade.minieigenHP``: the math types of Real, at module level and in the scope ``HP1``.

granum's math types (:mod:`granum.mathtypes`) hold doubles, the one precision level there is, so
``minieigenHP.HP1.Vector3`` is ``minieigenHP.Vector3`` is the ``Vector3`` of every script. Of YADE's
types, the complex ones (``Vector2c``, ``Vector3c``, ``Vector6c``, ``VectorXc``, ``Matrix3c``,
``Matrix6c``, ``MatrixXc``), ``Vector4``, ``Vector6i``, ``Matrix6``, ``VectorX``, ``MatrixX`` and
``AlignedBox2``/``AlignedBox3`` are not in granum yet.
"""

from __future__ import annotations

import types as _types

from granum.mathtypes import Matrix3, Quaternion, Vector2, Vector2i, Vector3, Vector3i, Vector6

#: whether there are aligned (vectorised) variants such as ``Vector3na``: no
vectorize = False

_TYPES = {"Vector2": Vector2, "Vector2i": Vector2i, "Vector3": Vector3, "Vector3i": Vector3i, "Vector6": Vector6,
          "Matrix3": Matrix3, "Quaternion": Quaternion}

HP1 = _types.ModuleType(f"{__name__}.HP1", "The math types of RealHP<1> (double): the same classes as at module level.")
HP1.__dict__.update(_TYPES, vectorize=vectorize)
