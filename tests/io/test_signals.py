"""Issue 55: SIGTERM during a large netCDF write or during checksum stamping ends the writer at once
with status 143, its temporary file removed and nothing put in place (before: a deadlock in
xarray's close, a 960 MB temporary left; or the signal swallowed, the job exiting 0 with its product
in place). A signal after the write finds the product complete."""

import signal
import subprocess
import sys
import textwrap
import time

import pytest

from sleighsim.io.checksum import verify

N = 20_000_000  # values: a write of about a second


def _writer(target, hook: str) -> subprocess.Popen:
    """A process writing N values to ``target``; it prints "ready", "<hook>" when the write reaches
    ``hook`` ("write": the netCDF write, "stamp": the checksum stamping), then "done", and sleeps."""
    code = textwrap.dedent(f"""
        import time
        import numpy as np, xarray as xr
        from sleighsim.io import netcdf
        ds = xr.Dataset({{"u": ("time", np.random.default_rng(0).random({N}))}})
        real_stamp, real_write = netcdf.stamp, xr.Dataset.to_netcdf
        def stamp(*a, **k):
            print("stamp", flush=True)
            return real_stamp(*a, **k)
        def write(*a, **k):
            print("write", flush=True)
            return real_write(*a, **k)
        netcdf.stamp, xr.Dataset.to_netcdf = stamp, write
        print("ready", flush=True)
        netcdf.write_dataset(ds, {str(target)!r})
        print("done", flush=True)
        time.sleep(60)
    """)
    return subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@pytest.mark.parametrize("hook, delay", [("write", 0.0), ("write", 0.3), ("stamp", 0.0), ("stamp", 0.05),
                                         ("stamp", 0.2)])
def test_sigterm_while_writing_or_stamping_ends_the_writer_leaving_nothing(tmp_path, hook, delay):
    target = tmp_path / "data" / "big.nc"
    proc = _writer(target, hook)
    try:
        lines = []
        while (line := proc.stdout.readline().strip()) != hook:
            assert line, proc.stderr.read()[-2000:]
            lines.append(line)
        time.sleep(delay)
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            pytest.fail(f"the writer neither ended nor finished 30 s after SIGTERM during {hook} (deadlocked or the "
                        "signal swallowed)")
    finally:
        proc.kill()
        proc.communicate()
    left = sorted(p.name for p in target.parent.iterdir())
    if proc.returncode == 128 + signal.SIGTERM:
        assert left == [], left  # neither a product nor a temporary file
    else:  # the signal came after the write: the default action, the product complete
        assert proc.returncode == -signal.SIGTERM and left == ["big.nc"] and verify(target)
