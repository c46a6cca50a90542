# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Tutorial: from `Parameters()` to a sweep on a Dask cluster
#
# This notebook walks through microslip in the order a study would: the contact's
# constants, its free normal vibration, one simulated run, the exact steady sliding
# velocity, a map of it, a forced and damped contact, and finally a parameter sweep
# computed on a local Dask cluster and written to NetCDF. Every quantity is SI.
#
# It is stored as a jupytext "percent" script (`docs/tutorial/tutorial.py`): open it in
# Jupyter with jupytext installed, or run it as a plain script
# (`python docs/tutorial/tutorial.py`). The documentation build executes it, and the
# test suite runs it and checks the numbers it computes
# (`tests/integration/test_tutorial.py`). The grids are small so that it runs in seconds;
# the comments say what a real study would use.

# %%
# %matplotlib inline
from pathlib import Path

import numpy as np
import xarray as xr
from dask.distributed import LocalCluster

import microslip as ms
from microslip.plotting import sweep_figure, velocity_map_figure
from microslip.plotting.response import response_figure
from microslip.plotting.trajectory import trajectory_figure

# %% [markdown]
# ## 1. The contact: `Parameters`
#
# `Parameters()` holds the paper's data (Sec. 3): a 1 kg slider on an interface with
# reaction $N = S c_n y^{m_2}$ (eq. 2.3), $m_2 = 2$, and Coulomb friction $\mu = 0.1$
# (eq. 2.2). The working point follows from them
# ([the paper's model](../theory/paper_model.md)).

# %%
p = ms.Parameters()
print(p)
print(f"static deflection y0 = {p.static_deflection:.5g} m (paper: 2.25e-7 m)")
print(f"contact stiffness K_n = {p.contact_stiffness:.5g} N/m")
print(f"natural frequency f0 = {p.natural_frequency:.5g} Hz (paper: 1485 Hz)")
print(f"nominal static friction mu m g = {p.static_friction_force:.5g} N")

# %% [markdown]
# Any field can be changed with keywords, and every value is checked: a value outside
# its documented range is refused with one line naming the field.

# %%
p_rough = ms.Parameters(mu=0.12, m2=1.5)
try:
    ms.Parameters(mu=-0.1)
except ValueError as error:
    print("refused:", error)

# %% [markdown]
# ## 2. Free normal vibration
#
# Started at rest at the highest point $y = y_0 - A$, the slider vibrates in the normal
# direction with a period given exactly by the energy integral
# ([free vibration](../theory/free_vibration.md)). The frequency falls with the
# amplitude; for small $a = A/y_0$ the Lindstedt–Poincaré estimate is
# $f/f_0 \approx 1 - (m_2 - 1)(2 m_2 + 1) a^2/48$.

# %%
y0 = p.static_deflection
for a in (0.05, 1 / 3, 2 / 3, 1.0):
    f = ms.free_frequency(p, amplitude=a * y0)
    estimate = 1 - (p.m2 - 1) * (2 * p.m2 + 1) * a**2 / 48
    print(
        f"A = {a:.3f} y0: f/f0 = {f / p.natural_frequency:.6f}  (small-a estimate {estimate:.6f})"
    )
backbone_small = ms.free_frequency(p, amplitude=0.05 * y0) / p.natural_frequency

# %% [markdown]
# ## 3. One simulation
#
# `simulate` integrates eqs. (2.4)–(2.5) under a constant tangential force F with every
# switching instant (stick → slip, slip → stick, loss and return of contact) located.
# Here F = 0.5 N, about half of $\mu m g$, and $A = 2 y_0/3$: the slider creeps forward in
# stick–slip (Fig. 4 of the paper).

# %%
amplitude = 2 * y0 / 3
run = ms.simulate(p, force=0.5, amplitude=amplitude, duration=0.02)
print(f"{run.t.size} samples, {run.event_t.size} switching events")
print(f"x after 20 ms: {run.x[-1]:.4g} m; state codes: {np.unique(run.state)} (0 stick, 1 slip)")

