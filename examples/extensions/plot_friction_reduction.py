"""
Friction reduction by normal vibration: the drive speed
=======================================================

A body slid at a prescribed velocity v over a contact whose normal force oscillates,
N(t) = N0 (1 + β cos ωt), feels a mean friction force below μ N0 only if its contact
can stick. With a compliant tangential contact (a spring k_t between the body and the
contact point) the contact point sticks while the friction limit μN rises faster than
the spring force k_t v can follow: the spring force then lags below μN, and the mean
friction coefficient μ_eff = <F_t>/<N> falls below μ. That happens only below the
critical speed, ṽ = k_t v / (μ max|dN/dt|) < 1 (:doc:`/theory/friction_reduction`).

For a flat punch (m2 = 1, N linear in the penetration) under a prescribed penetration
δ = δ_m (1 + β cos ωt) the reduction has a closed form: for β <= 1,
μ_eff/μ = 1 − β D(ṽ), with D(0) = 1 and D = 0 for ṽ >= 1. Below, the simulated curves
for four values of β collapse onto D; two with β > 1, where the contact opens in every
period and the spring relaxes, do not. Then μ_eff over drive speed and amplitude, with
the critical speed ṽ = 1 drawn in.

Run time: about eight seconds (258 points of the master curve, 375 of the map; each
point a simulation over a few excitation periods).
"""

# %%
# One period of stick and slip
# ----------------------------
#
# The flat punch of the paper's data (:func:`~microslip.plotting.friction.flat_punch`:
# m2 = 1, same contact stiffness K_n and f0), β = 0.5, k_t = K_n, driven at ṽ = 0.3.
# The spring force f follows μN while the contact point slides and falls behind it
# (stick, constant slope k_t v) where N rises steeply.
import numpy as np
from matplotlib.figure import Figure

import microslip as ms
from microslip.plotting.friction import (
    MASTER_BETAS,
    critical_speed,
    flat_punch_model,
    master_curve_figure,
    mu_eff_map_figure,
)

p = ms.Parameters()
beta = 0.5
model = flat_punch_model(p, beta, velocity=0.3 * critical_speed(p, beta))
period = 1.0 / model.excitation.frequency
t = np.linspace(0.0, 4.0 * period, 2001)
run = ms.simulate(model, duration=t[-1], t_eval=t)

fig_period = Figure(figsize=(7.5, 3.8), layout="constrained")
ax = fig_period.subplots()
ax.plot(run.t * 1e3, p.mu * run.N, color="0.4", lw=1.0, label="friction limit μN")
ax.plot(run.t * 1e3, run.spring_force, color="C0", lw=1.4, label="spring force f")
stick = run.direction == 0
ax.plot(run.t[stick] * 1e3, run.spring_force[stick], ".", ms=2, color="C3", label="stick")
ax.set_xlabel("t [ms]")
ax.set_ylabel("force [N]")
ax.set_title(f"flat punch, β = {beta}, ṽ = 0.3: the spring force lags below μN while stuck")
ax.legend(fontsize=8, loc="lower right")
ax.grid(True, lw=0.4, alpha=0.5)

# %%
# The master curve
# ----------------
#
# :func:`~microslip.plotting.friction.master_curve_figure` computes μ_eff with
# :func:`~microslip.analysis.effective_friction.effective_friction_curve` for each β at
# the same values of ṽ, and plots (1 − μ_eff/μ)/β against ṽ with the closed form D(ṽ).
fig_master, master = master_curve_figure(p)
collapse = master["reduction"].sel(beta=list(MASTER_BETAS))
spread = float((collapse.max("beta") - collapse.min("beta")).max())
error = float(abs(collapse - master["closed_form"]).max())
print(f"beta <= 1: spread across beta {spread:.2e}, largest distance from D(v~) {error:.2e}")
print("beta = 3 at v~ = 0.5: (1 - mu_eff/mu)/beta = "
      f"{float(master['reduction'].sel(beta=3.0, v_tilde=0.5)):.4f}, "
      f"D(0.5) = {float(master['closed_form'].sel(v_tilde=0.5)):.4f}")  # fmt: skip

# %%
# μ_eff over drive speed and amplitude
# ------------------------------------
#
# :func:`~microslip.plotting.friction.mu_eff_map_figure`: the penetration amplitude Δ
# from 0.05 δ_m to 1.45 δ_m against the drive speed. The white line is ṽ = 1,
# v_c = μ S c_n Δ ω / k_t: friction is reduced only to its left, and the more the
# slower the drive and the larger the amplitude.
fig_map, mu_map = mu_eff_map_figure(p)
ratio = mu_map["ratio"]
print(
    f"mu_eff/mu from {float(ratio.min()):.3f} to {float(ratio.max()):.3f}; "
    f"reduced (< 0.999) at {int((ratio < 0.999).sum())} of {ratio.size} points"
)
