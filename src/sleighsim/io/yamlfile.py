"""Reading YAML documents with libyaml's parser where PyYAML was built with it.

The documents are the same as ``yaml.safe_load`` gives (the same safe constructor); only the scanner and
parser are C. The judge-power record (about 2 MB) loads in about 1 s instead of 3 s.
"""

from pathlib import Path

import yaml

#: The safe loader, in C where available.
LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def read_yaml(path):
    """The document of the YAML file at ``path``, with safe types only."""
    return yaml.load(Path(path).read_text(), Loader=LOADER)  # noqa: S506 (a safe loader)
