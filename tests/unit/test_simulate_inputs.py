"""simulate(): input validation, output sampling and the xarray view."""

import math

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period
BASE = {"force": 0.5, "amplitude": Y0 / 2, "duration": 2e-3}


def run(**changes):
    return ms.simulate(P, **{**BASE, **changes})


@pytest.mark.parametrize(
    ("changes", "name", "value"),
    [
        ({"force": math.nan}, "force", "nan"),
        ({"force": math.inf}, "force", "inf"),
        ({"duration": -1e-3}, "duration", "-0.001"),
        ({"duration": 0.0}, "duration", "0.0"),
        ({"duration": math.nan}, "duration", "nan"),
        ({"amplitude": -1e-9}, "amplitude", "-1e-09"),
        ({"method": "euler"}, "method", "euler"),
        ({"method": "RK4"}, "method", "RK4"),
        ({"save_every": 0}, "save_every", "0"),
        ({"save_every": -2}, "save_every", "-2"),
        ({"save_every": 1.5}, "save_every", "1.5"),
        ({"save_every": True}, "save_every", "True"),
        ({"rtol": 0.0}, "rtol", "0.0"),
        ({"atol": -1.0}, "atol", "-1.0"),
    ],
)
def test_bad_scalars_name_the_field_and_value(changes, name, value):
    with pytest.raises(ValueError) as info:
        run(**changes)
    assert name in str(info.value)
    assert value in str(info.value)


def test_rk4_step_must_resolve_the_vibration():
    limit = T0 / 10
    run(method="rk4", dt=limit)  # the largest allowed step works
    with pytest.raises(ValueError, match="dt"):
        run(method="rk4", dt=limit * (1 + 1e-9))
    for bad in (0.0, -T0 / 100, math.nan):
        with pytest.raises(ValueError, match="dt"):
            run(method="rk4", dt=bad)


def test_dt_is_rejected_for_the_event_method():
    with pytest.raises(ValueError, match="dt"):
        run(method="event", dt=T0 / 100)


def test_exactly_one_of_amplitude_and_initial_state():
    with pytest.raises(ValueError, match="amplitude"):
        ms.simulate(P, force=0.5, duration=1e-3)
    with pytest.raises(ValueError, match="initial_state"):
        ms.simulate(P, force=0.5, duration=1e-3, amplitude=Y0, initial_state=(Y0, 0, 0, 0))


@pytest.mark.parametrize("state", [(Y0, 0.0, 0.0), (Y0, 0.0, 0.0, 0.0, 0.0), (Y0, math.nan, 0, 0)])
def test_bad_initial_state(state):
    with pytest.raises(ValueError, match="initial_state"):
        ms.simulate(P, force=0.5, duration=1e-3, initial_state=state)


def test_params_must_be_parameters():
    with pytest.raises(ValueError, match="params"):
        ms.simulate({"mass": 1.0}, force=0.5, amplitude=Y0, duration=1e-3)


@pytest.mark.parametrize(
    "t_eval",
    [
        [0.0, 1e-3, 5e-4],  # decreasing
        [-1e-6, 1e-3],  # before t = 0
        [0.0, 2e-3 * (1 + 1e-9)],  # past the duration
        [0.0, math.nan],
        [],
        [[0.0, 1e-3]],  # not one-dimensional
        ["a", "b"],
    ],
)
def test_bad_t_eval(t_eval):
    with pytest.raises(ValueError, match="t_eval"):
        run(t_eval=t_eval)


def test_initial_state_from_amplitude_is_rest_at_the_top():
    r = run(amplitude=0.4 * Y0)
    assert (r.t[0], r.y[0], r.ydot[0], r.x[0], r.xdot[0]) == (0.0, Y0 - 0.4 * Y0, 0.0, 0.0, 0.0)
    s = ms.simulate(P, force=0.5, duration=2e-3, initial_state=(Y0 - 0.4 * Y0, 0.0, 0.0, 0.0))
    np.testing.assert_array_equal(s.y, r.y)
    np.testing.assert_array_equal(s.x, r.x)


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize(
    "duration",
    [
        1e-7,  # shorter than one RK4 step
        37.3 * T0 / 200,
        200 * (T0 / 200) * (1 + 3e-12),  # a hair past a grid point
        200 * (T0 / 200) * (1 - 3e-12),
        0.0123456789,
    ],
)
def test_output_ends_exactly_at_the_duration(method, duration):
    dt = T0 / 200 if method == "rk4" else None
    for amplitude in (Y0 / 3, 1.3 * Y0):
        r = ms.simulate(P, force=0.5, amplitude=amplitude, duration=duration, method=method, dt=dt)
        assert r.t[0] == 0.0
        assert r.t[-1] == duration
        assert np.all(np.diff(r.t) > 0.0)


