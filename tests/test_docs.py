"""The documentation cannot drift from what it describes.

CONTRIBUTING.md's layout names every module of the package and its benchmarks table
every benchmark; the site silences no warning; the results page's tables are made from
the data files in ``docs/results`` (each naming the command that produced it), every
fragment is on a page and the README quotes the figures those files hold; the API
reference finds a page for every public name.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "robostereo"
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

import api_pages  # noqa: E402
import results_tables  # noqa: E402

#: the longest the results page may be, in lines
RESULTS_PAGE_LINES = 500


def _code_block_after(text: str, heading: str) -> list[str]:
    """The lines of the first fenced code block after the line ``heading``."""
    lines = text.splitlines()
    start = lines.index(heading)
    fences = [i for i in range(start, len(lines)) if lines[i].startswith("```")]
    return lines[fences[0] + 1: fences[1]]


def layout_paths(block: list[str]) -> list[str]:
    """The module paths (under ``src/robostereo``) a layout block names.

    A line's first word ending in ``/`` opens a folder, which holds the lines indented
    deeper below it; a first word ending in ``.py`` names a module in the innermost
    folder open at a smaller indentation (it may itself hold a folder path, such as
    ``robot/planning.py``).  Other lines (descriptions that run on) are skipped.
    """
    root, *rest = block
    assert root.strip() == "src/robostereo/", "the layout block starts with src/robostereo/"
    folders: list[tuple[int, str]] = []
    paths = []
    for line in rest:
        if not line.strip():
            continue
        indent = len(line) - len(line.lstrip())
        word = line.split()[0]
        while folders and folders[-1][0] >= indent:
            folders.pop()
        prefix = "".join(f for _, f in folders)
        if word.endswith("/"):
            folders.append((indent, word))
        elif word.endswith(".py"):
            paths.append(prefix + word)
    return paths


def test_contributing_layout_names_every_module() -> None:
    block = _code_block_after((ROOT / "CONTRIBUTING.md").read_text(), "## Layout")
    listed = layout_paths(block)
    actual = {p.relative_to(PACKAGE).as_posix() for p in PACKAGE.rglob("*.py")}
    missing = sorted(actual - set(listed))
    gone = sorted(set(listed) - actual)
    twice = sorted({p for p in listed if listed.count(p) > 1})
    assert not missing, (
        "CONTRIBUTING.md's layout (## Layout) does not name these modules of "
        "src/robostereo; add a line for each in its folder's block, saying what it holds: "
        + ", ".join(missing))
    assert not gone, ("CONTRIBUTING.md's layout names modules that do not exist (moved or "
                      "removed?): " + ", ".join(gone))
    assert not twice, "CONTRIBUTING.md's layout names these modules twice: " + ", ".join(twice)


def test_the_layout_parser_reads_folders_and_paths() -> None:
    block = ["src/robostereo/", "  a.py   x", "  pkg/   y", "    b.py  z", "      and more",
             "    sub/", "      c.py", "    d/e.py", "  f.py"]
    assert layout_paths(block) == ["a.py", "pkg/b.py", "pkg/sub/c.py", "pkg/d/e.py", "f.py"]


def test_contributing_names_every_benchmark() -> None:
    text = (ROOT / "CONTRIBUTING.md").read_text()
    missing = sorted(p.name for p in (ROOT / "benchmarks").glob("*.py")
                     if f"`benchmarks/{p.name}`" not in text)
    assert not missing, ("CONTRIBUTING.md's table of benchmarks does not name: "
                         + ", ".join(missing))


def test_the_site_silences_no_warning() -> None:
    conf = (DOCS / "conf.py").read_text()
    assert "suppress_warnings" not in conf, "fix the references instead of silencing them"


# -- the results page -----------------------------------------------------------------------


def _commands(node: object, where: str) -> list[str]:
    """Every ``command`` in a data file, each checked to come with its ``measured``."""
    found = []
    if isinstance(node, dict):
        if "command" in node:
            assert isinstance(node["command"], str) and node["command"].strip(), where
            assert str(node.get("measured", "")).strip(), f"{where}: a command says how it ran"
            found.append(node["command"])
        for key, value in node.items():
            found += _commands(value, f"{where}.{key}")
    elif isinstance(node, list):
        for i, value in enumerate(node):
            found += _commands(value, f"{where}[{i}]")
    return found


def test_every_results_file_names_its_command() -> None:
    files = sorted(results_tables.DATA.glob("*.json"))
    assert files
    for path in files:
        assert _commands(json.loads(path.read_text()), path.name), (
            f"{path.name} names no command that produced its figures")


def test_the_results_render_and_every_table_says_its_command(tmp_path: Path) -> None:
    written = results_tables.write_all(tmp_path)
    assert {p.name for p in written} == (
        {f"{n}.md" for n in results_tables.FRAGMENTS} | set(results_tables.FIGURES))
    for name in results_tables.FRAGMENTS:
        text = (tmp_path / f"{name}.md").read_text()
        if "|---" in text:
            assert "*Made by* `" in text, f"the table {name} does not say which command made it"
        assert not re.search(r"\bNone\b|\bnan\b", text), name
    for name in results_tables.FIGURES:
        assert (tmp_path / name).stat().st_size > 1000


def test_every_fragment_is_on_a_page_and_every_include_exists() -> None:
    pages = {p: p.read_text() for p in (DOCS / "guide").glob("*.md")}
    used = {m for text in pages.values() for m in re.findall(r"_generated/([\w.]+)", text)}
    made = {f"{n}.md" for n in results_tables.FRAGMENTS} | set(results_tables.FIGURES)
    assert not used - made, f"pages include fragments nothing makes: {sorted(used - made)}"
    assert not made - used, f"fragments no page includes: {sorted(made - used)}"


def test_the_results_page_is_short() -> None:
    lines = (DOCS / "guide" / "results.md").read_text().count("\n")
    assert lines <= RESULTS_PAGE_LINES, (
        f"docs/guide/results.md has {lines} lines: keep the history in development-log.md")


@pytest.mark.parametrize("phrase", [*results_tables.speed_phrases().values(),
                                    f"wrong {results_tables.false_ratio_span()} times less"])
def test_the_readme_quotes_the_results_data(phrase: str) -> None:
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert phrase in readme, (
        f"README.md does not say {phrase!r}, which the data in docs/results gives: "
        "quote the data, or update it from a new run of its command")


# -- the API reference ------------------------------------------------------------------------


def test_the_api_reference_has_a_page_for_every_public_module_and_name(tmp_path: Path) -> None:
    names = api_pages.write_pages(tmp_path)
    assert not [n for n in names if n.endswith("_kernels") or "._" in n]
    pages = {p.stem for p in tmp_path.glob("*.rst")} - {"index"}
    assert pages == set(names)
    top = (tmp_path / "robostereo.rst").read_text()
    import robostereo

    for name in robostereo.__all__:
        if name != "__version__":
            assert re.search(rf"`~[\w.]+\.{name}`", top), f"robostereo.{name} has no page"
