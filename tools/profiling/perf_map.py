"""Name numba's compiled code for ``perf``: write a perf map of every compiled function.

``perf record`` samples compiled kernels as anonymous ``[JIT]`` addresses; perf reads
their names from ``/tmp/perf-<pid>.map`` ("start size name" per line, hex). numba's own
``NUMBA_ENABLE_PROFILING`` does not write one with the llvmlite builds this project
installs, and code loaded from the kernel cache would not be in it anyway. Call
:func:`write_perf_map` at the end of the profiled script, after the kernels ran:

    perf record -e cpu-clock -F 2000 -o perf.data .venv/bin/python script.py
    perf report -i perf.data --no-children --sort sym

``cpu-clock`` is a software event: it works where the hardware counters are not exposed
(virtual machines). The size of each entry is the distance to the next function, so a
sample in padding is charged to the function before it.
"""

from __future__ import annotations

import gc
import os
from pathlib import Path


def compiled_functions() -> dict[int, str]:
    """{address: symbol} of every function defined by a compiled numba overload in this
    process (compiled here or loaded from the cache)."""
    from numba.core.registry import CPUDispatcher

    found: dict[int, str] = {}
    for dispatcher in _instances(CPUDispatcher):
        for result in dispatcher.overloads.values():
            library = result.library
            engine = library._codegen._engine
            # Compiled here: the final module; loaded from the cache: the shared bitcode.
            modules = [getattr(library, name, None) for name in ("_final_module", "_shared_module")]
            for module in (m for m in modules if m is not None):
                for function in module.functions:
                    if function.is_declaration:
                        continue
                    address = engine.get_function_address(function.name)
                    if address:
                        found[address] = function.name
    return found


def _instances(cls: type) -> list:
    """The objects the garbage collector tracks that are instances of ``cls``. A weak
    proxy whose object is gone raises ReferenceError when asked its class: skipped."""
    found = []
    for obj in gc.get_objects():
        try:
            if isinstance(obj, cls):
                found.append(obj)
        except ReferenceError:
            continue
    return found


def write_perf_map(path: str | os.PathLike | None = None) -> Path:
    """Write the perf map (default ``/tmp/perf-<pid>.map``); returns its path."""
    target = Path(path) if path is not None else Path(f"/tmp/perf-{os.getpid()}.map")
    functions = compiled_functions()
    starts = sorted(functions)
    with open(target, "w") as out:
        for start, end in zip(starts, [*starts[1:], None], strict=True):
            size = (end - start) if end is not None else 4096
            out.write(f"{start:x} {min(size, 1 << 20):x} {functions[start]}\n")
    return target


if __name__ == "__main__":
    raise SystemExit("import write_perf_map and call it at the end of the profiled script")
