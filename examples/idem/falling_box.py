# iDEM verification 1 (article "法線方向成分の確認"): a 2.0 x 1.0 x 2.0 m box of particles dropped
# flat from 0.6 m onto a fixed floor, e = 0.5, dt = 5e-4 s, alpha0 = 15. Writes falling_box.csv
# (t, vz) and falling_box.png (simulation against the analytic bouncing solution).
# Run with:  granum examples/idem/falling_box.py     (or: python examples/idem/falling_box.py)
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from granum.idem import analytic, cases  # noqa: E402

H, E = 0.6, 0.5
run = cases.falling_box(e=E, alpha0=15.0, dt=5e-4, h=H, duration=1.5)
t, vz = run["t"], run["vz"]
with open("falling_box.csv", "w", newline="") as fh:
    out = csv.writer(fh)
    out.writerow(["t", "vz"])
    out.writerows(zip((f"{x:.6g}" for x in t), (f"{x:.9g}" for x in vz), strict=True))

# rebounds: the steps where the velocity jumps upwards; impact speed = speed after the gravity kick
kick = 9.81 * 5e-4
hits = [n for n in range(1, len(vz)) if vz[n] > 0 and vz[n] - vz[n - 1] > 3 * kick]
for k, n in enumerate(hits[:6]):
    u = kick - vz[n - 1]
    print(f"impact {k + 1} at t = {t[n]:.4f} s: impact speed {u:.4f} m/s, rebound {vz[n]:.4f} m/s, "
          f"ratio {vz[n] / u:.5f} (e = {E})")
s = run["solver"]
print(f"at t = {t[-1]:.2f} s: vz = {vz[-1]:+.2e} m/s, height of the bottom {run['z'][-1]:+.2e} m; "
      f"iterations per step: mean {s.iterations().mean():.0f}, max {s.iterations().max():.0f}")

ta = np.linspace(0.0, t[-1], 3001)
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(ta, analytic.bounce_velocity(ta, H, E), "k-", lw=1, label="analytic")
ax.plot(t[::4], vz[::4], "r.", ms=2, label="iDEM")
ax.set_xlabel("t [s]")
ax.set_ylabel("vertical velocity vz [m/s]")
ax.set_title(f"Box dropped from {H} m, e = {E}, alpha0 = 15, dt = 5e-4 s")
ax.legend()
fig.tight_layout()
fig.savefig("falling_box.png", dpi=120)
