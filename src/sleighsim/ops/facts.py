"""Facts a cost summary records about the run's setting: the git commit and the machine (the merged
config is :func:`sleighsim.ops.config.merged_config`)."""

from __future__ import annotations

import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path

from sleighsim.ops.config import REPO


def git_commit(repo=REPO) -> str:
    """HEAD of ``repo`` (a path), with "-dirty" when tracked files differ (read-only git commands);
    "unknown" when git cannot tell."""
    try:
        head = subprocess.run(["git", "-C", str(repo), "rev-parse", "HEAD"], capture_output=True, text=True,
                              timeout=20, check=True).stdout.strip()
        dirty = subprocess.run(["git", "--no-optional-locks", "-C", str(repo), "status", "--porcelain",
                                "--untracked-files=no"], capture_output=True, text=True, timeout=20,
                               check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("-dirty" if dirty else "")


def widest_vector(flags) -> str:
    """The widest vector extension among the CPU's ``flags`` (/proc/cpuinfo's): AVX-512, AVX2, AVX or "SSE or
    none". The double-double engine's blocks follow it (``engine.ddbatch.MAX_WIDTH``), so a job's time does too."""
    names = {"avx512f": "AVX-512", "avx2": "AVX2", "avx": "AVX"}
    return next((name for flag, name in names.items() if flag in set(flags)), "SSE or none")


def machine_facts() -> dict:
    """Cores usable here, CPU model, its widest vector extension, memory (GB), platform, Python and Snakemake
    versions, as a dict."""
    model, flags, mem_gb = "unknown", None, None
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key = line.split(":", 1)[0].strip().lower()
            if key == "model name" and model == "unknown":
                model = line.split(":", 1)[1].strip()
            elif key == "flags" and flags is None:
                flags = line.split(":", 1)[1].split()
    except OSError:
        pass
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                mem_gb = round(int(line.split()[1]) / 1024**2, 2)
                break
    except (OSError, ValueError, IndexError):
        pass
    try:
        nproc = len(os.sched_getaffinity(0))
    except AttributeError:
        nproc = os.cpu_count()
    try:
        snakemake_version = metadata.version("snakemake")
    except metadata.PackageNotFoundError:
        snakemake_version = "not installed"
    return {"nproc": nproc, "cpu_count": os.cpu_count(), "cpu_model": model,
            "vector": widest_vector(flags) if flags is not None else "unknown", "memory_gb": mem_gb,
            "platform": platform.platform(), "python": platform.python_version(), "snakemake": snakemake_version}
