"""What this machine offers a job now: the memory available to it.

:mod:`microslip.budget` refuses a job whose estimated memory exceeds a fraction of it,
and the CLI bounds its in-memory outputs by it.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["available_memory"]


def _meminfo_available() -> float | None:
    try:
        text = Path("/proc/meminfo").read_text()
    except OSError:
        return None
    for line in text.splitlines():
        if line.startswith("MemAvailable:"):
            return float(line.split()[1]) * 1024.0
    return None


def _cgroup_available() -> float | None:
    """Room left under a cgroup v2 memory limit, if one is set."""
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        if limit == "max":
            return None
        used = Path("/sys/fs/cgroup/memory.current").read_text().strip()
        return max(float(limit) - float(used), 0.0)
    except (OSError, ValueError):
        return None


def available_memory() -> float:
    """Memory available to a new job now [bytes]: ``MemAvailable`` of ``/proc/meminfo``,
    else ``sysconf``'s available pages, else the total; also bounded by a cgroup (v2)
    memory limit where there is one."""
    available = _meminfo_available()
    if available is None:
        try:
            available = float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError, AttributeError):
            available = float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    cgroup = _cgroup_available()
    return min(available, cgroup) if cgroup is not None else available
