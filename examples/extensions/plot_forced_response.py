"""
Forced response of the normal contact
=====================================

The paper's outlook (Sec. 5) asks for damping in the contact and for normal vibration
driven by an excitation rather than left free. Here the contact has Kelvin–Voigt damping
with ratio ζ = 0.03 and the slider carries a harmonic normal force P0 sin 2πft
(:doc:`/theory/extensions`). Its steady response is a periodic orbit, found by shooting
and followed in frequency by pseudo-arclength continuation, with its stability from the
Floquet multipliers (:doc:`/theory/periodic_orbits`).

Two checks frame the picture: for a small forcing the response is the linear oscillator
of stiffness K_n and damping c, amplitude P0/sqrt((K_n − m ω²)² + (c ω)²); for a large one
the curve bends towards lower frequencies (the contact softens as the amplitude grows,
as the backbone of the free vibration does) and folds, so that two stable orbits coexist
between the folds. Run time: about three seconds (four branches).
"""

# %%
# One branch, step by step
# ------------------------
#
# :func:`microslip.forced_response` starts on the orbit reached from rest at the first
# frequency and continues to the second; :func:`~microslip.plotting.response.response_figure`
# draws it (stable solid, unstable dashed, folds circled, contact loss in red).
import numpy as np

import microslip as ms
from microslip.plotting.extensions import forced_response_figure
from microslip.plotting.response import response_figure

p = ms.Parameters()
f0 = p.natural_frequency
model = ms.Model(
    p,
    damping=ms.Viscous(ratio=0.03),
    excitation=ms.HarmonicForce(amplitude=1.0, frequency=0.75 * f0),
)
branch = ms.forced_response(model, frequencies=(0.75 * f0, 1.1 * f0))
fig_branch = response_figure(branch)

folds = [int(i) for i in np.atleast_1d(branch.attrs["folds"])]
print(
    f"{branch.sizes['point']} points; folds at f/f0 = "
    f"{[round(float(branch.frequency[i]) / f0, 4) for i in folds]}"
)
print(
    f"largest amplitude {float(branch.amplitude.max()) / p.static_deflection:.3f} y0; "
    f"contact lost on {int(branch.contact_lost.sum())} points; "
    f"unstable points: {int((~branch.stable).sum())}"
)

# %%
# Several forcing levels and the linear limit
# -------------------------------------------
#
# :func:`microslip.plotting.extensions.forced_response_figure` draws the branches for
# P0 = 0.05, 0.2, 0.5 and 1 N from 0.6 f0 to 1.4 f0, with the linear oscillator dotted
# (the figure of ``microslip figures --extensions``). Its dataset holds every branch
# point and the linear amplitude at it.
fig_levels, data = forced_response_figure(p)
for k in range(int(data["branch"].max()) + 1):
    one = data.where(data["branch"] == k, drop=True)
    amplitude = one["amplitude"].values
    deviation = np.max(np.abs(amplitude / one["linear_amplitude"].values - 1))
    peak = int(np.argmax(amplitude))
    print(
        f"P0 = {float(one['excitation_amplitude'][0]):5.2f} N: peak "
        f"{amplitude[peak] / p.static_deflection:.4f} y0 at f/f0 = "
        f"{float(one['frequency'][peak]) / f0:.4f}; "
        f"largest deviation from the linear oscillator {deviation:.1%}"
    )
