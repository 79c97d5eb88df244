"""Every command the README and docs/ show works: each is found in the text (code blocks, indented code,
code spans, the tutorial's comments) and checked by what it is. A Snakemake command is dry-run in a fresh
working directory (and its targets must stand before ``--configfile``, which reads every word after it as
a config file); a command of the package runs where it is quick and harmless, else its ``--help`` must
list every option the docs use; an install names extras and files that exist; a script parses. A command
no rule here knows fails the test, so a new one in the docs needs a check."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from conftest import ROOT

DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), ROOT / "docs" / "tutorial.py"]
PROGRAMS = ("snakemake", "sleighsim", "python", "pip", "pytest", "bash", "lint-imports", "snakefmt", "ruff",
            "cluster/slurm-test.sh", "jupytext", "dot")
#: Wrappers in front of a command, and environment assignments.
WRAPPER = re.compile(r"^(?:sudo\s+)?(?:env\s+)?(?:[A-Z_]+=\S+\s+)*(?:taskset\s+-c\s+\d+\s+)?(?:nice\s+-n\s+\d+\s+)?")
#: A word that stands for something the reader supplies.
PLACEHOLDER = re.compile(r"^(?:[A-Z][A-Z_]*[A-Z](?:/.*)?|\[.*|.*\.\.\.|R/.*|<.*>|.*\]|\.\.\.)$")
#: Snakemake's options that take no value, and the documented uses it does not dry-run (checked elsewhere).
ELSEWHERE = {"--report": "tests/workflow/test_workflow.py::test_snakemakes_own_report_holds_every_figure_under_its_"
                         "paper_section", "--rulegraph": "tests/workflow/test_rulegraph.py",
             "--lint": ".ci/run (snakemake --lint)"}
SNAKEMAKE_ENV = {"PYTHONPATH": str(ROOT / "src")}


def _candidates(text: str) -> list[str]:
    """Lines of fenced or indented code, code spans, and the tutorial's comment lines."""
    out, fenced = [], False
    for line in text.splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif fenced or line.startswith("    ") and not line.lstrip().startswith(("-", "*")):
            out.append(line.strip())
        out += re.findall(r"`([^`]+)`", line)
        if line.startswith("# ") and "python " in line:  # the tutorial's markdown cells
            out += re.findall(r"\(`?((?:python|jupytext) [^`)]+)`?", line)
    return out


#: An option whose value the text leaves out: a command ending with one is a mention of the option
#: ("as `snakemake --configfile` does"), not a command.
TAKES_VALUE = ("--configfile", "--report", "--profile", "--out", "-d", "-s")


def _commands(piece: str) -> list[str]:
    """The commands in one candidate: split at && and |, comments dropped, wrappers stripped; only those
    that start with a program of PROGRAMS, are more than its bare name, and are no mention of an option."""
    out = []
    for part in re.split(r"&&|\|", piece.split(" # ")[0].split("   #")[0]):
        cmd = WRAPPER.sub("", part.strip()).strip()
        words = cmd.split()
        if (words and words[0] in PROGRAMS and (len(words) > 1 or words[0] in ("pytest", "lint-imports"))
                and words[-1] not in TAKES_VALUE):
            out.append(cmd)
    return out


def documented() -> list[tuple[str, str]]:
    """(file, command) for every command of the docs, each once."""
    seen = {}
    for doc in DOCS:
        for piece in _candidates(doc.read_text()):
            for cmd in _commands(piece):
                seen.setdefault(cmd, doc.relative_to(ROOT).as_posix())
    return [(f, c) for c, f in seen.items()]


COMMANDS = documented()


def test_the_docs_hold_the_commands_a_newcomer_types():
    cmds = {c for _, c in COMMANDS}
    assert len(cmds) >= 30
    for must in ("snakemake -c2", "snakemake -c2 fig3", "sleighsim --help",
                 "snakemake -c2 --configfile config/smoke.yaml"):
        assert must in cmds, must


def _words(cmd: str) -> list[str]:
    return shlex.split(cmd.replace("\\", ""))


def configfile_misuse(words: list[str]) -> list[str]:
    """The words after ``--configfile`` that are no config file (Snakemake reads them as one)."""
    if "--configfile" not in words:
        return []
    after = words[words.index("--configfile") + 1:]
    files = after[: next((i for i, w in enumerate(after) if w.startswith("-")), len(after))]
    return [w for w in files if not w.endswith((".yaml", ".yml")) and not PLACEHOLDER.match(w)]


