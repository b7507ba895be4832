"""What every benchmark records about the machine it ran on, so that timings from different machines are not compared
as if they were one (the same worst-case search took 14.0 s on one machine of this workplace and 18.9 s on another).
"""

from __future__ import annotations

import os
import platform

import numpy as np


def _cpu_model() -> str:
    """The CPU's model name from /proc/cpuinfo (Linux), else what :func:`platform.processor` gives."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def machine_info(**extra) -> dict:
    """Python and numpy versions, architecture, CPU model and count, BLAS threads asked for, plus ``extra`` items."""
    return {"python": platform.python_version(), "numpy": np.__version__, "machine": platform.machine(), "cpu": _cpu_model(),
            "cpus": os.cpu_count(), "blas_threads": os.environ.get("OPENBLAS_NUM_THREADS", "default"), **extra}
