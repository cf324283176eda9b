"""The paper's Figure 2 drawn with matplotlib: Newmark, Simpson and the exact solution of the
pendulum at 10 steps per period over five periods.

    python3 examples/python/figure2.py [OUT.png]
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import varsym  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "figure2.png"
data = varsym.figure_data(2)
fig, (ax_q, ax_p) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
for ax, name in ((ax_q, "q"), (ax_p, "p")):
    ax.plot(data["t"], data[f"{name}_exact"], "k-", lw=1, label="exact")
    ax.plot(data["t"], data[f"{name}_newmark"], "o--", ms=3, label="Newmark")
    ax.plot(data["t"], data[f"{name}_simpson"], "s:", ms=3, label="Simpson")
    ax.set_ylabel(name)
ax_p.set_xlabel("t [s]")
ax_q.legend(loc="upper right", fontsize=8)
ax_q.set_title("Pendulum, 10 steps per period (Figure 2 of Dubois & Rojas-Quintero 2023)")
fig.tight_layout()
fig.savefig(out, dpi=120)
print(f"wrote {out}")
print("OK")
