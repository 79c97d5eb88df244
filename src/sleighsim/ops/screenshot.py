"""The report's first screen as an image (the README's docs/report-first-screen.png), by headless Chromium in a
1280 x 900 window, the size the report's first-screen check is laid out for:

    python -m sleighsim.ops.screenshot [results/report/index.html] [--out docs/report-first-screen.png]

Chromium comes from the system (``apt-get install chromium``); without it the command says so and exits 1."""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

#: The window the first screen is laid out for (pixels).
WINDOW = (1280, 900)
#: The browsers tried, in order.
BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def browser() -> str | None:
    """The first of BROWSERS on the PATH (None: none)."""
    return next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)


def flags(profile: Path) -> list[str]:
    """Headless Chromium's flags: no network but the page's own files, a fresh profile in ``profile``, the
    WINDOW, scripts given 10 s of virtual time."""
    return ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
            "--disable-component-update", "--disable-sync", "--no-first-run", f"--user-data-dir={profile}",
            "--virtual-time-budget=10000", f"--window-size={WINDOW[0]},{WINDOW[1]}", "--hide-scrollbars"]


def screenshot(page: Path, out: Path, exe: str) -> Path:
    """Write the first screen of ``page`` (an HTML file) to ``out`` (PNG) with the browser ``exe``;
    RuntimeError when the browser writes no image."""
    out = Path(out).resolve()
    out.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="sleighsim-shot-") as tmp:
        run = subprocess.run([exe, *flags(Path(tmp)), f"--screenshot={out}", Path(page).resolve().as_uri()],
                             capture_output=True, text=True, timeout=120)
    if not out.is_file():
        raise RuntimeError(f"{exe} wrote no screenshot of {page}: {run.stderr[-1000:]}")
    return out


def main(argv=None) -> int:
    """Screenshot the page given (or the default run's report) to --out; 1 without the page or a browser."""
    parser = argparse.ArgumentParser(prog="python -m sleighsim.ops.screenshot",
                                     description="The report's first screen as an image (headless Chromium).")
    parser.add_argument("page", nargs="?", default="results/report/index.html")
    parser.add_argument("--out", default="docs/report-first-screen.png")
    args = parser.parse_args(argv)
    if not Path(args.page).is_file():
        print(f"no report at {args.page}: run the workflow first (snakemake -c2)", file=sys.stderr)
        return 1
    exe = browser()
    if exe is None:
        print("no Chromium on the PATH (apt-get install chromium)", file=sys.stderr)
        return 1
    print(screenshot(Path(args.page), Path(args.out), exe))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
