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


def machine_facts() -> dict:
    """Cores usable here, CPU model, memory (GB), platform, Python and Snakemake versions, as a dict."""
    model, mem_gb = "unknown", None
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
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
    return {"nproc": nproc, "cpu_count": os.cpu_count(), "cpu_model": model, "memory_gb": mem_gb,
            "platform": platform.platform(), "python": platform.python_version(), "snakemake": snakemake_version}
