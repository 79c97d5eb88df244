#!/usr/bin/env bash
# Write the lock files from pyproject.toml with pip-tools (pip install pip-tools), for the Python
# that runs this script (3.11: requirements/py311.lock, and py311-test.lock with the test extra,
# constrained to the first so that both pin the shared packages alike). Resolved against PyPI
# alone: a local pip config's indexes, links and constraints are ignored. Existing pins are kept
# while they still satisfy pyproject; pass --upgrade to move every pin to the newest release.
#   python -m pip install pip-tools && bash requirements/compile.sh [--upgrade]
# tests/ops/test_lock.py (and .ci/run: python -m sleighsim.ops.lockcheck) check them against pyproject.
set -euo pipefail
cd "$(dirname "$0")/.."
py=$(python -c 'import sys; print(f"py{sys.version_info.major}{sys.version_info.minor}")')
compile() {
    env -u PIP_FIND_LINKS -u PIP_CONSTRAINT PIP_CONFIG_FILE=/dev/null python -m piptools compile --quiet \
        --generate-hashes --allow-unsafe --strip-extras --index-url https://pypi.org/simple "$@" pyproject.toml
}
compile "$@" --output-file "requirements/$py.lock"
compile "$@" --extra test --constraint "requirements/$py.lock" --output-file "requirements/$py-test.lock"
