"""docs/rulegraph.svg is the workflow's rule graph as it is now (redraw it with the command in
docs/running.md when this fails)."""

import html
import re
import subprocess
import sys

from conftest import ROOT


def _edges(nodes: dict, pairs) -> set:
    return {(nodes[a], nodes[b]) for a, b in pairs}


def test_the_rule_graph_in_docs_is_the_workflows():
    dot = subprocess.run([sys.executable, "-m", "snakemake", "--rulegraph"], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout
    want = _edges(dict(re.findall(r'^\s*(\d+)\[label = "([^"]+)"', dot, re.M)),
                  re.findall(r"^\s*(\d+) -> (\d+)", dot, re.M))
    svg = html.unescape((ROOT / "docs" / "rulegraph.svg").read_text())
    nodes = dict(re.findall(r'class="node">\s*<title>(\d+)</title>.*?<text[^>]*>([^<]+)</text>', svg, re.S))
    have = _edges(nodes, re.findall(r'class="edge">\s*<title>(\d+)->(\d+)</title>', svg))
    assert len(want) > 10 and have == want
