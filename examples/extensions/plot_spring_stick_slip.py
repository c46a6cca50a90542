"""
Spring-driven stick–slip with and without normal vibration
==========================================================

The classic stick–slip experiment: a body on a slideway pulled through a spring whose
far end moves at a constant speed v_d, F = k_d (v_d t − x), under static/kinetic
friction μ_s > μ_k (:doc:`/theory/stick_slip_drive`). The body sticks while the spring
loads, slips when F reaches μ_s N, and sticks again once its velocity returns to zero.
At a constant N = m g and without damping the cycle has a closed form: the force drops
by exactly 2 (μ_s − μ_k) m g whatever the drive speed, the slip lasts
(π + 2 atan(v_d / (Δ ω)))/ω and the stick 2Δ/v_d, with Δ = (μ_s − μ_k) m g/k_d and
ω = sqrt(k_d/m).

The paper's free normal vibration of amplitude A changes that: the friction limit
μ_s N(t) oscillates at the contact frequency f0, the body breaks loose near a minimum
of N, earlier and at a lower force, and the drop shrinks; at a larger amplitude the
stick–slip gives way to micro-slips near every minimum of N, with the spring force
hovering about μ_k m g.

Run time: about a second once compiled (three event simulations, each run until the
stick–slip is established).
"""

# %%
# The three runs
# --------------
#
# :func:`~microslip.plotting.stick_slip.spring_stick_slip_figure` builds the model of
# :func:`~microslip.plotting.stick_slip.stick_slip_model` (rigid contact,
# ``StaticKinetic(μ_s = 1.5 μ, μ_k = μ)``, ``SpringDrive(k_d = 1e-3 K_n, v_d)``) and runs
# :func:`~microslip.analysis.spring_stick_slip.stick_slip_drive` for A = 0, 0.1 y0 and
# 0.3 y0. It draws the last cycles of each: the spring force against the friction limit
# μ_s N (the grey band, oscillating at f0 with vibration), and the body velocity.
import microslip as ms
from microslip.analysis.stick_slip_closed_form import constant_normal_cycle
from microslip.plotting.stick_slip import spring_stick_slip_figure, stick_slip_model

p = ms.Parameters()
fig, cycles = spring_stick_slip_figure(p)

# %%
# The numbers against the closed form
# -----------------------------------
#
# Without vibration the simulated cycle is the closed form's;
# :func:`~microslip.analysis.stick_slip_closed_form.constant_normal_cycle` gives it.
model = stick_slip_model(p)
closed = constant_normal_cycle(model)
still = cycles.sel(case=0)
print(f"no vibration: force drop {float(still['force_drop']):.6f} N "
      f"(closed form {closed.force_drop:.6f} N), period {float(still['period']) * 1e3:.4f} ms "
      f"(closed form {closed.period * 1e3:.4f} ms)")  # fmt: skip
for k in range(1, cycles.sizes["case"]):
    case = cycles.isel(case=k)
    amplitude = float(case["amplitude"]) / p.static_deflection
    print(f"A = {amplitude:.1f} y0: mean force drop {float(case['force_drop']):.4f} N "
          f"(std {float(case['force_drop_std']):.2g} N), mean period "
          f"{float(case['period']) * 1e3:.3f} ms")  # fmt: skip
