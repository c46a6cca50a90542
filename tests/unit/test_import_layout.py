"""Start-up layout: a light ``import microslip`` and a cache registered before any @njit."""

import ast
import subprocess
import sys
from pathlib import Path

import microslip

PACKAGE = Path(microslip.__file__).resolve().parent


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


def test_every_module_that_imports_numba_registers_the_cache_first():
    """A jitted module that skipped the registration would be cached by numba's per-file
    key again, and serve stale machine code after an edit of a module it inlines."""
    jitted = [p for p in PACKAGE.rglob("*.py") if any(n.startswith("numba") for n in _imports(p))]
    assert len(jitted) >= 10  # model, integrators, analysis
    for path in jitted:
        if path.name == "_jit_cache.py":
            continue
        assert "microslip._jit_cache" in _imports(path), f"{path} does not import _jit_cache"


def test_import_microslip_loads_no_numerics():
    """The CLI's Ctrl-C handler must be in place before numba/xarray/dask load (seconds)."""
    code = (
        "import sys, microslip, microslip.cli.main\n"
        "print(sorted(m for m in ('numba', 'xarray', 'dask', 'scipy') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_public_names_resolve_lazily():
    for name in microslip.__all__:
        assert getattr(microslip, name) is not None
    assert microslip.Parameters().natural_frequency > 0
    assert "simulate" in dir(microslip)


def test_sweep_dataset_does_not_import_dask():
    """xarray's duck-array probe imports dask.array (~0.35 s of the warm
    import-to-first-result, benchmarks/README.md) and its default index another probe
    that imports dask (~0.07 s); the sweep Dataset skips both (its variables on the fast
    path, its indexes built by itself). Dask stays out unless a scheduler is asked for."""
    code = (
        "import sys, numpy as np, microslip as ms\n"
        "from microslip.sweeps.spec import SweepSpec\n"
        "from microslip.sweeps.dataset import sweep_dataset\n"
        "spec = SweepSpec.build(ms.Parameters(), {'mu': [0.1, 0.2]}, [0.1, 0.5], [1e-7])\n"
        "ds = sweep_dataset(spec, np.zeros(spec.shape))\n"
        "assert list(ds.indexes) == ['mu', 'force', 'amplitude'], list(ds.indexes)\n"
        "assert ds.force.attrs['units'] == 'N'\n"
        "print('dask' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
