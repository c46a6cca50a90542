"""Time sweeps of a compliant tangential contact: what the spec accepts and refuses, and
its work estimate, whose step count per parameter set must follow the shortest period
the step resolves (T0, the excitation, the body's oscillation on k_t) as
:func:`microslip.budget.shortest_period` gives it for each set's model."""

from __future__ import annotations

import math

import numpy as np
import pytest

import microslip as ms
from microslip.budget import shortest_period
from microslip.sweeps import SweepSpec, sweep
from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD

P = ms.Parameters()
K_N = P.contact_stiffness
DURATION = 0.01


def _steps_by_set(spec: SweepSpec) -> float:
    """Σ over the parameter sets of the grid steps at 1/200 of each set's own period,
    from the scalar shortest_period of each set's model (an independent loop)."""
    total = 0.0
    shape = [len(values) for _, values in spec.param_axes]
    for index in np.ndindex(*shape):
        period = shortest_period(spec.model_at((*index, 0)))
        total += math.ceil(DURATION * DEFAULT_RK4_STEPS_PER_PERIOD / period)
    return total


@pytest.mark.parametrize(
    ("model", "axes", "amplitudes"),
    [
        # tangential period shorter than T0 for some stiffnesses and masses, not others
        (ms.Model(P, tangential=ms.TangentialSpring(K_N)),
         {"tangential.stiffness": [0.1 * K_N, 4.0 * K_N, 900.0 * K_N], "mass": [0.5, 3.0]},
         [1e-7, 2e-7]),
        (ms.Model(P, tangential=ms.MindlinSpring(0.8235)),
         {"tangential.ratio": [0.01, 1.0, 9.0], "m2": [1.5, 2.0]}, [1e-7]),
        # the excitation period, swept above and below f0, against a stiff spring
        (ms.Model(P, tangential=ms.TangentialSpring(2.0 * K_N), damping=ms.Viscous(0.05),
                  excitation=ms.HarmonicForce(2.0, 1000.0)),
         {"excitation.frequency": [500.0, 1500.0, 6000.0]}, None),
    ],
)  # fmt: skip
def test_work_counts_the_steps_of_each_sets_shortest_period(model, axes, amplitudes):
    forces = [0.2, 0.5, 0.8]
    spec = SweepSpec.build(model, axes, forces, amplitudes, method="time", duration=DURATION)
    n_points = len(forces) * (1 if amplitudes is None else len(amplitudes))
    assert spec.estimate().work == pytest.approx(n_points * _steps_by_set(spec), rel=1e-12)


def test_a_stiff_spring_grid_is_refused_by_the_time_budget():
    """k_t = 1e6 K_n: a period 1000 times shorter than T0, so 1000 times the steps; a
    grid of 3.9e12 trajectory-steps (estimated at ~9 h on 2 threads, still over the
    limit on 32) is refused before computing, the estimate naming its run time."""
    model = ms.Model(P, tangential=ms.TangentialSpring(1e6 * K_N))
    with pytest.raises(ms.WorkLimitError, match="trajectory-steps"):
        sweep(model, None, force=np.linspace(0.1, 0.9, 512),
              amplitude=np.linspace(0, 2e-7, 512), method="time", duration=0.05)  # fmt: skip


def test_steady_refuses_a_compliant_contact_and_names_the_time_method():
    model = ms.Model(P, tangential=ms.TangentialSpring(K_N))
    with pytest.raises(ms.UnsupportedModelError, match="method='time' also takes a compliant"):
        sweep(model, None, force=[0.5], amplitude=[1e-7])


