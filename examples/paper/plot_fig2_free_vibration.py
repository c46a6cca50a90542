"""
Fig. 2: free normal micro-vibrations
====================================

**The paper's figure.** Fig. 2 of Grudziński & Kostek (2005) has four panels: (a) the
load–deflection characteristic of the interface, :math:`|R|` = S c_n y^m2 (eq. 2.3), with the
working point C at the static deflection; (b) y(t) and (c) ẏ(t) of the free (undamped)
normal vibration started at rest from y = 0, y0/3 and 2y0/3, i.e. amplitudes
A = y0, 2y0/3 and y0/3; (d) their phase portraits.

**What the paper states** (Sec. 3): y0 = δ0 = 2.25e-7 m; the small-vibration frequency
f0 = (1/2π) sqrt(K_n/m) with K_n = 2 sqrt(m g S c_n) is 1485 Hz; the vibrations are
asymmetric about the static position, and as the amplitude rises the asymmetry grows and
the frequency falls.

**Ours.** :func:`microslip.plotting.figure2` draws the same four panels from the exact
free vibration (:doc:`/theory/free_vibration`); the numbers it is drawn from are in the
returned :class:`xarray.Dataset`. Run time: about a second (three periods per amplitude).
"""

# %%
import microslip as ms
from microslip.plotting import figure2

p = ms.Parameters()  # the paper's data
fig, ds = figure2(p)

# %%
# The values the paper states, and ours
# -------------------------------------
#
# The working point and f0 of Sec. 3, then the frequency of each vibration: it falls as
# the amplitude grows (Fig. 2b, c). The frequency is exact (energy integral), not read
# off the time series.
print(f"y0 = {p.static_deflection:.4e} m          (paper: 2.25e-7 m)")
print(
    f"K_n = {p.contact_stiffness:.4e} N/m  (= 2 sqrt(m g S c_n) = "
    f"{2 * (p.mass * p.g * p.area * p.c_n) ** 0.5:.4e} N/m)"
)
print(f"f0 = {p.natural_frequency:.1f} Hz           (paper: 1485 Hz)")
for a, f in zip(ds["amplitude_ratio"].values, ds["frequency"].values, strict=True):
    print(f"A = {a:.3f} y0: f = {f:7.1f} Hz, f/f0 = {f / p.natural_frequency:.4f}")

# %%
# Asymmetry
# ---------
#
# The vibration reaches less far below the static position than above it: the contact
# stiffens with depth (:math:`|R|` grows as y^2), so the lowest point y_max lies less than A below
# y0, and the more so the larger the amplitude.
y0 = p.static_deflection
for a, lo, hi in zip(
    ds["amplitude_ratio"].values, ds["y_min"].values, ds["y_max"].values, strict=True
):
    print(
        f"A = {a:.3f} y0: above y0 by {(y0 - lo) / y0:.3f} y0, below y0 by {(hi - y0) / y0:.3f} y0"
    )
