"""A time map over 1e9 s (1.5e12 normal periods) is the exact steady map.

On a free vibration the lanes run on one period's tape, repeated, and a lane that
starts a period as it started the last one takes its remaining periods at once
(docs/theory/numerics.md, "Repeating lanes"). Over 1e9 s the start-up is ~1e-12 of the
run, so the mean velocity x(t)/t is the steady-state mean velocity of the exact
one-period map (docs/theory/steady_sliding.md), an independent computation: orbit
tables, no time stepping. The bound is the RK4 tape's error at T0/200 (the 1e-6 of
max v the time sweeps keep); measured 2.9e-8.

The run is in a child process with a deadline. A kernel that stepped through every
period once all its lanes are parked (it did: a set-up whose lanes all stuck went on
serving 1.5e12 empty periods) never returns, and compiled code cannot be interrupted
from within. The rest at A = 0 is periodic too (N = m g for ever): counted as
repeating, not at the full cost of 3e14 steps, which the work limit would refuse.
"""

import json
import subprocess
import sys

import numpy as np

import microslip as ms

FORCES = np.linspace(0.1, 0.95, 6)  # N, all below μ m g = 0.981 N
AMPLITUDES = np.linspace(0.0, 2.2e-7, 5)  # m, up to ~y0 (2.25e-7 m)
DURATION = 1e9  # s

CHILD = """
import json, sys
import numpy as np
import microslip as ms
forces, amplitudes, duration = json.loads(sys.argv[1])
v = ms.velocity_map(forces=forces, amplitudes=amplitudes, method="time", duration=duration)
print(json.dumps(np.asarray(v).tolist()))
"""


def test_a_billion_second_time_map_is_the_exact_steady_map():
    # Compile (or load) the kernels here first: the child's deadline is for the run.
    ms.velocity_map(forces=FORCES, amplitudes=AMPLITUDES, method="time", duration=0.01)
    payload = json.dumps([FORCES.tolist(), AMPLITUDES.tolist(), DURATION])
    done = subprocess.run(
        [sys.executable, "-c", CHILD, payload], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    long_run = np.array(json.loads(done.stdout))
    steady = np.asarray(ms.velocity_map(forces=FORCES, amplitudes=AMPLITUDES, method="steady"))
    assert np.max(steady) > 1e-4  # creep at the larger amplitudes
    assert np.all(long_run[:, 0] == 0.0)  # A = 0: held (eq. 4.1)
    np.testing.assert_array_equal(long_run == 0.0, steady == 0.0)
    assert np.max(np.abs(long_run - steady)) <= 1e-6 * np.max(steady)