@pytest.mark.parametrize(
    ("tangential", "part"),
    [(None, ms.Stribeck(0.15, 0.1, velocity=1e-3)),
     (ms.TangentialSpring(K_N), ms.SpringDrive(stiffness=1e6, velocity=1e-3))],
    ids=["friction", "drive"],
)  # fmt: skip
def test_time_keeps_refusing_other_friction_laws_and_drives(tangential, part):
    """StaticKinetic friction runs (tests/unit/test_sweep_static_kinetic.py); Stribeck
    (velocity-dependent μ: no closed form on a piece) and drives other than the sweep's
    constant forces are refused."""
    model = ms.Model(P, tangential=tangential, **{part.slot: part})
    with pytest.raises(ms.UnsupportedModelError, match=f"{part.slot}={type(part).__name__}"):
        sweep(model, None, force=[0.5], amplitude=[1e-7], method="time", duration=DURATION)


def test_a_user_step_is_checked_against_the_tangential_period():
    model = ms.Model(P, tangential=ms.TangentialSpring(400.0 * K_N))  # period T0/20
    with pytest.raises(ValueError, match=r"dt=.* is too large"):
        sweep(model, None, force=[0.5], amplitude=[1e-7], method="time", duration=DURATION,
              dt=P.natural_period / 50)  # fmt: skip


def test_a_spring_time_sweep_is_the_same_bits_however_it_is_chunked():
    """The spring-lane kernel runs each amplitude (or forced set-up) as its own normal
    tape, so a sweep cut into one chunk per amplitude, or per parameter set, gives the
    same bits as one chunk."""
    free = ms.Model(P, tangential=ms.TangentialSpring(K_N))
    kwargs = dict(force=[0.2, 0.6, 0.9], method="time", duration=0.002)
    one = sweep(free, None, amplitude=[0.5e-7, 1.5e-7, 3e-7], **kwargs)
    cut = sweep(free, None, amplitude=[0.5e-7, 1.5e-7, 3e-7], amplitude_chunk=1, **kwargs)
    np.testing.assert_array_equal(np.asarray(one.values), np.asarray(cut.values))
    assert np.all(np.asarray(one.values) > 0.0)
    forced = ms.Model(P, tangential=ms.TangentialSpring(K_N), damping=ms.Viscous(0.05),
                      excitation=ms.HarmonicForce(3.0, 1200.0))  # fmt: skip
    axes = {"excitation.amplitude": [2.0, 4.0, 6.0]}
    together = sweep(forced, axes, **kwargs)
    alone = [sweep(forced.replace(**{"excitation.amplitude": a}), None, **kwargs) for a in axes[
        "excitation.amplitude"]]  # fmt: skip
    for k, single in enumerate(alone):
        np.testing.assert_array_equal(
            np.asarray(together.values)[k], np.asarray(single.values).ravel()
        )


def test_mindlin_set_ups_with_a_flight_at_a_rough_exponent_cross_it_by_windows():
    """m2 = 1.5 (k_t ∝ δ^0.5, rough at touchdown) with a flight every period: the Mindlin
    lanes cross each lift-off and touchdown on the scalar RK4 step
    (integrators/mindlin_windows.py) and agree with the event method (rtol 1e-12) as
    closely as simulate(method="rk4") at the sweep's step does (9.6e-7 of the largest
    velocity; the lanes 7.0e-7); m2 = 2 in the same sweep runs on the Mindlin lanes, as
    it does alone."""
    from microslip.sweeps.kernel_choice import rough_exponents, time_kernel

    model = ms.Model(ms.Parameters(m2=1.5), tangential=ms.MindlinSpring(0.8235))
    assert time_kernel(model) == "mindlin" and rough_exponents(model)
    assert not rough_exponents(model.replace(m2=2.0))
    y0 = model.params.static_deflection
    forces, amplitude = [0.2, 0.6], 1.4 * y0
    result = sweep(model, None, force=forces, amplitude=[amplitude], method="time",
                   duration=0.003)  # fmt: skip
    events = np.array(
        [ms.simulate(model, force=f, amplitude=amplitude, duration=0.003, rtol=1e-12).x[-1]
         for f in forces]
    ) / 0.003  # fmt: skip
    error = np.abs(np.asarray(result.values)[:, 0] - events).max()
    assert np.all(np.abs(events) > 0) and error <= 2e-6 * np.abs(events).max()
    forced = ms.Model(
        ms.Parameters(m2=2.0), tangential=ms.MindlinSpring(0.8235),
        damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(4.0, 1200.0),
    )  # fmt: skip
    both = sweep(forced, {"m2": [1.5, 2.0]}, force=forces, method="time", duration=0.003)
    alone = sweep(forced, None, force=forces, method="time", duration=0.003)
    np.testing.assert_array_equal(np.asarray(both.values)[1], np.asarray(alone.values))