def test_rk4_samples_on_the_grid():
    dt = T0 / 200
    r = ms.simulate(P, force=0.5, amplitude=Y0 / 3, duration=0.005, method="rk4", dt=dt)
    grid = np.arange(int(0.005 / dt) + 1) * dt
    on_grid = np.isin(grid, r.t)
    assert on_grid.all()
    # Off-grid samples are switching instants (or the end).
    extra = np.setdiff1d(r.t, np.append(grid, 0.005))
    assert np.all(np.isin(extra, r.event_t))


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("every", [2, 3, 7])
def test_save_every_keeps_every_nth_boundary_and_the_end(method, every):
    kwargs = {"force": 0.5, "amplitude": 1.3 * Y0, "duration": 0.004, "method": method}
    full = ms.simulate(P, **kwargs)
    thin = ms.simulate(P, save_every=every, **kwargs)
    n = full.t.size - 1  # boundaries 1..n after the initial sample
    keep = [0, *range(every, n + 1, every)] + ([n] if n % every else [])
    np.testing.assert_array_equal(thin.t, full.t[keep])
    for name in ("y", "ydot", "x", "xdot", "direction"):
        np.testing.assert_array_equal(getattr(thin, name), getattr(full, name)[keep])
    # Switching instants are all recorded whatever is saved.
    np.testing.assert_array_equal(thin.event_t, full.event_t)
    assert thin.t[-1] == 0.004


@pytest.mark.parametrize("method", ["event", "rk4"])
def test_t_eval_returns_exactly_the_requested_times(method):
    t_eval = np.concatenate([[0.0, 0.0], np.sort(np.random.default_rng(1).uniform(0, 4e-3, 50))])
    t_eval = np.append(t_eval, [4e-3, 4e-3])
    r = ms.simulate(P, force=0.5, amplitude=1.3 * Y0, duration=4e-3, method=method, t_eval=t_eval)
    np.testing.assert_array_equal(r.t, t_eval)
    assert (r.y[0], r.ydot[0], r.x[0], r.xdot[0]) == (Y0 - 1.3 * Y0, 0.0, 0.0, 0.0)
    assert r.y[1] == r.y[0]
    assert r.x[-1] == r.x[-2]


def test_t_eval_on_the_rk4_grid_reproduces_the_step_output():
    dt = T0 / 200
    kwargs = {"force": 0.5, "amplitude": 1.3 * Y0, "duration": 37.3 * dt, "method": "rk4"}
    steps = ms.simulate(P, dt=dt, **kwargs)
    grid = np.arange(38) * dt
    sampled = ms.simulate(P, dt=dt, t_eval=grid, **kwargs)
    index = np.searchsorted(steps.t, grid)
    np.testing.assert_array_equal(steps.t[index], grid)
    for name in ("y", "ydot", "x", "xdot"):
        np.testing.assert_array_equal(getattr(sampled, name), getattr(steps, name)[index])


def test_t_eval_agrees_with_runs_ending_at_those_times():
    times = [1.1e-3, 2.345e-3, 3.9e-3]
    kwargs = {"force": 0.5, "amplitude": Y0, "rtol": 1e-12, "atol": 1e-14}
    r = ms.simulate(P, duration=4e-3, t_eval=times, **kwargs)
    for i, t in enumerate(times):
        end = ms.simulate(P, duration=t, **kwargs)
        assert r.y[i] == pytest.approx(end.y[-1], rel=0, abs=1e-11 * Y0)
        assert r.x[i] == pytest.approx(end.x[-1], rel=0, abs=1e-11 * Y0)


def test_to_xarray_has_units_everywhere():
    r = run(amplitude=1.3 * Y0)
    ds = r.to_xarray()
    names = [*ds.data_vars, *ds.coords]
    assert {"y", "ydot", "x", "xdot", "xddot", "R", "Ft", "friction_limit", "state"} <= set(names)
    assert "time" in ds.coords
    for name in names:
        assert "units" in ds[name].attrs, name
        assert isinstance(ds[name].attrs["units"], str) and ds[name].attrs["units"], name
    assert ds["time"].attrs["units"] == "s"
    assert ds["y"].attrs["units"] == "m"
    assert ds["R"].attrs["units"] == "N"
    np.testing.assert_array_equal(ds["time"].values, r.t)
    np.testing.assert_array_equal(ds["x"].values, r.x)
    np.testing.assert_array_equal(ds["event_time"].values, r.event_t)


def test_result_is_immutable():
    r = run()
    with pytest.raises(AttributeError):
        r.t = np.zeros(3)  # type: ignore[misc]


def test_force_and_amplitude_limits():
    with pytest.raises(ValueError, match=r"\|force\|=1e\+308 N exceeds"):
        run(force=-1e308)
    with pytest.raises(ValueError, match=r"amplitude=1.0 m exceeds the supported 1e3 y0"):
        run(amplitude=1.0)
    with pytest.raises(ValueError, match="allow_large"):
        run(allow_large="yes")
