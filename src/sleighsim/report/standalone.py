"""The reproduction report as one file: its page with every image beside it inlined, so that
Snakemake's own report (``snakemake --report report.zip``) can carry and open it."""

from __future__ import annotations

import base64
import mimetypes
import re
from pathlib import Path

_IMG = re.compile(r'(<img\b[^>]*?\bsrc=")([^":]+)(")')


def inline_images(html_path) -> str:
    """The page at ``html_path`` with each ``<img src="...">`` naming a file beside it (a relative
    path) replaced by a data URI of that file; FileNotFoundError when one is missing."""
    html_path = Path(html_path)

    def data_uri(m: re.Match) -> str:
        image = html_path.parent / m[2]
        mime = mimetypes.guess_type(image.name)[0] or "application/octet-stream"
        return f"{m[1]}data:{mime};base64,{base64.b64encode(image.read_bytes()).decode()}{m[3]}"

    return _IMG.sub(data_uri, html_path.read_text())
