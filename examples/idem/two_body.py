# iDEM verification 3 (article "2個の物体の衝突"): two equal 2.0 x 1.0 x 2.0 m boxes, A at 2.0 m/s hits B
# at rest, e = 0.5, mu = 0, dt = 5e-4 s, alpha0 = 150 (no gravity: with mu = 0 a floor would only
# carry the weight). Writes two_body.csv (t, vA, vB) and two_body.png (against the 1-D impact).
# Run with:  granum examples/idem/two_body.py     (or: python examples/idem/two_body.py)
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from granum.idem import analytic, cases  # noqa: E402

E, V0, GAP = 0.5, 2.0, 0.1
run = cases.two_body(e=E, alpha0=150.0, dt=5e-4, v0=V0, gap=GAP, duration=0.3)
t, va, vb = run["t"], run["vA"], run["vB"]
with open("two_body.csv", "w", newline="") as fh:
    out = csv.writer(fh)
    out.writerow(["t", "vA", "vB"])
    out.writerows((f"{a:.6g}", f"{b:.9g}", f"{c:.9g}") for a, b, c in zip(t, va, vb, strict=True))
fa, fb = analytic.collision_velocities(1.0, 1.0, V0, 0.0, E)
p = run["p"][:, 0]
s = run["solver"]
print(f"final vA = {va[-1]:.6f} m/s (analytic {fa}), vB = {vb[-1]:.6f} m/s (analytic {fb}); "
      f"momentum error {np.abs(p - run['p0'][0]).max() / abs(run['p0'][0]):.1e} (relative); "
      f"kinetic energy {run['ke0']:.1f} -> {run['ke'][-1]:.1f} J; "
      f"iterations in the impact step {s.iterations().max():.0f}")

t_hit = GAP / V0
ta = np.linspace(0.0, t[-1], 601)
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(ta, np.where(ta < t_hit, V0, fa), "k-", lw=1, label="analytic")
ax.plot(ta, np.where(ta < t_hit, 0.0, fb), "k--", lw=1)
ax.plot(t[::5], va[::5], "r.", ms=3, label="iDEM, A")
ax.plot(t[::5], vb[::5], "b.", ms=3, label="iDEM, B")
ax.set_xlabel("t [s]")
ax.set_ylabel("velocity [m/s]")
ax.set_title(f"Two equal boxes, e = {E}, alpha0 = 150, dt = 5e-4 s")
ax.legend()
fig.tight_layout()
fig.savefig("two_body.png", dpi=120)