def test_mindlin_touchdown_tie_runs_on_the_scalar_step():
    """λ = 1 and F = μ m g, from rest in flight: the lanes land with |ẋ| = μ R exactly (in
    free fall ẋ = F t/m, R = g t/λ), where stick and slip coincide and the lane law's
    search stalls (docs/theory/numerics.md). The lanes take that lane through the piece
    on the scalar RK4 step instead (mindlin_windows.step_lane); without it
    (``windowed=False``, as on the GPU) it is handed back alone, NaN, and the other lane
    of its set-up keeps the bits of a run of it alone. All agree with the event method to
    1e-6 of the largest velocity."""
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.normal_tape import normal_coefficients
    from microslip.integrators.shared_lanes import LaneStalledError
    from microslip.simulation import initial_state_from_amplitude

    model = ms.Model(P, tangential=ms.MindlinSpring(1.0))
    y0, mg = P.static_deflection, P.mass * P.g
    forces, amplitudes, duration = [0.5 * P.mu * mg, P.mu * mg], [3.0 * y0, 0.5 * y0], 0.005
    c = normal_coefficients(model.pack(0.0))
    normal0 = np.array([initial_state_from_amplitude(P, amplitudes[0])[:2]])
    dt = shortest_period(model) / DEFAULT_RK4_STEPS_PER_PERIOD
    args = (c[None], normal0, [1.0], [0, 0], forces, P.mu, P.mu, duration, dt)
    with pytest.raises(LaneStalledError) as stalled:
        run_mindlin_lanes(*args, windowed=False)
    assert list(stalled.value.setups) == [] and list(stalled.value.lanes) == [1]
    x = stalled.value.partial[0]
    assert np.isnan(x[1])
    alone = run_mindlin_lanes(c[None], normal0, [1.0], [0], [forces[0]], P.mu, P.mu, duration,
                              dt)[0]  # fmt: skip
    assert x[0] == alone[0]
    windowed = run_mindlin_lanes(*args)
    assert windowed[0][0] == alone[0] and np.isfinite(windowed[0][1])
    result = np.asarray(
        sweep(model, None, force=forces, amplitude=amplitudes, method="time",
              duration=duration).values
    )  # fmt: skip
    events = np.array(
        [
            [ms.simulate(model, force=f, amplitude=a, duration=duration, rtol=1e-12).x[-1]
             for a in amplitudes]
            for f in forces
        ]
    ) / duration  # fmt: skip
    assert np.all(np.abs(events) > 0)
    assert np.abs(result - events).max() <= 1e-6 * np.abs(events).max()


