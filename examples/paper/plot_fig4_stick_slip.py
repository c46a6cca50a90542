"""
Fig. 4: stick–slip driven by normal micro-vibrations
====================================================

**The paper's figure.** Fig. 4 of Grudziński & Kostek (2005) is a grid of time histories
for a constant tangential force F = 0.5 N (about half of μ m g = 0.981 N), in four
columns for the amplitudes A = 0, y0/3, 2y0/3 and y0: rows (a) y, (b) ẏ, (c) ÿ, (d) :math:`|R|`,
(e) the friction force against F (columns 1–4), and (f) x, (g) ẋ, (h) ẍ of the slider
(columns 1′–4′).

**What the paper states** (Sec. 4): without vibration (A = 0) :math:`|R|` = m g, F_t = μ m g and
the slider stays at rest, since F < μ m g (eq. 4.1). With vibration, motion is possible
below μ m g, under condition (4.2): the slider moves in short slips, once per normal
period, whenever the friction limit :math:`μ|R|` drops below F. The jerks Δx, the peak velocity
and the mean velocity grow with the amplitude.

**Ours.** :func:`microslip.plotting.figure4`, from simulations with every stick/slip
switch located (:doc:`/theory/numerics`), with the exact steady slip distance and mean
velocity of each column (:doc:`/theory/steady_sliding`) in its dataset. Run time: under a
second.
"""

# %%
import microslip as ms
from microslip.plotting import figure4

p = ms.Parameters()
fig, ds = figure4(p)

# %%
# The values the paper states, and ours
# -------------------------------------
#
# The motion threshold of eq. (4.2), F > μ min :math:`|R|` = μ S c_n (y0 − A)^m2, and the steady
# stick–slip of each column: no motion at A = 0, then Δx and the mean velocity growing
# with A.
F = float(ds["force"])
print(f"F = {F} N, mu m g = {p.static_friction_force:.3f} N")
for k, a in enumerate(ds["amplitude_ratio"].values):
    amplitude = a * p.static_deflection
    threshold = p.motion_threshold(amplitude)
    dx = float(ds["slip_distance"][k])
    v = float(ds["mean_velocity"][k])
    moves = "moves" if F > threshold else "stays"
    print(
        f"A = {a:.3f} y0: threshold {threshold:.3f} N -> {moves}; "
        f"slip per period {dx * 1e9:6.2f} nm, mean velocity {v * 1e6:6.2f} µm/s"
    )

# %%
# The same steady cycle from :func:`microslip.stick_slip_cycle`: the slip and stick
# times per normal period and the peak velocity of each slip.
for a in (1 / 3, 2 / 3, 1.0):
    c = ms.stick_slip_cycle(p, force=F, amplitude=a * p.static_deflection)
    print(
        f"A = {a:.3f} y0: slip {c.slip_time * 1e3:.3f} ms, stick {c.stick_time * 1e3:.3f} ms, "
        f"peak velocity {c.peak_velocity * 1e6:6.1f} µm/s"
    )