trajectory_figure(run)

# %% [markdown]
# The result converts to an `xarray.Dataset` with a unit on every variable, ready to be
# written to NetCDF.

# %%
run_ds = run.to_xarray()
print({name: run_ds[name].attrs.get("units") for name in ("y", "x", "xdot", "R", "Ft")})

# %% [markdown]
# ## 4. The exact steady state
#
# The normal motion does not depend on the sliding, and the friction impulse follows
# from the normal velocity alone, so the long-time mean velocity is computed from one
# period of the normal vibration ([steady sliding](../theory/steady_sliding.md)) instead
# of a long simulation. The time average of a long simulation tends to it.

# %%
v_exact = ms.mean_velocity(p, force=0.5, amplitude=amplitude)
cycle = ms.stick_slip_cycle(p, force=0.5, amplitude=amplitude)
print(f"exact mean velocity v = {v_exact:.6e} m/s")
print(
    f"cycle: period {cycle.period:.4e} s, slip {cycle.slip_time:.3e} s, "
    f"stick {cycle.stick_time:.3e} s, slip distance {cycle.slip_distance:.3e} m"
)

long = ms.simulate(p, force=0.5, amplitude=amplitude, duration=400 * cycle.period)
# mean over whole periods after the first stop (the first slide starts at a phase of its own)
start = np.searchsorted(long.t, 10 * cycle.period)
v_time = (long.x[-1] - long.x[start]) / (long.t[-1] - long.t[start])
print(f"time average over 390 periods: {v_time:.6e} m/s")

# %% [markdown]
# Below the motion threshold $F = \mu S c_n \max(y_0 - A, 0)^{m_2}$ (eq. 4.2) the slider
# never moves and the mean velocity is exactly 0.

# %%
threshold = p.motion_threshold(amplitude)
print(f"threshold at A = 2y0/3: {threshold:.5g} N")
print("v just below:", ms.mean_velocity(p, force=0.999 * threshold, amplitude=amplitude))

# %% [markdown]
# ## 5. A map of the mean velocity (Fig. 7)
#
# `velocity_map` evaluates the exact steady state on a grid of forces and amplitudes;
# a 256 × 256 map takes well under a second. This one is coarser.

# %%
forces = np.linspace(0.05, 0.95, 46)  # a real map: 256 values or more (still < 1 s)
amplitudes = np.linspace(0.0, 3e-7, 41)
vmap = ms.velocity_map(p, forces=forces, amplitudes=amplitudes)
print(vmap.dims, vmap.shape, vmap.attrs.get("units"))

velocity_map_figure(vmap.to_dataset(), p)

# %% [markdown]
# ## 6. Past the paper: a damped, forced contact
#
# A `Model` composes the paper's contact with optional parts
# ([extensions](../theory/extensions.md)). Here Kelvin–Voigt damping with ratio
# ζ = 0.03 and a harmonic normal force of 0.5 N at 1400 Hz. The normal motion settles
# on a periodic orbit, found by shooting; its Floquet multipliers say whether it is
# stable ([periodic orbits](../theory/periodic_orbits.md)).

# %%
m = ms.Model(
    p, damping=ms.Viscous(ratio=0.03), excitation=ms.HarmonicForce(amplitude=0.5, frequency=1400.0)
)
orbit = ms.periodic_orbit(m)
print(
    f"period {orbit.period:.4e} s, amplitude {orbit.amplitude:.4e} m, "
    f"|multipliers| {np.abs(orbit.multipliers).round(4)}, stable: {orbit.stable}"
)
v_forced = ms.mean_velocity(m, force=0.8)
print(
    f"mean velocity at F = 0.8 N: {v_forced:.4e} m/s "
    f"(without vibration nothing moves below mu m g = {p.static_friction_force:.3f} N)"
)

