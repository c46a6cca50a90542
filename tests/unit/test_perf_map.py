"""tools/profiling/perf_map.py names numba's compiled code for perf: a function compiled
here appears in the map at the address numba calls, and the entries are sorted,
non-overlapping "start size name" lines. A dead weak proxy among the collector's objects
(a full test run leaves some) does not stop it: asked its class, it raises."""

import importlib.util
import weakref
from pathlib import Path

import numba

ROOT = Path(__file__).resolve().parents[2]


def load():
    spec = importlib.util.spec_from_file_location(
        "perf_map", ROOT / "tools" / "profiling" / "perf_map.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_compiled_function_is_named_at_its_address(tmp_path):
    @numba.njit
    def perf_map_probe(x):
        return 2.0 * x + 1.0

    assert perf_map_probe(1.0) == 3.0

    class Gone:
        pass

    gone = Gone()
    proxy = weakref.proxy(gone)
    del gone
    assert proxy is not None  # kept alive, its object collected
    path = load().write_perf_map(tmp_path / "perf.map")
    entries = [line.split(" ", 2) for line in path.read_text().splitlines()]
    starts = [int(start, 16) for start, _, _ in entries]
    sizes = [int(size, 16) for _, size, _ in entries]
    assert starts == sorted(starts) and all(s > 0 for s in sizes)
    assert all(a + s <= b for a, s, b in zip(starts, sizes, starts[1:], strict=False))
    named = {name: int(start, 16) for start, _, name in entries}
    probe = [
        name
        for name in named
        if "perf_map_probe" in name and not name.startswith(("cpython", "cfunc"))
    ]
    assert probe, "the probe's compiled function is missing from the map"
    (signature,) = perf_map_probe.signatures
    address = perf_map_probe.overloads[signature].library.get_pointer_to_function(probe[0])
    assert named[probe[0]] == address
