"""
Fig. 6: momentary loss of contact
=================================

**The paper's figure.** Fig. 6 of Grudziński & Kostek (2005): a free normal vibration
large enough that the slider leaves the slideway for part of each period, (a) y,
(b) ẏ, (c) the phase portrait, (d) :math:`|R|` and (e) the friction force with the drive
F = 0.5 N, and (f) x, (g) ẋ, (h) ẍ of the slider.

**What the paper states** (Sec. 4): while contact is lost :math:`|R|` and F_t are zero; with such
vibrations any small tangential force moves the slider ("vibrating items drifting on a
resting tabletop"). The text does not give the amplitude of its Fig. 6; we use
A = 1.3 y0.

**Ours.** :func:`microslip.plotting.figure6`. During a flight (y < 0) the slider moves on
a parabola, ÿ = g, which the simulation follows in closed form between the located
instants of lift-off and touchdown (:doc:`/theory/numerics`). Run time: well under a
second.
"""

# %%
import numpy as np

import microslip as ms
from microslip.plotting import figure6

p = ms.Parameters()
fig, ds = figure6(p)

# %%
# The values the paper states, and ours
# -------------------------------------
#
# In flight (state 2) the reaction and the friction force are exactly zero and the
# slider accelerates tangentially at F/m; the mean reaction over whole periods stays m g
# (eq. 2.4 integrated over a period).
state = ds["state"].values
flight = state == 2
F, m = float(ds["force"]), p.mass
print(f"A = {float(ds['amplitude_ratio']):.2f} y0, period {float(ds['period']) * 1e3:.4f} ms")
t = ds["time"].values
print(f"fraction of the time in flight: {np.diff(t)[flight[:-1]].sum() / (t[-1] - t[0]):.3f}")
print(
    f"in flight: max |R| = {np.abs(ds['R'].values[flight]).max()} N, "
    f"max |F_t| = {np.abs(ds['Ft'].values[flight]).max()} N, "
    f"xddot = F/m: {np.allclose(ds['xddot'].values[flight], F / m, rtol=1e-12)}"
)

# %%
# Any small force moves the slider: with loss of contact the threshold of eq. (4.2) is 0,
# and the exact mean velocity is positive even for F = 1 % of μ m g.
amplitude = float(ds["amplitude"])
print(f"threshold mu S c_n max(y0 - A, 0)^m2 = {p.motion_threshold(amplitude)} N")
for fraction in (0.01, 0.1, 0.5):
    v = ms.mean_velocity(p, force=fraction * p.static_friction_force, amplitude=amplitude)
    print(f"F = {fraction:4.2f} mu m g: mean velocity {v * 1e6:.3f} µm/s")