# %% [markdown]
# The forced response follows the branch of periodic orbits in frequency by
# pseudo-arclength continuation. With a forcing of 1 N the resonance curve bends to lower
# frequencies (the contact softens with amplitude), folds twice and loses contact near
# its top: between the folds three orbits coexist, the middle one unstable.

# %%
strong = m.replace(**{"excitation.amplitude": 1.0})
response = ms.forced_response(strong, frequencies=(1100.0, 1600.0))
folds = [int(i) for i in np.atleast_1d(response.attrs["folds"])]
print(
    f"{response.sizes['point']} branch points; folds at "
    f"{[round(float(response.frequency[i]), 1) for i in folds]} Hz; "
    f"largest amplitude {float(response.amplitude.max()):.3e} m; "
    f"contact lost somewhere: {bool(response.contact_lost.any())}"
)

response_figure(response)

# %% [markdown]
# ## 7. A sweep on a Dask cluster
#
# `sweep` computes the mean velocity over any numeric fields of a model (by their dotted
# names), the force and the amplitude. In process it uses all cores; with
# `scheduler="tcp://host:port"` it sends its chunks to a Dask cluster, with the same
# result bit for bit. Here a `LocalCluster` of two single-threaded workers, listening on
# TCP like a real cluster, stands in for one; a `store` makes the sweep resumable
# ([resuming and scaling a sweep](../howto/resume_sweep.md)).
#
# The workers run as threads of this process (`processes=False`) so that the notebook
# also runs as a plain script: worker *processes* are started by re-importing the main
# script, which a script must then guard with `if __name__ == "__main__":`. On a real
# cluster the workers are separate processes started by `dask scheduler` and
# `dask worker`, and only the address changes.

# %%
axes = {"mu": [0.08, 0.1, 0.12], "m2": [1.5, 2.0]}
sweep_forces = np.linspace(0.05, 0.75, 15)  # below mu m g = 0.785 N for mu = 0.08
sweep_amplitudes = np.linspace(0.0, 3e-7, 16)  # a real sweep: hundreds, in chunks of ~16

in_process = ms.sweep(p, axes, force=sweep_forces, amplitude=sweep_amplitudes)

with LocalCluster(
    n_workers=2,
    threads_per_worker=1,
    processes=False,
    protocol="tcp",
    host="127.0.0.1",
    dashboard_address=None,
) as cluster:
    print("scheduler:", cluster.scheduler_address)
    on_cluster = ms.sweep(
        p,
        axes,
        force=sweep_forces,
        amplitude=sweep_amplitudes,
        scheduler=cluster.scheduler_address,
        store=Path("sweep.partial.zarr"),
        amplitude_chunk=8,
    )
print(on_cluster.dims, on_cluster.shape)
print("identical to the in-process sweep:", bool((on_cluster == in_process).all()))

# %% [markdown]
# The result is an `xarray.DataArray` with units on every coordinate; write it to
# NetCDF and read it back ([reading the output](../howto/read_netcdf.md)).

# %%
on_cluster.to_dataset(name="mean_velocity").to_netcdf("sweep.nc")
back = xr.open_dataset("sweep.nc")
print(back["mean_velocity"].attrs["units"], back["mu"].attrs.get("units"))
v_at = back["mean_velocity"].sel(mu=0.1, m2=2.0).sel(force=0.5, amplitude=2e-7, method="nearest")
print(f"v(mu = 0.1, m2 = 2, F = 0.5 N, A = {float(v_at.amplitude):.3g} m) = {float(v_at):.4e} m/s")
back.close()

sweep_figure(on_cluster, p)

# %% [markdown]
# ## Where next
#
# - the [gallery](../auto_examples/index.rst) reproduces each of the paper's figures;
# - the [theory pages](../theory/index.md) derive what the code computes;
# - the [how-to guides](../howto/index.md) cover choosing a method, scaling sweeps and
#   adding a law;
# - the [command line](../cli.rst) does all of the above without Python.
