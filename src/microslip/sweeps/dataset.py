"""The xarray form of a sweep result, with units on every variable and coordinate."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import xarray as xr
from xarray.indexes import PandasIndex

import microslip
from microslip.metadata import cf_static_attributes
from microslip.sweeps.spec import SweepSpec


def _variable(dims, values, attrs: dict) -> xr.Variable:
    """An xarray Variable of a NumPy array, built on xarray's fast path: the normal
    path probes for a Dask array, and that probe imports dask.array (~0.35 s, a third
    of the warm import-to-first-result time, benchmarks/README.md) though the values
    here are always plain NumPy arrays."""
    return xr.Variable(dims, np.asarray(values), attrs, fastpath=True)


def _indexed(coords: dict[str, xr.Variable]) -> xr.Coordinates:
    """``coords`` (one dimension coordinate each) with their indexes built here: left to
    xarray, the default index goes through the same Dask probe, which imports dask
    (74 ms of the first sweep Dataset of a process, measured)."""
    indexes = {
        name: PandasIndex(pd.Index(var.values, name=name), name) for name, var in coords.items()
    }
    variables = {}
    for name, index in indexes.items():
        variables.update(index.create_variables({name: coords[name]}))
    return xr.Coordinates(variables, indexes=indexes)


def sweep_dataset(spec: SweepSpec, values: np.ndarray) -> xr.Dataset:
    """Dataset with ``mean_velocity`` [m/s] and, for the free vibration, the no-sliding
    boundary ``motion_threshold`` [N]. A forced model's result has no amplitude axis."""
    coords = {
        name: _variable(name, vals, {"units": spec.base.unit(name), "long_name": name})
        for name, vals in spec.param_axes
    }
    coords["force"] = _variable(
        "force", spec.forces, {"units": "N", "long_name": "tangential force F"}
    )
    long_name = (
        "long-time mean sliding velocity (exact steady state)"
        if spec.method == "steady"
        else f"mean sliding velocity x(T)/T over T = {spec.duration!r} s (RK4)"
    )
    attrs = {
        **cf_static_attributes("microslip mean sliding velocity sweep"),
        "method": spec.method,
        "sweep_definition": json.dumps(spec.definition(), sort_keys=True),
        "microslip_version": microslip.__version__,
        **spec.base.to_attrs(),
    }
    if spec.forced:
        velocity = _variable(
            spec.result_dims, values[..., 0], {"units": "m s-1", "long_name": long_name}
        )
        return xr.Dataset({"mean_velocity": velocity}, coords=_indexed(coords), attrs=attrs)
    coords["amplitude"] = _variable(
        "amplitude",
        spec.amplitudes,
        {"units": "m", "long_name": "normal vibration amplitude A = y0 - y_min"},
    )
    velocity = _variable(spec.dims, values, {"units": "m s-1", "long_name": long_name})
    threshold_dims = (*(name for name, _ in spec.param_axes), "amplitude")
    threshold = np.empty([len(v) for _, v in spec.param_axes] + [len(spec.amplitudes)])
    for index in np.ndindex(*threshold.shape[:-1]):
        params = spec.params_at((*index, 0))
        threshold[index] = [params.motion_threshold(a) for a in spec.amplitudes]
    ds = xr.Dataset(
        {
            "mean_velocity": velocity,
            "motion_threshold": _variable(
                threshold_dims,
                threshold,
                {"units": "N", "long_name": "no-sliding boundary mu S c_n max(y0 - A, 0)^m2"},
            ),
        },
        coords=_indexed(coords),
        attrs=attrs,
    )
    return ds
