# iDEM cost on a heap: 1,000 small boxes (3 x 3 x 3 particles each) released from a loose
# lattice with random orientations fall on a fixed floor and pile up; every step's iteration
# counts and the speed are written to heap.csv and summarised on stdout.
# Run with:  granum examples/idem/heap.py [steps] [sequential|simultaneous]
#      (or:  python examples/idem/heap.py ...)
import csv
import sys
import time

import numpy as np

from granum import idem

N_SIDE = 10          # 10 x 10 x 10 = 1,000 boxes
SIZE = 0.2           # box edge [m]
SPACING = 0.1        # particle spacing [m]: 3 particles per edge
PITCH = 0.4          # lattice pitch of the initial positions [m] (> box diagonal: no overlap)
steps = int(sys.argv[1]) if len(sys.argv) > 1 else 1200
impact = sys.argv[2] if len(sys.argv) > 2 else "sequential"

rng = np.random.default_rng(2024)
solver = idem.IDEMSolver(e=0.3, mu=0.5, alpha0=15, dt=5e-4, impact=impact)
extent = N_SIDE * PITCH + 2.0
solver.add(idem.plane_body((0, 0, 0), (extent, extent), SPACING))
for i in range(N_SIDE):
    for j in range(N_SIDE):
        for k in range(N_SIDE):
            centre = (PITCH * (i - (N_SIDE - 1) / 2) + rng.uniform(-0.03, 0.03),
                      PITCH * (j - (N_SIDE - 1) / 2) + rng.uniform(-0.03, 0.03),
                      0.25 + PITCH * k)
            axis = rng.normal(size=3)
            solver.add(idem.box_body(centre, (SIZE, SIZE, SIZE), SPACING, density=2500.0,
                                     ori=(axis / np.linalg.norm(axis), rng.uniform(0, np.pi))))
print(f"{len(solver.bodies) - 1} boxes, {len(solver._pbody)} particles ({len(solver._surf)} on surfaces)")

t0 = time.perf_counter()
solver.run(1)  # first step: compiles the kernels (or loads them from the cache)
print(f"first step (compilation or cache load): {time.perf_counter() - t0:.1f} s")
wall0 = solver.wall
solver.run(steps - 1, every=100, callback=lambda s: print(
    f"t = {s.time:.3f} s  contacts {s.stats['contacts']:5d}  rounds {s.stats['rounds']:3d}  "
    f"iterations {s.stats['compression_iterations'] + s.stats['release_iterations']:7d}  "
    f"steps/s {(s.iter - 1) / (s.wall - wall0):.1f}", flush=True))

h = solver.history
its = h[:, 2] + h[:, 3]
with open("heap.csv", "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["t", "contacts", "rounds", "iterations", "impulses"])
    for n in range(len(h)):
        w.writerow([f"{(n + 1) * solver.dt:.6g}", int(h[n, 0]), int(h[n, 1]), int(its[n]), int(h[n, 4])])
late = slice(len(h) // 2, None)
print(f"iterations per step: mean {its.mean():.0f}, max {its.max():.0f}; over the second half: mean "
      f"{its[late].mean():.0f} with {h[late, 0].mean():.0f} contacts on average")
print(f"steps per second: {(steps - 1) / (solver.wall - wall0):.2f} (wall {solver.wall - wall0:.1f} s for "
      f"{steps - 1} steps); capped steps: {int((h[:, 10] > 0).sum())}")
