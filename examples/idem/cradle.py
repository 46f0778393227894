# iDEM verification 4 (article "10個の物体の衝突"): a row of ten equal 2.0 x 1.0 x 2.0 m boxes, nine at
# rest in contact, the first hitting them at 1.0 m/s; e = 1, mu = 0, no gravity, dt = 5e-4 s,
# alpha0 = 150. Writes cradle.csv (t, v_first, v_last) and cradle.png (against the analytic
# outcome: the striker stops, the last box leaves at 1.0 m/s).
# Run with:  granum examples/idem/cradle.py     (or: python examples/idem/cradle.py)
import csv
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from granum.idem import cases  # noqa: E402

V0, GAP, N = 1.0, 0.1, 10
t0 = time.perf_counter()
run = cases.cradle(n=N, e=1.0, alpha0=150.0, dt=5e-4, v0=V0, gap=GAP, duration=0.4)
elapsed = time.perf_counter() - t0
t, vf, vl = run["t"], run["v_first"], run["v_last"]
with open("cradle.csv", "w", newline="") as fh:
    out = csv.writer(fh)
    out.writerow(["t", "v_first", "v_last"])
    out.writerows((f"{a:.6g}", f"{b:.9g}", f"{c:.9g}") for a, b, c in zip(t, vf, vl, strict=True))
s = run["solver"]
p = run["p"][:, 0]
its = s.iterations()
print(f"final velocities: {np.array2string(run['v'][-1], precision=6)} m/s")
print(f"momentum error {np.abs(p - run['p0'][0]).max() / abs(run['p0'][0]):.1e} (relative); kinetic energy "
      f"{run['ke0']:.3f} -> {run['ke'][-1]:.3f} J")
print(f"iterations per step: {its.mean():.0f} on average, {its.max():.0f} in the impact step "
      f"({s.history[:, 1].max():.0f} rounds); {len(t) / s.wall:.0f} steps/s "
      f"({len(t)} steps in {s.wall:.2f} s of solver time, {elapsed:.2f} s with recording)")

t_hit = GAP / V0
ta = np.linspace(0.0, t[-1], 801)
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(ta, np.where(ta < t_hit, V0, 0.0), "k-", lw=1, label="analytic, striker")
ax.plot(ta, np.where(ta < t_hit, 0.0, V0), "k--", lw=1, label="analytic, last box")
ax.plot(t[::5], vf[::5], "r.", ms=3, label="iDEM, striker")
ax.plot(t[::5], vl[::5], "b.", ms=3, label="iDEM, last box")
ax.set_xlabel("t [s]")
ax.set_ylabel("velocity [m/s]")
ax.set_title("Ten boxes in a row (Newton's cradle), e = 1, alpha0 = 150, dt = 5e-4 s")
ax.legend()
fig.tight_layout()
fig.savefig("cradle.png", dpi=120)