@pytest.mark.parametrize("words, bad", [
    ("snakemake -c2 --configfile config/smoke.yaml fig3".split(), ["fig3"]),
    ("snakemake -n --configfile config/cluster.yaml results/data/fig11_grid.nc".split(),
     ["results/data/fig11_grid.nc"]),
    ("snakemake -c2 fig3 --configfile config/smoke.yaml".split(), []),
    ("snakemake -c2 --configfile config/smoke.yaml -- fig3".split(), []),
    ("snakemake -c2".split(), []),
])
def test_a_target_after_configfile_is_caught(words, bad):
    assert configfile_misuse(words) == bad


def _help(argv_prefix: list[str], sub: list[str]) -> str:
    res = subprocess.run([*argv_prefix, *sub, "--help"], capture_output=True, text=True, timeout=120, cwd=ROOT,
                         env={**_env(), **SNAKEMAKE_ENV})
    assert res.returncode == 0, (argv_prefix, sub, res.stderr[-1500:])
    return res.stdout


def _env() -> dict:
    import os

    return dict(os.environ)


def _options_in_help(words: list[str], argv_prefix: list[str], subs: tuple[str, ...]) -> None:
    """The subcommand path (leading words of ``subs``) answers --help and lists every option used."""
    sub = [w for w in words if w in subs][:2]
    text = _help(argv_prefix, sub)
    for opt in (w.split("=")[0] for w in words if w.startswith("--")):
        assert opt in text, (words, opt)


def _snakemake(words: list[str], tmp_path: Path) -> None:
    assert not configfile_misuse(words), f"targets after --configfile: {configfile_misuse(words)}"
    used = [w for w in words if w.startswith("--")]
    if any(w in ELSEWHERE for w in used):
        pytest.skip("checked by " + ", ".join(ELSEWHERE[w] for w in used if w in ELSEWHERE))
    args = words[1:]
    if "--profile" in args and shutil.which("sbatch") is None:  # the SLURM executor is the cluster extra's
        i = args.index("--profile")
        args = args[:i] + args[i + 2:]
    dry = [] if "--unlock" in args else ["-n"]  # before the words: a "--" ends the options
    key = tuple(a for a in args if not re.fullmatch(r"-c\d*", a))  # the cores change no dry run
    if key not in _DRY_RUNS:
        cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(tmp_path),
               *dry, *args]
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=ROOT,
                             env={**_env(), **SNAKEMAKE_ENV})
        _DRY_RUNS[key] = (res.returncode, (res.stdout + res.stderr)[-3000:])
    code, out = _DRY_RUNS[key]
    assert code == 0, out


#: Dry runs already made in this process, by their words without the cores (``snakemake -c2 drift`` and
#: ``snakemake drift`` are one).
_DRY_RUNS: dict[tuple[str, ...], tuple[int, str]] = {}


#: Package commands that run in full (quick, writing only under the test's directory); the others need a
#: finished results tree (exercised by tests/claims, tests/ops, tests/io) and are checked by their --help.
RUN = {
    "sleighsim --help": (), "sleighsim configdoc --check": (), "python -m sleighsim.ops.configdoc --check": (),
    "python -m sleighsim.ops.lockcheck": (),
    "python -m sleighsim.ops.costs estimate --configfile config/cluster.yaml": (),
    "python -m sleighsim.scenes.bench results/data/bench.nc": ("--quick",),
    "sleighsim verify results": (),
}
SUBCOMMANDS = ("claims", "diff", "costs", "estimate", "plot", "times", "configdoc", "finding", "judge", "verify")


def _package(cmd: str, words: list[str], tmp_path: Path) -> None:
    if words[0] == "python" and words[1] == "-m":
        prefix, rest = [sys.executable, "-m", words[2]], words[3:]
    elif words[0] == "python":
        script = ROOT / words[1]
        assert script.is_file(), script
        if script == ROOT / "docs" / "tutorial.py":
            assert (ROOT / "tests" / "test_tutorial.py").is_file()  # runs it, on the smoke horizons
            return
        prefix, rest = [sys.executable, str(script)], words[2:]
    else:
        prefix, rest = [sys.executable, "-m", "sleighsim.cli"], words[1:]
    if cmd in RUN:
        if cmd == "sleighsim verify results":
            import xarray as xr

            from sleighsim.io.netcdf import write_dataset

            write_dataset(xr.Dataset({"u": ("t", [1.0, 2.0])}), tmp_path / "results" / "data" / "fig3.nc")
        args = [str(tmp_path / a) if a.startswith("results/") else a for a in rest]
        res = subprocess.run([*prefix, *args, *RUN[cmd]], capture_output=True, text=True, timeout=600,
                             cwd=tmp_path if "verify" in cmd else ROOT, env={**_env(), **SNAKEMAKE_ENV})
        assert res.returncode == 0, (cmd, (res.stdout + res.stderr)[-3000:])
        return
    _options_in_help(rest, prefix, SUBCOMMANDS)


