# iDEM verification 2 (article "接線方向成分の確認"): the 2.0 x 1.0 x 2.0 m box released at rest on a
# 30 degree slope, e = 0, mu in {0, 0.1, 0.3, 0.5}, dt = 5e-4 s, alpha0 = 15. Writes slope.csv
# (t, mu, v: speed along the slope) and slope.png (against v = g (sin 30 - mu cos 30) t).
# Run with:  granum examples/idem/slope.py     (or: python examples/idem/slope.py)
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from granum.idem import analytic, cases  # noqa: E402

THETA = math.radians(30.0)
fig, ax = plt.subplots(figsize=(7, 4))
with open("slope.csv", "w", newline="") as fh:
    out = csv.writer(fh)
    out.writerow(["t", "mu", "v"])
    for mu, colour in zip((0.0, 0.1, 0.3, 0.5), ("C0", "C1", "C2", "C3"), strict=True):
        run = cases.slope(mu, theta=THETA, e=0.0, alpha0=15.0, dt=5e-4, duration=1.0)
        t, v = run["t"], run["v"]
        out.writerows((f"{a:.6g}", mu, f"{b:.9g}") for a, b in zip(t, v, strict=True))
        exact = analytic.slope_speed(t, THETA, mu)
        accel = float((t * v).sum() / (t * t).sum())
        print(f"mu = {mu}: acceleration {accel:.6f} m/s^2 (analytic {exact[-1] / t[-1]:.6f}), largest error "
              f"{abs(v - exact).max():.2e} m/s, iterations per step {run['solver'].iterations().mean():.0f}")
        ax.plot(t, exact, "k-", lw=1)
        ax.plot(t[::40], v[::40], "o", color=colour, ms=3, label=f"iDEM, mu = {mu}")
ax.plot([], [], "k-", lw=1, label="g (sin 30° - mu cos 30°) t")
ax.set_xlabel("t [s]")
ax.set_ylabel("speed along the slope v [m/s]")
ax.set_title("Box sliding on a 30° slope, e = 0, alpha0 = 15, dt = 5e-4 s")
ax.legend()
fig.tight_layout()
fig.savefig("slope.png", dpi=120)