def test_the_estimate_counts_rough_set_ups_that_may_leave_contact_on_the_batched_kernel():
    """A rough-exponent Mindlin sweep (m2 = 1.5): set-ups of a free vibration from rest
    at A < y0 stay in contact and run on the lanes; those at A >= y0, every forced one
    and every one of an m2 axis may be handed back and are estimated on the batched
    kernel (~100 times dearer per trajectory-step)."""
    from microslip.sweeps.kernel_choice import estimate_work, rough_setups

    hertz = ms.Parameters(m2=1.5)
    y0 = hertz.static_deflection
    model = ms.Model(hertz, tangential=ms.MindlinSpring(0.8235))
    assert rough_setups(model, (), [0.5 * y0, 0.9 * y0]) == 0.0
    assert rough_setups(model, (), [0.5 * y0, 1.0 * y0, 1.3 * y0, 0.2 * y0]) == 0.5
    assert rough_setups(model, (), None) == 1.0
    assert rough_setups(model.replace(m2=2.0), (), [1.3 * y0]) == 0.0
    assert rough_setups(ms.Model(hertz, tangential=ms.TangentialSpring(1e8)), (), [2 * y0]) == 0
    forced = model.replace(excitation=ms.HarmonicForce(2.0, 1200.0))
    assert rough_setups(forced, (), None) == 1.0
    assert rough_setups(model.replace(m2=2.0), (("m2", (1.5, 2.0)),), [0.5 * y0]) == 1.0
    forces = np.linspace(0.1, 0.9, 64)

    def seconds(amplitudes):
        n = len(amplitudes)
        work = estimate_work(model, (), forces.size, n, "time", 0.01, None, n, forces=forces,
                             amplitudes=amplitudes)  # fmt: skip
        return work.seconds

    in_contact = seconds(np.array([0.2, 0.4, 0.6, 0.8]) * y0)
    with_flights = seconds(np.array([0.2, 0.4, 1.2, 1.6]) * y0)
    assert with_flights > 10.0 * in_contact


def test_the_batched_estimate_counts_whole_blocks_a_round_of_threads_at_a_time(monkeypatch):
    """The batched kernel runs a chunk's handed-back lanes in blocks of block_for lanes
    (a multiple of 8, at most 64, one per thread where the run is small), the last one
    padded (its copies cost as much as lanes), a block per thread at a time: on two
    threads 1 lane costs a block of 8; 16 lanes two blocks of 8, one each; 128 lanes two
    blocks of 64; 129 lanes three blocks of 64, two rounds."""
    from microslip.integrators.batched import DEFAULT_BLOCK, block_for
    from microslip.sweeps import cost

    monkeypatch.setattr(cost, "batch_threads", lambda: 2)
    steps = 1000.0

    def per_thread(lanes):
        return cost.batched_lane_steps(lanes * steps, run_lanes=lanes)

    assert DEFAULT_BLOCK == 64
    assert [block_for(n, 2) for n in (1, 16, 17, 64, 128, 129, 4096)] == [8, 8, 16, 32, 64,
                                                                           64, 64]  # fmt: skip
    assert block_for(16, 1) == 16 and block_for(100, 1) == 64
    assert per_thread(1) == per_thread(16) == 8 * steps
    assert per_thread(128) == 64 * steps
    assert per_thread(129) == per_thread(256) == 2 * 64 * steps
    assert cost.batched_lane_steps(256 * steps) == 128 * steps  # runs not known: even


@pytest.mark.parametrize("amplitude", [4.0, 10.0, 40.0])
def test_leaves_contact_agrees_with_the_event_method(amplitude):
    """The probe of a forced normal motion (its tape, integrated as the Mindlin lanes
    would) leaves contact exactly where the event method, a separate integration,
    reports a loss of contact within the run."""
    from microslip.integrators.normal_tape import leaves_contact, normal_coefficients
    from microslip.model.system import EVENT_NAMES

    model = ms.Model(ms.Parameters(m2=1.5), damping=ms.Viscous(0.05),
                     excitation=ms.HarmonicForce(amplitude, 1200.0))  # fmt: skip
    y0 = model.params.static_deflection
    dt = shortest_period(model) / DEFAULT_RK4_STEPS_PER_PERIOD
    probe = leaves_contact(normal_coefficients(model.pack(0.0)), y0, 0.0, 0.01, dt)
    event = ms.simulate(model, force=0.1, duration=0.01)
    lost = EVENT_NAMES.index("contact_lost") in set(event.event_kind.tolist())
    assert probe == lost
    assert lost == (amplitude > 4.0)  # both cases are met


