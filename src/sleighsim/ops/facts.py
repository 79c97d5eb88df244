"""Facts a cost summary records about the run's setting: the merged config, the git commit and
the machine."""

from __future__ import annotations

import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
BASE_CONFIG = REPO / "config" / "config.yaml"


def _plain(value):
    """Plain dicts and lists (Snakemake's loaders may return ordered or custom mappings)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def merged_config(configfiles=(), base=BASE_CONFIG) -> dict:
    """``base`` with each of ``configfiles`` merged onto it, the way Snakemake merges ``--configfile``
    onto the Snakefile's ``configfile:`` (snakemake.utils.update_config on load_configfile)."""
    from snakemake.common.configfile import load_configfile
    from snakemake.utils import update_config

    config = _plain(load_configfile(str(base)))
    for f in configfiles:
        update_config(config, _plain(load_configfile(str(f))))
    return _plain(config)


def git_commit(repo=REPO) -> str:
    """HEAD of ``repo``, with "-dirty" when tracked files differ (read-only git commands)."""
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
    """Cores usable here, CPU model, memory, platform, Python and Snakemake versions."""
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
