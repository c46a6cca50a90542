"""
Fig. 7: mean sliding velocity over force and amplitude
======================================================

**The paper's figure.** Fig. 7 of Grudziński & Kostek (2005) is a surface of the mean
sliding velocity v (axis in units of 10⁻⁴ m/s) over the tangential force F (up to about
0.9 N) and the vibration amplitude A (up to about 0.3 µm), for μ = 0.1, with a "no
sliding" region at small F and A and the regions "without loss of contact" and "with
loss of contact" marked.

**What the paper states** (Sec. 4): no sliding for small enough amplitudes and forces;
for A > 0.225 µm = y0 contact is lost momentarily and the slider moves under even very
small forces; motion at a constant mean velocity below μ m g needs A > 0; above μ m g
the slider accelerates (not analysed).

**Ours.** :func:`microslip.velocity_map` with the exact steady state (one period of the
normal vibration per amplitude, shared by every force; :doc:`/theory/steady_sliding`),
drawn by :func:`microslip.plotting.velocity_map_figure`: (a) the surface as in the paper,
(b) filled contours with the analytic no-sliding boundary of eq. (4.2) and the line
A = y0. Grid: 181 forces × 151 amplitudes, a fraction of a second; a 256 × 256 map takes
well under a second too.
"""

# %%
import numpy as np

import microslip as ms
from microslip.plotting import velocity_map_figure

p = ms.Parameters()
forces = np.linspace(0.05, 0.95, 181)  # [N], below mu m g = 0.981 N
amplitudes = np.linspace(0.0, 3e-7, 151)  # [m]
v = ms.velocity_map(p, forces=forces, amplitudes=amplitudes)
fig = velocity_map_figure(v.to_dataset(), p)

# %%
# The values the paper states, and ours
# -------------------------------------
#
# The no-sliding region is exactly F <= μ S c_n max(y0 − A, 0)^m2 (eq. 4.2): v is 0 on
# one side and positive on the other. Above A = y0 every force moves the slider. The
# largest mean velocity on this grid is of the order of the paper's 10⁻⁴ m/s axis.
values = v.transpose("force", "amplitude").values
limit = np.array([[p.motion_threshold(a) for a in amplitudes]])
F = forces[:, None]
print("v == 0 wherever F < threshold:", bool(np.all(values[F < limit * (1 - 1e-9)] == 0.0)))
print("v > 0 wherever F > threshold:", bool(np.all(values[F > limit * (1 + 1e-9)] > 0.0)))
lost = amplitudes > p.static_deflection
print(
    f"A > y0 = {p.static_deflection * 1e6:.4f} µm: smallest v over all forces "
    f"{values[:, lost].min():.3e} m/s (> 0)"
)
i, j = np.unravel_index(values.argmax(), values.shape)
print(
    f"largest v on the grid: {values[i, j]:.3e} m/s at F = {forces[i]:.2f} N, "
    f"A = {amplitudes[j] * 1e6:.3f} µm"
)
