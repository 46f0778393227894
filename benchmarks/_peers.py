"""The dense lattice next to LAMMPS and LIGGGHTS (``benchmarks/run --peers``).

``peers/dense_lattice.lammps`` and ``peers/dense_lattice.liggghts`` build the scene of ``dense_lattice.py``
(same lattice, radius, density, stiffnesses kn = E r and ks = 0.3 kn, friction, six walls, gravity, time step).
Each program runs the same number of timed steps at 1 and at 2 processes (granum: threads), taking turns, and
the fastest run of each counts. The peers' time is their "Loop time" of the timed run (their set-up and first
step excluded, like granum's warm-up); their contact count (sphere-sphere pairs, from compute contact/atom) is
checked against the lattice's 3 n² (n - 1), which granum's count includes (granum also counts the wall
contacts).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
PEERS = {"LAMMPS": ("lmp", "dense_lattice.lammps"), "LIGGGHTS": ("liggghts", "dense_lattice.liggghts")}
TARGET = 1.5  # granum / LAMMPS, steps per second, at each process count
_LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps")


def run_peer(program: str, procs: int, n: int, steps: int, workdir: str, timeout: float) -> dict | None:
    """One run of ``program`` ("LAMMPS" or "LIGGGHTS"): {"steps_per_s", "seconds", "contacts"}, or None when
    the program is not installed; raises RuntimeError with the output's tail when it fails."""
    exe, script = PEERS[program]
    if shutil.which(exe) is None:
        return None
    cmd = [exe, "-in", os.path.join(HERE, "peers", script), "-var", "n", str(n), "-var", "steps", str(steps),
           "-log", "none"]
    if procs > 1:
        root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
        cmd = ["mpirun", *root, "-np", str(procs), *cmd]
    p = subprocess.run(cmd, cwd=workdir, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, errors="replace", timeout=timeout)
    loops = _LOOP.findall(p.stdout)
    contacts = re.findall(r"PEER contacts=([0-9.]+)", p.stdout)
    if p.returncode != 0 or not loops or not contacts or int(loops[-1][2]) != steps:
        raise RuntimeError(f"{' '.join(cmd)}: rc={p.returncode}\n{p.stdout[-3000:]}")
    seconds = float(loops[-1][0])
    return {"seconds": seconds, "steps_per_s": steps / seconds, "contacts": int(float(contacts[-1]))}


def peers_check(args, granum, workdir, failures, run_one) -> None:
    """Print the table granum -j1/-j2 vs LAMMPS and LIGGGHTS at 1/2 processes on the dense lattice."""
    n = 20
    steps = 50 if args.quick else 500
    repeat = args.repeat if args.repeat is not None else (1 if args.quick else 3)
    env = {"BENCH_N": str(n), "BENCH_STEPS": str(steps)}
    best: dict[tuple[str, int], dict | None] = {}
    for _ in range(repeat):
        for procs in (1, 2):
            rec, status, out = run_one(granum, "granum", procs, "dense_lattice.py", env, workdir, args.timeout)
            if rec is None:
                failures.append(("granum", f"peers -j{procs}", status, out))
            elif best.get(("granum", procs)) is None or rec["steps_per_s"] > best[("granum", procs)]["steps_per_s"]:
                best[("granum", procs)] = rec
            for program in PEERS:
                try:
                    got = run_peer(program, procs, n, steps, workdir, args.timeout)
                except (RuntimeError, subprocess.TimeoutExpired) as e:
                    failures.append((program, f"peers np={procs}", "FAIL", str(e)))
                    continue
                key = (program, procs)
                if got is not None and (best.get(key) is None or got["steps_per_s"] > best[key]["steps_per_s"]):
                    best[key] = got
    lattice_pairs = 3 * n * n * (n - 1)
    print(f"dense lattice, {n ** 3} spheres, {steps} steps (fastest of {repeat}); "
          f"sphere-sphere contacts of the lattice: {lattice_pairs}")
    print(f"{'program':<10} {'procs':>5} {'steps/s':>10} {'contacts':>9} {'granum/it':>10}  target")
    for procs in (1, 2):
        g = best.get(("granum", procs))
        for program in ("granum", *PEERS):
            rec = best.get((program, procs))
            if rec is None:
                print(f"{program:<10} {procs:>5} {'(not run)':>10}")
                continue
            ratio = g["steps_per_s"] / rec["steps_per_s"] if g and program != "granum" else None
            target = ""
            if program == "LAMMPS" and ratio is not None:
                target = f">={TARGET}x LAMMPS {'PASS' if ratio >= TARGET else 'FAIL'}"
            if program != "granum" and rec["contacts"] != lattice_pairs:
                failures.append((program, f"peers np={procs}", "contacts",
                                 f"{rec['contacts']} sphere-sphere contacts, expected {lattice_pairs}"))
            print(f"{program:<10} {procs:>5} {rec['steps_per_s']:>10.4g} {rec['contacts']:>9} "
                  f"{'' if ratio is None else f'{ratio:.2f}':>10}  {target}")
