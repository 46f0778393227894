"""The random numbers of YADE's seeded packings: C++'s ``std::mt19937`` with libstdc++'s
``uniform_real_distribution<double>(0, 1)``, in compiled code.

``SpherePack.makeCloud(..., seed=k)`` in YADE 2023.02a draws every radius and coordinate from a Mersenne
Twister seeded with ``k``, each number made of two 32-bit outputs as libstdc++'s ``generate_canonical`` makes
a 53-bit double: u = fl(d1 + d2 · 2³²) / 2⁶⁴ (below 1). Drawing the same numbers in the same order gives the
same cloud: checked sphere by sphere against YADE's output (tests/reference/yade/pack_cloud.py).

The generator is the published MT19937 (M. Matsumoto and T. Nishimura, "Mersenne Twister: a
623-dimensionally equidistributed uniform pseudo-random number generator", ACM TOMACS 8, 1998) with the
C++ standard's seeding (``std::mersenne_twister_engine::seed``, the ``init_genrand`` of the reference code).
State: a (625,) uint64 array, the 624 words and the index of the next one.
"""

from __future__ import annotations

import numpy as np

from granum._jit import jit

_N, _M = 624, 397
_MASK32 = 0xFFFFFFFF


@jit
def mt_new(seed):
    """A new generator state (625,) uint64 seeded with ``seed`` (taken modulo 2³², as std::mt19937's seed)."""
    s = np.empty(_N + 1, np.uint64)
    s[0] = np.uint64(seed & _MASK32)
    for i in range(1, _N):
        prev = s[i - 1]
        s[i] = (np.uint64(1812433253) * (prev ^ (prev >> np.uint64(30))) + np.uint64(i)) & np.uint64(_MASK32)
    s[_N] = _N  # the next output twists the state first
    return s


@jit
def _twist(s):
    for i in range(_N):
        y = (s[i] & np.uint64(0x80000000)) | (s[(i + 1) % _N] & np.uint64(0x7FFFFFFF))
        v = s[(i + _M) % _N] ^ (y >> np.uint64(1))
        if y & np.uint64(1):
            v ^= np.uint64(0x9908B0DF)
        s[i] = v
    s[_N] = 0


@jit
def mt_next32(s):
    """The next 32-bit output of the generator ``s`` (as an unsigned value in a uint64)."""
    if s[_N] >= _N:
        _twist(s)
    y = s[s[_N]]
    s[_N] += np.uint64(1)
    y ^= y >> np.uint64(11)
    y ^= (y << np.uint64(7)) & np.uint64(0x9D2C5680)
    y ^= (y << np.uint64(15)) & np.uint64(0xEFC60000)
    y ^= y >> np.uint64(18)
    return y & np.uint64(_MASK32)


@jit
def mt_uniform(s):
    """A double uniform in [0, 1) from two outputs, as libstdc++'s generate_canonical<double, 53>."""
    low = float(mt_next32(s))
    high = float(mt_next32(s))
    u = (low + high * 4294967296.0) / 18446744073709551616.0
    return u if u < 1.0 else np.nextafter(1.0, 0.0)
