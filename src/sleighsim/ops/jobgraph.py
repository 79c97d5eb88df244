"""A run's job graph, from Snakemake's own output, its critical path and its predicted wall on n cores.

The job graph comes from two dry runs in the run's directory, saved by ``benchmarks/full_run.py``
under ``<workdir>/costs/``: ``snakemake --forceall -n --dag`` (``dag.dot``: the edges; its labels show
only the wildcards a job adds to its inputs' jobs) and ``snakemake --forceall -n`` (``dryrun.txt``:
every job's rule, wildcards, input and benchmark file). :func:`job_graph` matches the two.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict

import networkx as nx

#: Where benchmarks/full_run.py keeps the dry-run outputs of a run, inside its workdir.
COSTS_DIR = "costs"
DAG_FILE = "dag.dot"
DRYRUN_FILE = "dryrun.txt"

_NODE = re.compile(r'^\s*(\d+)\s*\[\s*label\s*=\s*"((?:[^"\\]|\\.)*)"')
_EDGE = re.compile(r"^\s*(\d+)\s*->\s*(\d+)")
_HEAD = re.compile(r"^(?:local)?(?:rule|checkpoint)\s+(\S+):\s*$")
_FIELD = re.compile(r"^\s+(\w+):(?:\s+(.*))?$")
#: Nodes the critical path runs between, before and after every job (not jobs themselves).
_START, _END, _PAST_END = object(), object(), object()


def parse_dot(text: str) -> tuple[dict, list]:
    """Nodes {id: (rule, {wildcard: value shown in the label})} and edges [(dependency, job)] of
    ``snakemake --dag`` output (lines before ``digraph`` are ignored)."""
    nodes, edges = {}, []
    for line in text.splitlines():
        if m := _NODE.match(line):
            parts = m.group(2).split("\\n")
            wildcards = dict(p.split(": ", 1) for p in parts[1:] if ": " in p)
            nodes[int(m.group(1))] = (parts[0], wildcards)
        elif m := _EDGE.match(line):
            edges.append((int(m.group(1)), int(m.group(2))))
    return nodes, edges


def parse_dryrun(text: str) -> list[dict]:
    """The jobs of ``snakemake -n`` output: [{rule, jobid, input, output, benchmark, wildcards}]."""
    jobs, job = [], None
    for line in text.splitlines():
        if m := _HEAD.match(line):
            job = {"rule": m.group(1), "jobid": None, "input": [], "output": [], "benchmark": None, "wildcards": {}}
            jobs.append(job)
        elif job is not None and (f := _FIELD.match(line)):
            key, value = f.group(1), f.group(2) or ""
            if key in ("input", "output"):
                job[key] = [v.strip() for v in value.split(", ") if v.strip()]
            elif key == "benchmark":
                job["benchmark"] = value.strip()
            elif key == "jobid" and value.strip().isdigit():
                job["jobid"] = int(value)
            elif key == "wildcards":
                job["wildcards"] = dict(w.split("=", 1) for w in value.split(", ") if "=" in w)
        elif not line.startswith("    "):
            job = None
    return jobs


def topological_order(dag: nx.DiGraph) -> list:
    """Node ids, every node after its dependencies (ties by id); raises ValueError on a cycle."""
    try:
        return list(nx.lexicographical_topological_sort(dag))
    except nx.NetworkXUnfeasible:
        raise ValueError("the job graph has a cycle") from None


def _match(node, rule: str, shown: dict, deps: list, graph: dict, by_rule: dict, used: set):
    """Index and dry-run job of ``rule`` that the DAG node matches, or (None, None) and a note."""
    inherited = set()
    for d in deps:
        inherited |= set(graph[d]["wildcards"].items())
    candidates = [(i, j) for i, j in enumerate(by_rule[rule]) if (rule, i) not in used
                  and all(j["wildcards"].get(k) == v for k, v in shown.items())
                  and all(k in shown or (k, v) in inherited for k, v in j["wildcards"].items())]
    if len(candidates) > 1:
        made = {f for d in deps for f in graph[d]["output"]}
        candidates = [(i, j) for i, j in candidates if made <= set(j["input"])] or candidates
    if len(candidates) == 1:
        return candidates[0], None
    return (None, None), f"DAG node {node} ({rule} {shown}) matched {len(candidates)} dry-run jobs: no benchmark taken"


def job_graph(dot_text: str, dryrun_text: str) -> tuple[dict, list[str]]:
    """Every job of the DAG: {node id: {rule, wildcards, deps, benchmark, output}} with its full
    wildcards and benchmark file from the dry run, and notes on nodes that could not be matched.

    A dot label shows only the wildcards a job does not share with the jobs it depends on, so the
    others are taken from those jobs: going through the graph in dependency order, a node matches the
    dry-run job of its rule whose wildcards are the label's plus ones its dependencies carry (ties
    broken by the dependencies' outputs being its inputs)."""
    nodes, edges = parse_dot(dot_text)
    dag = nx.DiGraph()
    dag.add_nodes_from(nodes)
    dag.add_edges_from((a, b) for a, b in edges if a in nodes and b in nodes)
    by_rule = defaultdict(list)
    for j in parse_dryrun(dryrun_text):
        by_rule[j["rule"]].append(j)
    used, graph, notes = set(), {}, []
    for n in topological_order(dag):
        rule, shown = nodes[n]
        deps = sorted(dag.predecessors(n))
        (index, match), note = _match(n, rule, shown, deps, graph, by_rule, used)
        if match is None:
            notes.append(note)
        else:
            used.add((rule, index))
        graph[n] = {"rule": rule, "deps": deps,
                    "wildcards": dict(match["wildcards"]) if match else dict(shown),
                    "benchmark": match["benchmark"] if match else None,
                    "output": match["output"] if match else []}
    return graph, notes


