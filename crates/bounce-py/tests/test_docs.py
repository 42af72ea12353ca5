"""Every snippet of the README and the user guide (docs/src) runs, and every link lands.

Each page's code blocks run in order in a scratch folder that sees the repository's
`scenarios/` and `examples/` as a reader's checkout does:

- `python`: run with this interpreter (the package installed); it must exit 0.
- `toml`: a scenario is written to a file, checked with `bounce check` and run for a few
  steps; a sweep file (a top-level `scenario` key) is written to `sweep.toml`, which the
  page's commands then run; a Cargo manifest (a `[dependencies]` table) must parse.
- `sh`: every `bounce` command (written `bounce ...`, `cargo run --release -- ...` or
  `target/release/bounce ...`) must name a real command and real flags (against its
  `--help`), and runs unless it opens a window or needs a cluster; any other command must be
  one this test knows, and the scripts it names must exist.
- `rust`: run as the library's doctests (`cargo test --doc -p bounce`), not here.
- `text`: output shown to the reader, not run.
"""

import os
import pathlib
import re
import shlex
import subprocess
import sys
import tomllib

import pytest

from conftest import ROOT

PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs" / "src").rglob("*.md"))
KINDS = {"python", "toml", "sh", "rust", "text"}
FENCE = re.compile(r"^```(\S*)\s*$")


def blocks(path):
    """The fenced code blocks of a page: (info string, text, line)."""
    out, info, lines, start = [], None, [], 0
    for number, line in enumerate(path.read_text().splitlines(), 1):
        fence = FENCE.match(line)
        if fence and info is None:
            info, lines, start = fence.group(1), [], number
        elif line.startswith("```") and info is not None:
            out.append((info, "\n".join(lines) + "\n", start))
            info = None
        elif info is not None:
            lines.append(line)
    assert info is None, f"{path}: a code block opened at line {start} never closes"
    return out


def page_id(path):
    return str(path.relative_to(ROOT))


def test_every_block_says_its_language():
    for page in PAGES:
        for info, _, line in blocks(page):
            assert info in KINDS, f"{page_id(page)}:{line}: a code block marked {info!r}"


# What a `sh` line may run besides `bounce`: the first word, and whether the test runs it.
OTHER_COMMANDS = {
    "cargo": False,  # building: the test suite itself is built that way
    "scripts/test": False,
    "scripts/build-web": False,
    "scripts/build-guide": False,
    "scripts/install-python": False,
    "scripts/install-mpi": False,
    "python3": False,  # a static server for the page
    "sbatch": False,  # a cluster's scheduler
}
# `bounce` commands that open a window or run for long: their flags are checked, not run.
NOT_RUN = {"view"}


def bounce_args(words):
    """The arguments of a `bounce` command line, or None if the line runs something else."""
    if words[0] == "bounce" or words[0].endswith("/bounce"):
        return words[1:]
    if words[:4] == ["cargo", "run", "--release", "--"]:
        return words[4:]
    if words[0] == "mpirun":
        rest = words[1:]
        while rest and rest[0].startswith("-"):
            rest = rest[2:]  # -np N
        return bounce_args(rest)
    return None


HELP = {}


def flags_of(bounce_bin, command):
    if command not in HELP:
        done = subprocess.run([bounce_bin, command, "--help"], capture_output=True, text=True)
        assert done.returncode == 0, f"`bounce {command}` is no command: {done.stderr}"
        # Option lines are indented a few spaces; a wrapped description's lines many more.
        HELP[command] = set(re.findall(r"(?m)^ {1,10}(?:-\w, )?(--[\w-]+)", done.stdout))
    return HELP[command]


