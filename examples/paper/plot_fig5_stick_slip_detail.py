"""
Fig. 5: friction force and velocity in stick–slip
=================================================

**The paper's figure.** Fig. 5 of Grudziński & Kostek (2005) enlarges the two largest
amplitudes of Fig. 4 (A = 2y0/3 and y0, F = 0.5 N): (a), (b) the drive F and the friction
force F_t against time, with the potential static friction :math:`μ|R|` as thin lines while the
slider sticks; (c) the friction force against the sliding velocity ẋ; (d), (e) ẋ(t);
(f) the phase plane x–ẋ of the sliding phases.

**What the paper states** (Sec. 4): a slip starts when the friction limit falls below F;
the velocity first rises (F_t < F), then falls (F_t > F) until the slider stops; while
sliding F_t = F − m ẍ, while sticking the real friction force equals F and the potential
one is much higher. For given vibrations the stick–slip settles on a stable limit cycle,
and both phases are very short.

**Ours.** :func:`microslip.plotting.figure5`. In (f) x is counted from each release, so
every steady slip lies on one arch: the limit cycle. Run time: under a second.
"""

# %%
import numpy as np

import microslip as ms
from microslip.plotting import figure5

p = ms.Parameters()
fig, ds = figure5(p)

# %%
# The values the paper states, and ours
# -------------------------------------
#
# While sliding the friction force is F − m ẍ (eq. 2.5) and equals :math:`-μ|R|` (eq. 2.2); while
# sticking it equals −F and :math:`μ|R|` exceeds F. Both are checked on the plotted samples, and
# the phases of each steady cycle are listed: "very short" means fractions of a
# millisecond.
F = float(ds["force"])
for k, a in enumerate(ds["amplitude_ratio"].values):
    state = ds["state"].values[k]
    Ft, limit = ds["Ft"].values[k], ds["friction_limit"].values[k]
    xddot = ds["xddot"].values[k]
    slip, stick = state == 1, state == 0
    law = np.max(np.abs(Ft[slip] + limit[slip])) / F
    balance = np.max(np.abs(Ft[slip] - (p.mass * xddot[slip] - F))) / F
    margin = np.min(limit[stick] - F)
    c = ms.stick_slip_cycle(p, force=F, amplitude=a * p.static_deflection)
    print(
        f"A = {a:.3f} y0: sliding |F_t + mu|R||/F <= {law:.1e}, |F_t - (m xddot - F)|/F <= "
        f"{balance:.1e}; sticking mu|R| - F >= {margin:.3f} N; "
        f"slip {c.slip_time * 1e3:.3f} ms, stick {c.stick_time * 1e3:.3f} ms per cycle"
    )