def critical_path(graph: dict, weight: dict) -> tuple[float, list]:
    """The chain of jobs along the DAG with the largest summed weight: (total, [node ids in order]).

    A job's weight (``weight``, 0 where absent; weights are not negative) goes onto the edges out of
    it: to the jobs that depend on it and to an end node after every job; a start node comes before
    every job. The longest path from start to end (networkx) then sums the weights of the jobs on
    it, and an infinite edge past the end node makes that path the longest of all. Ties, as networkx
    keeps the first of equal predecessors: the dependency with the smallest id, and of equally long
    chains the one ending at the smallest id."""
    if not graph:
        return 0.0, []
    dag = nx.DiGraph()
    dag.add_nodes_from(graph)
    for n, g in graph.items():
        for d in sorted(g["deps"]):
            dag.add_edge(d, n)
    order = topological_order(dag)
    for d, n in dag.edges:
        dag.edges[d, n]["weight"] = weight.get(d, 0.0)
    for n in graph:
        dag.add_edge(_START, n, weight=0.0)  # after its dependencies: the first of equals is a job
    for n in sorted(graph):
        dag.add_edge(n, _END, weight=weight.get(n, 0.0))
    dag.add_edge(_END, _PAST_END, weight=math.inf)
    path = nx.dag_longest_path(dag, weight="weight", topo_order=[_START, *order, _END, _PAST_END])
    return float(nx.path_weight(dag, path[:-1], "weight")), path[1:-2]


def predicted_wall(graph: dict, weight: dict, cores: int) -> float:
    """The wall time of the job graph on ``cores`` cores by list scheduling with the measured job
    times (``weight``, 0 where absent): whenever a core is free it takes the ready job (all its
    dependencies finished) that heads the longest remaining chain (its weight plus its longest chain
    of dependants), ties by id. One core per job, no startup or scheduling overhead: a lower bound on
    Snakemake's wall for jobs of these lengths, and never below the critical path or the total work /
    cores."""
    if cores < 1:
        raise ValueError(f"cores must be at least 1, got {cores!r}")
    if not graph:
        return 0.0
    dag = nx.DiGraph()
    dag.add_nodes_from(graph)
    dag.add_edges_from((d, n) for n, g in graph.items() for d in g["deps"])
    tail = {}
    for n in reversed(topological_order(dag)):
        tail[n] = weight.get(n, 0.0) + max((tail[m] for m in dag.successors(n)), default=0.0)
    waiting = {n: dag.in_degree(n) for n in dag}
    ready = [n for n, k in waiting.items() if k == 0]
    free, running, now = cores, [], 0.0  # running: (end time, node)
    while ready or running:
        ready.sort(key=lambda n: (-tail[n], str(n)))
        while free and ready:
            n = ready.pop(0)
            running.append((now + weight.get(n, 0.0), n))
            free -= 1
        running.sort(key=lambda r: (r[0], str(r[1])))
        now, n = running.pop(0)
        free += 1
        for m in dag.successors(n):
            waiting[m] -= 1
            if waiting[m] == 0:
                ready.append(m)
    return float(now)
