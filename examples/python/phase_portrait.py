"""A phase portrait of your own system, defined in Python without compiling anything: the
pendulum L = ½ m l² θ̇² + m g l cos θ as a string, integrated by Simpson's scheme from several
initial angles (oscillations, and rotations above the separatrix).

    python3 examples/python/phase_portrait.py [OUT.png]
"""
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import varsym  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "phase_portrait.png"
pendulum = varsym.Lagrangian("0.5*m*l**2*th_dot**2 + m*g*l*cos(th)", ["th"],
                             {"m": 1.0, "g": 9.81, "l": 1.0})
fig, ax = plt.subplots(figsize=(7, 4.5))
worst = 0.0
for v0 in [1.0, 2.5, 4.0, 5.5, 6.5, 7.0]:
    rows = varsym.Stepper(pendulum, h=0.01, q0=[0.0], v0=[v0]).run(400)
    worst = max(worst, np.ptp(rows["energy"]) / abs(rows["energy"][0]))
    th = (rows["q"][:, 0] + np.pi) % (2 * np.pi) - np.pi  # θ in [−π, π): rotations wrap
    p = rows["p"][:, 0].copy()
    p[1:][np.abs(np.diff(th)) > np.pi] = np.nan  # no line across the wrap
    ax.plot(th, p, lw=1, label=f"v0 = {v0}")
ax.set_xlabel("θ [rad]")
ax.set_ylabel("p = m l² dθ/dt [kg m²/s]")
ax.set_title("Pendulum phase portrait (varsym.Lagrangian, Simpson, h = 0.01 s)")
ax.legend(fontsize=7, loc="upper right")
fig.tight_layout()
fig.savefig(out, dpi=120)
print(f"wrote {out}; largest relative energy variation {worst:.2e}")
assert worst < 1e-4, worst  # a symplectic scheme: bounded, small energy error
print("OK")
