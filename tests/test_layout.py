"""The package's structure: layers, import cycles, private names, module sizes, old paths.

Read from the source with :mod:`ast` (nothing of robostereo is imported for the graph),
so the rules hold for lazy imports inside functions too.  Run as a script to print the
import graph's figures::

    python tests/test_layout.py
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = SRC / "robostereo"
ROOT = SRC.parent

#: the layers, lowest first: a module may import modules of its own layer or lower ones
LAYERS: tuple[tuple[str, ...], ...] = (
    ("robostereo.errors", "robostereo._moved"),
    ("robostereo.geometry",),
    ("robostereo.io", "robostereo.datasets"),
    ("robostereo.matcher",),
    ("robostereo.simulation", "robostereo.evaluation", "robostereo.rig"),
    ("robostereo.robot",),
    ("robostereo.experiments", "robostereo.plots", "robostereo.batch",
     "robostereo.batch_inputs", "robostereo.batch_workers"),
    ("robostereo.cli",),
)
#: the application layer, which the library never imports
APPLICATION = ("robostereo.experiments", "robostereo.plots", "robostereo.batch",
               "robostereo.batch_inputs", "robostereo.batch_workers", "robostereo.cli")
#: the robot side's sub-packages, lowest first: each imports only its own or lower ones
ROBOT_LAYERS: tuple[tuple[str, ...], ...] = (
    ("robostereo.robot.arms", "robostereo.robot.capture", "robostereo.robot.handeye"),
    ("robostereo.robot.views",),
    ("robostereo.robot.planning", "robostereo.robot.importers"),
    ("robostereo.robot.simulated",),
)
#: modules (and sub-packages) that robot/ may hold directly, at most
MAX_ROBOT_ENTRIES = 8
#: lines a module may have at most (numba kernel modules excepted)
MAX_LINES = 600


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    """Every module of the package: dotted name -> file."""
    return {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _resolve(name: str, known: dict[str, Path]) -> str | None:
    """The robostereo module `name` refers to (itself, or the package holding it)."""
    while name and name not in known:
        name = name.rpartition(".")[0]
    return name or None


def imports(name: str, path: Path, known: dict[str, Path]) -> list[tuple[str, str, int]]:
    """``(module, imported name or '', line)`` for every robostereo import of one module.

    ``from robostereo.a import b`` counts as an import of ``robostereo.a.b`` when that is
    a module, else of ``robostereo.a`` with the name ``b``.  Relative imports are resolved.
    """
    tree = ast.parse(path.read_text(), str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: list[tuple[str, str, int]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("robostereo"):
                    mod = _resolve(alias.name, known)
                    if mod:
                        found.append((mod, "", node.lineno))
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            if not base.startswith("robostereo"):
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                if sub in known:
                    found.append((sub, "", node.lineno))
                else:
                    mod = _resolve(base, known)
                    if mod:
                        found.append((mod, alias.name, node.lineno))
    return found


def import_graph() -> dict[str, set[str]]:
    """module -> the robostereo modules it imports (package ``__init__`` edges included)."""
    known = modules()
    return {name: {m for m, _, _ in imports(name, path, known) if m != name}
            for name, path in known.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def layer(name: str) -> int | None:
    for rank, prefixes in enumerate(LAYERS):
        if any(name == p or name.startswith(p + ".") for p in prefixes):
            return rank
    return None


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    """``a -> b`` for each import of a higher layer (the package root excepted)."""
    bad = []
    for a, targets in graph.items():
        ra = layer(a)
        for b in sorted(targets):
            rb = layer(b)
            if ra is not None and rb is not None and rb > ra:
                bad.append(f"{a} -> {b}")
    return bad


# ------------------------------------------------------------------------------ tests


def test_every_module_has_a_layer() -> None:
    lost = [m for m in modules() if m != "robostereo" and layer(m) is None]
    assert lost == [], f"modules in no layer of LAYERS: {lost}"


def test_no_import_cycle() -> None:
    assert cycles(import_graph()) == []


def test_no_module_imports_a_higher_layer() -> None:
    assert upward_imports(import_graph()) == []


def test_the_library_never_imports_the_application_layer() -> None:
    graph = import_graph()
    bad = [f"{a} -> {b}" for a, targets in graph.items() for b in targets
           if a != "robostereo" and not a.startswith(APPLICATION)
           and b.startswith(APPLICATION)]
    assert bad == []


def test_no_module_imports_another_modules_private_names() -> None:
    known = modules()
    bad = [f"{name}:{line} imports {mod}.{imported}"
           for name, path in known.items()
           for mod, imported, line in imports(name, path, known)
           if imported.startswith("_") and not imported.startswith("__") and mod != name]
    assert bad == []


def test_robot_sub_packages_import_only_their_own_or_lower_ones() -> None:
    def rank(name: str) -> int | None:
        for r, prefixes in enumerate(ROBOT_LAYERS):
            if any(name == p or name.startswith(p + ".") for p in prefixes):
                return r
        return None

    bad = [f"{a} -> {b}" for a, targets in import_graph().items() for b in sorted(targets)
           if (ra := rank(a)) is not None and (rb := rank(b)) is not None and rb > ra]
    assert bad == []
    within = [f"{a} -> {b}" for a, targets in import_graph().items() for b in sorted(targets)
              if rank(a) == 0 and rank(b) == 0 and a.split(".")[2] != b.split(".")[2]]
    assert within == [], "arms, capture and handeye stand apart"


def test_robot_is_a_few_sub_packages_and_few_modules() -> None:
    robot = PACKAGE / "robot"
    packages = [p for p in robot.iterdir() if (p / "__init__.py").is_file()]
    entries = packages + [p for p in robot.glob("*.py") if p.name != "__init__.py"]
    assert len(packages) >= 3 and len(entries) <= MAX_ROBOT_ENTRIES, sorted(
        p.name for p in entries)
    lost = [m for m in modules() if m.startswith("robostereo.robot.")
            and not any(m == p or m.startswith(p + ".") for ps in ROBOT_LAYERS for p in ps)]
    assert lost == [], f"robot modules in no entry of ROBOT_LAYERS: {lost}"


def test_evaluation_is_a_package_with_nothing_left_at_the_top() -> None:
    assert (PACKAGE / "evaluation" / "__init__.py").is_file()
    assert sorted(p.name for p in PACKAGE.glob("evaluation*.py")) == []


def test_no_module_is_longer_than_the_limit_but_numba_kernels() -> None:
    long = {name: n for name, path in modules().items()
            if not name.endswith("_kernels")
            and (n := len(path.read_text().splitlines())) > MAX_LINES}
    assert long == {}


def test_every_public_function_and_class_is_in_its_modules_all() -> None:
    """The API reference documents ``__all__``: a public name left out is undocumented."""
    missing = []
    for name, path in modules().items():
        tree = ast.parse(path.read_text())
        listed: set[str] = set()
        for node in tree.body:
            if isinstance(node, ast.Assign) and any(
                    getattr(t, "id", None) == "__all__" for t in node.targets):
                try:
                    listed = set(ast.literal_eval(node.value))
                except ValueError:  # built, not literal (robostereo.robot)
                    listed = {n.name for n in tree.body
                              if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
        missing += [f"{name}.{n.name}" for n in tree.body
                    if isinstance(n, (ast.FunctionDef, ast.ClassDef))
                    and not n.name.startswith("_") and n.name not in listed]
    assert missing == []


def test_nothing_in_the_project_imports_a_moved_path() -> None:
    from robostereo._moved import MOVED

    bad = []
    for folder in ("src", "tests", "benchmarks"):
        for path in (ROOT / folder).rglob("*.py"):
            if path.name in ("_moved.py", "test_layout.py"):
                continue
            tree = ast.parse(path.read_text(), str(path))
            for node in ast.walk(tree):
                names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                         else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
                bad += [f"{path.relative_to(ROOT)}:{node.lineno} {n}"
                        for n in names if n in MOVED]
    assert bad == []


def _python(code: str) -> str:
    """Run `code` in a fresh interpreter (a module imports once per process); its stdout."""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


@pytest.mark.parametrize("old", sorted(__import__("robostereo._moved").
                                       _moved.MOVED))
def test_a_moved_path_still_imports_with_a_deprecation_warning(old: str) -> None:
    code = (
        "import importlib, warnings\n"
        "with warnings.catch_warnings(record=True) as w:\n"
        "    warnings.simplefilter('always')\n"
        f"    m = importlib.import_module({old!r})\n"
        "assert any(issubclass(x.category, DeprecationWarning) for x in w), w\n"
        "assert m.__all__ and all(hasattr(m, n) for n in m.__all__)\n"
        "print(len(m.__all__))\n"
    )
    assert int(_python(code)) > 0


def test_the_readme_api_lines_of_the_old_paths_still_work() -> None:
    code = (
        "import warnings\n"
        "warnings.simplefilter('ignore', DeprecationWarning)\n"
        "from robostereo.pipeline import match_stereo, MatchParameters\n"
        "from robostereo.triangulation import StereoCamera\n"
        "from robostereo.camera import EpipolarGeometry, load_camera_yaml, save_camera_yaml\n"
        "from robostereo.calibration import read_calibration\n"
        "from robostereo.robot.poses import SE3\n"
        "from robostereo.robot.geometry import GeneralEpipolarGeometry\n"
        "print('ok')\n"
    )
    assert _python(code).strip() == "ok"


if __name__ == "__main__":  # the figures for a note
    g = import_graph()
    print(f"{len(g)} modules, {sum(map(len, g.values()))} import edges")
    print(f"cycles: {cycles(g)}")
    ups = upward_imports(g)
    print(f"upward imports ({len(ups)}):", *ups, sep="\n  ")
    sizes = sorted(((len(p.read_text().splitlines()), n) for n, p in modules().items()),
                   reverse=True)
    print("largest:", ", ".join(f"{n} {k}" for k, n in sizes[:6]))