def test_a_forced_hertz_sweep_over_the_limit_is_estimated_on_the_set_ups_that_fly(
    monkeypatch,
):
    """The bound counts every forced set-up of a rough exponent on the batched kernel.
    Over the time limit, estimate_work integrates each set-up's normal motion instead:
    excitation amplitudes that keep the contact are estimated on the lanes alone (what
    the bound would refuse runs), those with flights on the batched kernel too."""
    from microslip import budget
    from microslip.sweeps import kernel_choice

    model = ms.Model(
        ms.Parameters(m2=1.5), tangential=ms.MindlinSpring(0.8235),
        damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(4.0, 1200.0),
    )  # fmt: skip
    forces = np.linspace(0.1, 0.9, 16)

    def seconds(amplitudes):
        axes = (("excitation.amplitude", tuple(amplitudes)),)
        return kernel_choice.estimate_work(model, axes, forces.size, 1, "time", 0.01, None, 1,
                                           forces, [math.nan]).seconds  # fmt: skip

    in_contact, flying = [1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 30.0, 40.0]
    bound_in_contact, bound_flying = seconds(in_contact), seconds(flying)
    assert bound_in_contact == bound_flying  # under the limit: the bound, every one flies
    monkeypatch.setattr(budget, "TIME_LIMIT_S", 0.5 * bound_in_contact)
    monkeypatch.setattr(kernel_choice, "PROBE_SHARE", 0.0)  # no time to look: the bound
    assert seconds(in_contact) == bound_in_contact
    monkeypatch.setattr(kernel_choice, "PROBE_SHARE", 1.0)
    kernel_choice._flying_setups.cache_clear()
    assert kernel_choice.flying_setups(model, (("excitation.amplitude", flying),), [math.nan],
                                       0.01, None) == 0.5  # fmt: skip
    lanes_alone = seconds(in_contact)
    assert lanes_alone < budget.TIME_LIMIT_S < bound_in_contact  # accepted, not refused
    assert lanes_alone < seconds(flying) < bound_flying


def test_lanes_the_gpu_hands_back_get_the_bits_of_the_cpu_run():
    """What the GPU lanes hand back (a Hertz set-up's flights, a lane on a tie) the sweep
    runs on the CPU lanes, lanes picked out of the run (mindlin_run._cpu_mindlin_lanes): each
    must get the bits it has in a CPU run of the whole (a lane depends on nothing else),
    whatever set-ups and forces it is picked with; a wrong set-up or force mapping
    changes them."""
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.normal_tape import normal_coefficients
    from microslip.simulation import initial_state_from_amplitude
    from microslip.sweeps.mindlin_run import _cpu_mindlin_lanes

    hertz = ms.Parameters(m2=1.5)
    model = ms.Model(hertz, tangential=ms.MindlinSpring(0.8235))
    y0, mg = hertz.static_deflection, hertz.mass * hertz.g
    amplitudes = [0.5 * y0, 1.3 * y0, 2.0 * y0]
    coeffs = np.tile(normal_coefficients(model.pack(0.0)), (3, 1))
    normal0 = np.array([initial_state_from_amplitude(hertz, a)[:2] for a in amplitudes])
    periods = np.array([ms.free_period(hertz, a) for a in amplitudes])
    forces = np.array([0.2, 0.5, 0.9]) * hertz.mu * mg
    groups = np.repeat(np.arange(3), forces.size)
    lane_forces = np.tile(forces, 3)
    mu_s, mu_k = np.full(9, hertz.mu), np.full(9, 0.8 * hertz.mu)
    dt = shortest_period(model) / DEFAULT_RK4_STEPS_PER_PERIOD
    setup_args = (coeffs, normal0, np.full(3, 0.8235))
    whole = run_mindlin_lanes(*setup_args, groups, lane_forces, mu_s, mu_k, 0.002, dt,
                              periods=periods)[0]  # fmt: skip
    picked = np.array([4, 6, 8])  # set-ups 1, 2, 2 (not 0: run as 0, 1, 1); forces 1, 0, 2
    x, back = _cpu_mindlin_lanes(picked, groups, setup_args, periods, lane_forces, mu_s,
                                 mu_k, 0.002, dt)  # fmt: skip
    assert back.size == 0
    np.testing.assert_array_equal(x, whole[picked])
