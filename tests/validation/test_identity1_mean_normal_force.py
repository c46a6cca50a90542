"""MODEL.md identity 1: in every periodic state ⟨N⟩ = m g (with damping, excitation and
loss of contact), since m ÿ = m g + P − N with ⟨ÿ⟩ = ⟨P⟩ = 0 over a period.

⟨N⟩ is integrated along ``microslip.periodic_orbit`` (its node arrays and
``orbit_state``, 8-point Gauss–Legendre per node interval) with N evaluated by the
independent law of ``forced_reference`` at the orbit's (t, y, ẏ): a wrong law in the
code, or an orbit that does not satisfy its own equation, moves ⟨N⟩ off m g. The
damped free decay (no excitation) tends to rest at y0, where N = m g: ``simulate`` is
checked against the scipy reference over the decay, and the running mean of N
(Simpson on a fine grid) against the closed form m g − m (ẏ(T) − ẏ(0))/T.
"""

import math

import numpy as np
import pytest
from forced_reference import NormalReference, periodic_cases, steady_case
from orbit_quadrature import orbit_average
from scipy.integrate import simpson

import microslip as ms


@pytest.mark.parametrize("name", sorted(periodic_cases()))
def test_mean_normal_force_on_periodic_orbit(name):
    model, ref, _u, summary = steady_case(name)
    orbit = ms.periodic_orbit(model)
    weight = model.params.mass * model.params.g
    mean_n = orbit_average(orbit, ref.normal_force)
    assert abs(mean_n / weight - 1.0) < 1e-9, (name, mean_n / weight - 1.0)
    # the reference itself obeys the identity, and agrees on contact loss
    assert abs(summary["mean_N"] / weight - 1.0) < 1e-10
    assert bool(orbit.contact_lost) == summary["contact_lost"]


def test_damped_free_decay_mean_tends_to_weight():
    p = ms.Parameters()
    model = ms.Model(p, damping=ms.HuntCrossley(ratio=0.2))
    y0, t0 = p.static_deflection, p.natural_period
    amplitude = 0.5 * y0  # stays in contact: N is smooth and Simpson is accurate
    duration = 20.0 * t0
    t_eval = np.linspace(0.0, duration, 20 * 400 + 1)
    r = ms.simulate(model, force=0.0, amplitude=amplitude, duration=duration, t_eval=t_eval)
    ref = NormalReference(model)
    run = ref.integrate(0.0, [1.0 - amplitude / y0, 0.0], duration * ref.omega,
                        tau_eval=t_eval * ref.omega)  # fmt: skip
    eta = np.concatenate([s[:, 0] for s in run.samples_u])
    assert np.max(np.abs(r.y / y0 - eta)) < 1e-8
    weight = p.mass * p.g
    states = zip(r.t, r.y, r.ydot, strict=True)
    n_ref = np.array([ref.normal_force(t, y, yd) for t, y, yd in states])
    assert np.max(np.abs(r.N - n_ref)) < 1e-7 * weight
    mean_n = simpson(r.N, x=r.t) / duration
    closed = weight - p.mass * (r.ydot[-1] - r.ydot[0]) / duration
    assert abs(mean_n - closed) < 1e-8 * weight
    # decayed: the last values sit at the static equilibrium, N = m g
    decay = math.exp(-0.2 * 2.0 * math.pi * 20.0)
    assert abs(r.N[-1] / weight - 1.0) < 10.0 * decay * amplitude / y0 * p.m2 + 1e-9
