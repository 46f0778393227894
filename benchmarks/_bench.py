"""Timing and reporting shared by the benchmark scripts.

The scripts run unmodified under both ``granum`` and ``yade -n -x``; they import this
module from their own directory (``sys.argv[0]`` is the script path in both launchers).
"""

import os
import resource
import time


def env_int(name, default):
    """Integer from environment variable ``name``, or ``default``."""
    return int(os.environ.get(name, str(default)))


def measure(O, name, n_spheres, steps, warmup, t_script, extra=None, drive=None):
    """Run ``warmup`` untimed steps (collider's first run, granum's kernel compilation),
    then ``steps`` timed steps in one ``O.run(steps, True)``, and print one line
    ``BENCH name=... seconds=... steps_per_s=...`` for ``benchmarks/run`` to parse.

    ``t_script``: ``time.perf_counter()`` at the start of the script (set-up time is
    measured from it). ``extra``: callable returning ``{key: value}`` to append after the run.
    ``drive``: callable running ``n`` steps, instead of ``O.run(n, True)``.
    """
    t_setup = time.perf_counter() - t_script
    t0 = time.perf_counter()
    if warmup > 0:
        O.run(warmup, True)
    t_warmup = time.perf_counter() - t0
    t0 = time.perf_counter()
    if drive is None:
        O.run(steps, True)
    else:
        drive(steps)
    seconds = time.perf_counter() - t0
    rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # ru_maxrss is in kB on Linux
    fields = {
        'name': name,
        'spheres': n_spheres,
        'bodies': len(O.bodies),
        'steps': steps,
        'threads': O.numThreads,
        'seconds': f'{seconds:.6g}',
        'steps_per_s': f'{steps / seconds:.6g}',
        'particle_steps_per_s': f'{n_spheres * steps / seconds:.6g}',
        'contacts': O.interactions.countReal(),
        'peak_rss_mb': f'{rss_mb:.1f}',
        'setup_s': f'{t_setup:.3g}',
        'warmup_s': f'{t_warmup:.3g}',
        'total_s': f'{time.perf_counter() - t_script:.6g}',
    }
    if extra is not None:
        fields.update(extra())
    print('BENCH ' + ' '.join(f'{k}={v}' for k, v in fields.items()))
