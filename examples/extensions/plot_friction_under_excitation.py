"""
Friction under normal excitation: mean velocity and effective friction
======================================================================

A constant tangential force F below μ m g cannot move a slider on a still contact. Under
a harmonic normal force the contact's normal force N(t) oscillates about its mean m g
(the mean is exactly m g in any periodic state: integrate m ÿ = m g + P − N over a
period), and whenever μN drops below F the slider slips. The steady mean velocity is
exact: the reflected process of the free drift over one period of the periodic normal
orbit (:doc:`/theory/steady_sliding`, identity 5 there).

Two views, both with Kelvin–Voigt damping ζ = 0.03:

1. the force needed to slide at a mean velocity of 10 µm/s, as an effective friction
   coefficient μ_eff = F/(m g), against the excitation frequency
   (:func:`microslip.friction_curve`), for three forcing levels;
2. the mean velocity over force and frequency at P0 = 0.5 N
   (:func:`microslip.plotting.extensions.forced_velocity_map_figure`).

The friction coefficient is constant throughout: the reduction comes from the dynamics
of the contact alone, the paper's point. Run time: about eight seconds (25 frequencies ×
three levels, a root search in F at each).
"""

# %%
# Effective friction against the excitation frequency
# ---------------------------------------------------
#
# microslip has no plotting function for a friction curve; the dataset has units on
# every variable and a plain line plot shows it.
import numpy as np
from matplotlib.figure import Figure

import microslip as ms
from microslip.plotting.extensions import forced_velocity_map_figure

p = ms.Parameters()
f0 = p.natural_frequency
frequencies = np.linspace(0.6, 1.4, 25) * f0  # [Hz]
curves = {}
for P0 in (0.25, 0.5, 1.0):  # [N], of m g = 9.81 N
    model = ms.Model(
        p, damping=ms.Viscous(ratio=0.03), excitation=ms.HarmonicForce(amplitude=P0, frequency=f0)
    )
    curves[P0] = ms.friction_curve(model, frequencies=frequencies, velocity=1e-5)

fig = Figure(figsize=(7.5, 4.5), layout="constrained")
ax = fig.subplots()
for P0, ds in curves.items():
    ax.plot(ds["frequency"] / f0, ds["mu_eff_ratio"], marker=".", label=f"P0 = {P0} N")
ax.axhline(1.0, color="0.5", lw=0.8, ls="--", label="no excitation: μ_eff = μ")
ax.set_xlabel("excitation frequency f / f0 [-]")
ax.set_ylabel("μ_eff / μ = F_needed / (μ m g) [-]")
ax.set_title("force needed for a mean velocity of 10 µm/s, viscous damping ζ = 0.03")
ax.legend(fontsize=8)
ax.grid(True, lw=0.4, alpha=0.5)

for P0, ds in curves.items():
    ratio = ds["mu_eff_ratio"].values
    k = int(np.nanargmin(ratio))
    print(
        f"P0 = {P0:4.2f} N: smallest mu_eff/mu = {ratio[k]:.3f} at f/f0 = "
        f"{float(ds['frequency'][k]) / f0:.3f}; all period-1: {bool(ds['period_one'].all())}"
    )

# %%
# Mean velocity over force and frequency
# --------------------------------------
#
# The extension figure of ``microslip figures --extensions``: v(F, f) from
# :func:`microslip.sweep` over ``excitation.frequency`` (19 forces × 21 frequencies, one
# periodic orbit per frequency shared by every force).
fig_map, v = forced_velocity_map_figure(p)
velocity = v["mean_velocity"]
print(
    f"v from {float(velocity.min()):.3g} to {float(velocity.max()):.3g} "
    f"{velocity.attrs['units']}; points that slide: {int((velocity > 0).sum())} of {velocity.size}"
)
