"""
Fig. 3: normal vibration and contact forces
===========================================

**The paper's figure.** Fig. 3 of Grudziński & Kostek (2005): (a) the normal free
vibration y(t) with the largest amplitude that keeps contact, A = y0 (started at rest
at y = 0, just touching); (b) the normal reaction :math:`|R|(t)` and the friction force
F_t = :math:`μ|R|` it would allow, with μ = 0.1.

**What the paper states** (Sec. 3): the reaction and the friction force are periodic and
vary "from nearly 0 up to approximately 3 times" the static value m g; their mean does
not change.

**Ours.** :func:`microslip.plotting.figure3`. For A = y0 and m2 = 2 the largest reaction
is exactly 3 m g (energy conservation from the top, y = 0, to the lowest point;
:doc:`/theory/free_vibration`), and the time average of :math:`|R|` over a period is exactly m g
(integrate eq. 2.4 over a period). Run time: well under a second.
"""

# %%
import numpy as np

import microslip as ms
from microslip.plotting import figure3

p = ms.Parameters()
fig, ds = figure3(p)

# %%
# The values the paper states, and ours
# -------------------------------------
#
# The range of :math:`|R|` in units of m g, and its mean over whole periods (the dataset holds
# several periods, sampled densely; the mean is taken with the trapezoidal rule over
# whole periods, so it carries a small discretisation error).
weight = float(ds["weight"])
R, t = ds["R"].values, ds["time"].values
print(f"min |R| = {R.min() / weight:.4f} m g   (paper: nearly 0)")
print(f"max |R| = {R.max() / weight:.4f} m g   (paper: about 3; exact: 3)")
period = float(ds["period"])
whole = t <= t[0] + np.floor((t[-1] - t[0]) / period) * period
mean = np.trapezoid(R[whole], t[whole]) / (t[whole][-1] - t[whole][0])
print(f"mean |R| over whole periods = {mean / weight:.5f} m g   (exact: 1)")
max_friction = ds["Ft"].values.max()
print(f"max F_t = mu max|R| = {max_friction:.4f} N (mu m g = {p.static_friction_force:.4f} N)")
