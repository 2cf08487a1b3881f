"""The machine a benchmark ran on, as its outputs record it."""
import os
from pathlib import Path


def cpu():
    """The CPU's model name and its widest vector instructions, e.g.
    'AMD EPYC (AVX-512)'."""
    info = Path("/proc/cpuinfo").read_text() if Path("/proc/cpuinfo").exists() else ""
    model = next((x.split(":", 1)[1].strip() for x in info.splitlines() if x.startswith("model name")), "unknown")
    flags = next((x.split(":", 1)[1].split() for x in info.splitlines() if x.startswith("flags")), [])
    width = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else "no AVX2"
    return f"{model} ({width})"


def machine():
    """cpu() and the number of cores, as columns of a benchmark's table."""
    return dict(cpu=cpu(), cores=os.cpu_count())
