"""Each normal law is compiled once per run, for the coefficient tuple.

Every path hands the laws the coefficients as a tuple (``model.coefficients.as_tuple``,
docs/design.md "Compile time"); a path that passes the coefficient array compiles every
law beneath it a second time, seconds of a cold start. The check runs the package's
paths in a fresh process on an empty kernel cache, where every law that is called is
compiled there (in the test session a kernel loaded from the cache compiles nothing
beneath it, and a test may call a law with an array on purpose).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

PROBE = """
import json, warnings
import numpy as np
import microslip as ms
from microslip.model import contact, damping, excitation, friction, normal, system

warnings.simplefilter("ignore")
p = ms.Parameters()
forced = ms.Model(p, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0))
# The steady map (orbit tables), the time map on a repeated and a stepped tape, the
# spring and Mindlin lanes, simulate and its samples, a periodic orbit (the flow), the
# effective friction.
ms.velocity_map(p, forces=[0.2, 0.6], amplitudes=[0.0, 1e-7])
ms.velocity_map(p, forces=[0.2, 0.6], amplitudes=[0.0, 1e-7], method="time", duration=4e-3)
ms.sweep(forced, {"excitation.amplitude": [1.0]}, force=[0.3], method="time", duration=1e-3)
for tangential in (ms.TangentialSpring(p.contact_stiffness), ms.MindlinSpring(0.8235)):
    model = ms.Model(p, tangential=tangential)
    ms.sweep(model, None, force=[0.3], amplitude=[0.0, 1e-7], method="time", duration=4e-3)
run = ms.simulate(forced, force=0.5, duration=1e-3)
run.N, run.friction_limit, run.drive_force
ms.forced_response(forced, frequencies=(1300.0, 1400.0), max_points=3)
# The effective friction on a free vibration (its orbit table) and on a prescribed
# penetration (the closed-form orbit), through the normal pieces.
drive = ms.PrescribedVelocity(1e-4)
free = ms.Model(p, tangential=ms.TangentialSpring(7e7), drive=drive)
ms.effective_friction_map(free, [1e-5, 1e-3], "amplitude", [1e-7])
punch = ms.Model(
    ms.Parameters(m2=1.0, c_n=1e8, area=1.0), tangential=ms.TangentialSpring(1e6), drive=drive,
    excitation=ms.PrescribedPenetration(mean=1e-7, amplitude=0.5e-7, frequency=1000.0),
)
ms.effective_friction(punch)
laws = {
    "elastic_force": contact.elastic_force,
    "elastic_stiffness": contact.elastic_stiffness,
    "damped_force": damping.damped_force,
    "damped_force_partials": damping.damped_force_partials,
    "applied_force": excitation.applied_force,
    "gap": normal.gap,
    "normal_force": normal.normal_force,
    "normal_acceleration": normal.normal_acceleration,
    "normal_force_rate": normal.normal_force_rate,
    "friction_limit": friction.friction_limit,
    "kinetic_coefficient": friction.kinetic_coefficient,
    "kinetic_coefficient_at_rest": friction.kinetic_coefficient_at_rest,
    "normal_acceleration_call": system.normal_acceleration_call,
}
print(json.dumps({
    name: [str(sig) for sig in law.signatures] for name, law in laws.items()
}))
"""


def test_every_law_is_compiled_for_the_coefficient_tuple_alone(tmp_path):
    env = {**os.environ, "MICROSLIP_CACHE_DIR": str(tmp_path / "cache")}
    done = subprocess.run(
        [sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, timeout=900
    )
    assert done.returncode == 0, done.stderr
    signatures = json.loads(done.stdout.splitlines()[-1])
    # The probe reached every law (an empty list would make the check below vacuous).
    assert all(signatures.values()), {name: s for name, s in signatures.items() if not s}
    arrays = {name: s for name, s in signatures.items() if any("array" in x.lower() for x in s)}
    assert arrays == {}, f"compiled for a coefficient array: {arrays}"