def run_sh(line, where, cwd, bounce_bin):
    words = shlex.split(line, comments=True)
    if not words:
        return
    args = bounce_args(words)
    if args is None:
        assert words[0] in OTHER_COMMANDS, f"{where}: a command this test does not know: {line}"
        for word in words:
            if word.startswith("scripts/"):
                assert (ROOT / word).exists(), f"{where}: {word} does not exist"
        return
    if args[0].startswith("-"):
        assert args == ["--version"], f"{where}: {line}"
        return
    command = args[0]
    known = flags_of(bounce_bin, command)
    for word in args[1:]:
        if word.startswith("--"):
            assert word in known, f"{where}: `bounce {command}` has no flag {word}"
    if command in NOT_RUN or words[0] == "mpirun":
        return
    done = subprocess.run(
        [bounce_bin, *args], cwd=cwd, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, f"{where}: {line}\n{done.stdout}{done.stderr}"


def run_toml(text, where, cwd, bounce_bin, number):
    parsed = tomllib.loads(text)
    if "dependencies" in parsed:  # a Cargo manifest
        assert "bounce" in parsed["dependencies"], where
        return
    if "scenario" in parsed:  # a sweep file: the page's commands run it
        (cwd / "sweep.toml").write_text(text)
        assert (cwd / parsed["scenario"]).exists(), f"{where}: no {parsed['scenario']}"
        return
    path = cwd / f"snippet-{number}.toml"
    path.write_text(text)
    for args in (["check", path], ["run", path, "--out", cwd / f"snippet-{number}", "--steps", "5", "-q"]):
        done = subprocess.run([bounce_bin, *map(str, args)], cwd=cwd, capture_output=True, text=True)
        assert done.returncode == 0, f"{where}: bounce {args[0]}\n{done.stdout}{done.stderr}"


def run_python(text, where, cwd):
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run(
        [sys.executable, "-c", text], cwd=cwd, capture_output=True, text=True, env=env, timeout=600
    )
    assert done.returncode == 0, f"{where}\n{done.stdout}{done.stderr}"
    return done.stdout


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_every_snippet_of_the_page_runs(page, tmp_path, bounce_bin):
    for name in ("scenarios", "examples"):
        (tmp_path / name).symlink_to(ROOT / name)
    for number, (info, text, line) in enumerate(blocks(page)):
        where = f"{page_id(page)}:{line}"
        if info == "python":
            run_python(text, where, tmp_path)
        elif info == "toml":
            run_toml(text, where, tmp_path, bounce_bin, number)
        elif info == "sh":
            for command in text.splitlines():
                run_sh(command, where, tmp_path, bounce_bin)


def test_the_python_obstacle_example_touches_every_obstacle(tmp_path):
    """The reference page's obstacle example: discs reach the peg, the moving piston and the
    sink, so the work and the impulses it prints are not zero."""
    page = ROOT / "docs" / "src" / "reference" / "python.md"
    (example,) = [t for i, t, _ in blocks(page) if i == "python" and "polyline" in t]
    check = example + (
        "\nassert abs(peg[1]) > 0 and abs(piston[1]) > 0, (peg, piston)"
        "\nassert world.obstacle_work != 0"
        "\nassert world.sensors['drain']['left'] > 0, 'the sink removed none'\n"
    )
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios")
    run_python(check, "the obstacle example", tmp_path)


def anchors(path):
    """The ids mdBook gives a page's headings."""
    out = set()
    for line in path.read_text().splitlines():
        if line.startswith("#") and not line.startswith("#!"):
            title = line.lstrip("#").strip().lower()
            slug = "".join(c for c in title if c.isalnum() or c in " -_").replace(" ", "-")
            out.add(slug)
    return out


def test_every_link_between_pages_lands():
    link = re.compile(r"\]\(([^)\s]+)\)")
    checked = 0
    for page in PAGES:
        text = re.sub(r"(?s)```.*?```", "", page.read_text())
        for target in link.findall(text):
            if re.match(r"[a-z]+://", target):
                continue
            path, _, anchor = target.partition("#")
            dest = (page.parent / path).resolve() if path else page
            assert dest.exists(), f"{page_id(page)}: a link to {target}, which does not exist"
            if anchor:
                assert anchor in anchors(dest), f"{page_id(page)}: no heading #{anchor} in {path}"
            checked += 1
    assert checked > 50


def test_every_guide_page_is_in_the_summary():
    src = ROOT / "docs" / "src"
    summary = (src / "SUMMARY.md").read_text()
    listed = set(re.findall(r"\]\(([^)]+\.md)\)", summary))
    pages = {str(p.relative_to(src)) for p in src.rglob("*.md")} - {"SUMMARY.md"}
    assert listed == pages


def test_every_public_python_name_is_on_the_reference_page():
    import bounce

    text = (ROOT / "docs" / "src" / "reference" / "python.md").read_text()
    missing = []
    for name in bounce.__all__ if hasattr(bounce, "__all__") else dir(bounce):
        if name.startswith("_"):
            continue
        obj = getattr(bounce, name)
        if not isinstance(obj, type) and not callable(obj):
            continue
        if f"`{name}" not in text and f"{name}(" not in text:
            missing.append(name)
        if isinstance(obj, type):
            for member in dir(obj):
                if not member.startswith("_") and f"`{member}" not in text and f"{member}(" not in text and f", {member}" not in text:
                    missing.append(f"{name}.{member}")
    assert not missing, f"not on docs/src/reference/python.md: {missing}"


def test_the_first_runs_summary_is_the_one_the_guide_shows(tmp_path, bounce_bin):
    """Getting started shows the gas run's summary and says yours will match: it must."""
    page = ROOT / "docs" / "src" / "getting-started.md"
    (shown,) = [t for i, t, _ in blocks(page) if i == "text" and "state hash" in t]
    done = subprocess.run(
        [bounce_bin, "run", ROOT / "scenarios" / "gas.toml", "--out", tmp_path / "out", "-q",
         "--set", "output.frame_every=0", "--set", "output.gif=false"],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == shown.splitlines()[0]