def _install(words: list[str]) -> None:
    """What ``pip install`` is given exists: the package (its pyproject.toml), its extras, a lock file, or a
    package the extras name."""
    project = (ROOT / "pyproject.toml").read_text()
    extras = tomllib.loads(project)["project"]["optional-dependencies"]
    given = [w for w in words[words.index("install") + 1:] if not w.startswith("-")]
    assert given, words
    for w in given:
        m = re.fullmatch(r"\.(?:\[(.+)\])?", w)
        if m:
            assert set(m[1].split(",") if m[1] else ()) <= set(extras), w
        elif w.endswith(".lock"):
            assert (ROOT / w).is_file(), w
        else:
            assert any(w in dep for deps in extras.values() for dep in deps), w


def _test_script(words: list[str]) -> None:
    """A test module run as a script (docs/birkhoff.md): it exists and its __main__ takes the documented
    first argument (and a precision the package knows)."""
    from sleighsim.precision import Precision

    script = (ROOT / words[1]).read_text()
    main = script[script.index('if __name__ == "__main__":'):]
    assert f"py {words[2]} " in main, words
    if words[2] == "sleigh":
        Precision(words[3])


@pytest.mark.parametrize("doc, cmd", COMMANDS, ids=[c for _, c in COMMANDS])
def test_every_documented_command_works(doc, cmd, tmp_path):
    words = _words(cmd)
    if words[:3] == ["python", "-m", "pip"]:
        words = words[2:]
    program = words[0]
    if program == "snakemake":
        _snakemake(words, tmp_path)
    elif program == "python" and words[1].startswith("tests/"):
        _test_script(words)
    elif program in ("sleighsim", "python"):
        _package(cmd, words, tmp_path)
    elif program == "pip":
        _install(words)
    elif program == "pytest":
        assert all((ROOT / w).exists() for w in words[1:] if not w.startswith("-") and "/" in w), cmd
    elif program in ("bash", "cluster/slurm-test.sh"):
        script = ROOT / (words[1] if program == "bash" else program)
        assert subprocess.run(["bash", "-n", str(script)], capture_output=True).returncode == 0, script
    elif program in ("lint-imports", "snakefmt", "ruff"):
        assert shutil.which(program) or (Path(sys.executable).parent / program).exists(), program
    elif program in ("jupytext", "dot"):
        if shutil.which(program) is None:
            pytest.skip(f"{program} is optional (the docs say so) and not installed")
        flag = {"jupytext": "--version", "dot": "-V"}[program]  # graphviz's dot knows no --version
        assert subprocess.run([program, flag], capture_output=True).returncode == 0
    else:
        pytest.fail(f"{doc}: no rule checks {cmd!r}")


#: A dotted word ending so is a file's name (``claims.csv``, ``report.zip``), not a module's.
FILE_SUFFIXES = ("csv", "nc", "zip", "html", "yaml", "yml", "md", "py", "png", "pdf", "svg", "lock", "tsv", "json",
                 "txt", "log", "toml")


def named_in_docs() -> set[str]:
    """The package's dotted names in the docs' code spans (``claims.rules.SLIGHT``,
    ``sleighsim.ops.config.merged_config``), without the leading ``sleighsim.``."""
    import pkgutil

    import sleighsim

    packages = {m.name for m in pkgutil.iter_modules(sleighsim.__path__)}
    dotted = re.compile(r"(?<![\w/.-])(?:sleighsim\.)?[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+")
    names = set()
    for doc in DOCS:
        for span in re.findall(r"`([^`\n]+)`", doc.read_text()):
            names |= {n.removeprefix("sleighsim.") for n in dotted.findall(span)}
    return {n for n in names if n.split(".")[0] in packages and n.split(".")[-1] not in FILE_SUFFIXES}


def _resolves(name: str) -> bool:
    """The longest importable module of ``sleighsim.<name>`` holds the rest as attributes."""
    import importlib

    parts = ["sleighsim", *name.split(".")]
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
            break
        except ModuleNotFoundError:
            continue
    for attr in parts[i:]:
        if not hasattr(obj, attr):
            return False
        obj = getattr(obj, attr)
    return True


def test_every_module_and_name_the_docs_cite_exists():
    """docs/running.md once named ``sleighsim.ops.facts.merged_config``, which never existed."""
    names = named_in_docs()
    assert len(names) > 50 and "ops.config.merged_config" in names
    assert not _resolves("ops.facts.merged_config")
    assert [n for n in sorted(names) if not _resolves(n)] == []


def test_the_readme_stays_one_screen():
    """The README is one screen: at most 120 lines (the house's rule); details go to docs/."""
    assert len((ROOT / "README.md").read_text().splitlines()) <= 120
