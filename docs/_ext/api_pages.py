"""The API reference's pages, written from the package at every build.

One page per public module (``api/<dotted name>.rst``), so a new module is documented
without anyone listing it; the index groups the pages by sub-package.  Left out: the
numba kernels (``*_kernels`` modules: the Python beside them is their interface), private
modules and names (a leading ``_``) and the command line (``robostereo.cli``, described in
the user guide).  A package's page gives its docstring, its modules and, for each name
it exports, the page that documents it; the top page does the same for
``robostereo.__all__``.  :func:`write_pages` is called by ``docs/conf.py``.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
from pathlib import Path
from types import ModuleType

PACKAGE = "robostereo"
#: left out of the reference with all they hold: documented in the user guide
UNDOCUMENTED = ("robostereo.cli",)
#: the top-level modules that are no package, each with the group it is listed in
TOP_LEVEL = {
    "robostereo.errors": "robostereo",
    "robostereo.datasets": "robostereo.io",
    "robostereo.rig": "robostereo.evaluation",
    "robostereo.experiments": "application",
    "robostereo.plots": "application",
    "robostereo.batch": "application",
    "robostereo.batch_inputs": "application",
    "robostereo.batch_workers": "application",
}
#: the groups of the index, in the order of the layers (sub-packages follow their parent)
ORDER = ("robostereo", "robostereo.geometry", "robostereo.io", "robostereo.matcher",
         "robostereo.simulation", "robostereo.evaluation", "robostereo.robot", "application")
#: titles and summaries of the groups that are no package
TITLES = {"robostereo": ("The top level", "The one error type and its checks."),
          "application": ("The application layer", "The thesis's experiments, figures and "
                          "batches: they use the library, which never imports them.")}


def documented(name: str) -> bool:
    """Whether module ``name`` gets a page."""
    parts = name.split(".")
    return (not any(p.startswith("_") for p in parts) and not name.endswith("_kernels")
            and not any(name == u or name.startswith(u + ".") for u in UNDOCUMENTED))


def public_modules() -> list[str]:
    """Every module with a page, the package first."""
    root = importlib.import_module(PACKAGE)
    names = [PACKAGE] + [i.name for i in pkgutil.walk_packages(root.__path__, PACKAGE + ".")]
    return [n for n in names if documented(n)]


def is_package(module: ModuleType) -> bool:
    return hasattr(module, "__path__")


def summary(module: ModuleType) -> str:
    """The first paragraph of a module's docstring, on one line."""
    doc = (inspect.getdoc(module) or "").strip()
    return " ".join(doc.split("\n\n")[0].split())


def group_of(name: str, packages: set[str]) -> str:
    """The index group of module ``name``: its package, or for a top-level module the
    group :data:`TOP_LEVEL` gives it."""
    if name in packages:
        return name
    parent = name.rpartition(".")[0]
    if parent != PACKAGE:
        return parent
    if name not in TOP_LEVEL:
        raise RuntimeError(f"docs/_ext/api_pages.py: TOP_LEVEL does not say in which group of "
                           f"the API index the new top-level module {name} goes")
    return TOP_LEVEL[name]


def _rank(group: str) -> tuple[int, str]:
    top = next((o for o in sorted(ORDER, key=len, reverse=True)
                if group == o or group.startswith(o + ".")), None)
    return (ORDER.index(top) if top else len(ORDER), group)


def _defined_in(module: ModuleType, name: str) -> bool:
    """Whether ``name`` is bound at the top level of ``module``'s own source."""
    try:
        tree = ast.parse(inspect.getsource(module))
    except (OSError, TypeError):
        return False
    for node in tree.body:
        targets = []
        if isinstance(node, ast.Assign):
            targets = node.targets
        elif isinstance(node, ast.AnnAssign):
            targets = [node.target]
        elif isinstance(node, ast.FunctionDef | ast.ClassDef) and node.name == name:
            return True
        if any(isinstance(t, ast.Name) and t.id == name for t in targets):
            return True
    return False


def home(name: str, obj: object, modules: dict[str, ModuleType]) -> str:
    """The module whose page documents ``obj``, exported as ``name``: a documented module
    (no package) that lists it in its ``__all__``, where it is defined."""
    holders = [m for m, mod in modules.items() if not is_package(mod)
               and name in getattr(mod, "__all__", ()) and getattr(mod, name, None) is obj]
    defined = getattr(obj, "__module__", None)
    if (inspect.isclass(obj) or inspect.isfunction(obj)) and defined in holders:
        return defined
    own = [m for m in holders if _defined_in(modules[m], name)]
    if own or holders:
        return (own or holders)[0]
    raise RuntimeError(f"docs: {name} is documented on no page of the API reference (no "
                       "documented module lists it in its __all__)")


def _exports(package: ModuleType, modules: dict[str, ModuleType]) -> list[str]:
    """Lines listing a package's exported names by the page that documents them."""
    by_home: dict[str, list[str]] = {}
    for n in getattr(package, "__all__", ()):
        if n.startswith("__"):
            continue
        by_home.setdefault(home(n, getattr(package, n), modules), []).append(n)
    lines = []
    for h, names in by_home.items():
        refs = ", ".join(f":py:obj:`~{h}.{n}`" for n in names)
        lines.append(f"* :mod:`{h}`: {refs}")
    return lines


def _page(name: str, modules: dict[str, ModuleType]) -> str:
    module = modules[name]
    lines = [name, "=" * len(name), ""]
    if not is_package(module):
        lines += [f".. automodule:: {name}", ""]
        return "\n".join(lines)
    lines += [f".. automodule:: {name}", "   :no-members:", ""]
    inner = [m for m in modules if m.rpartition(".")[0] == name]
    if inner:
        lines += ["Modules", "-------", ""]
        lines += [f"* :mod:`{m}`: {summary(modules[m]).rstrip('.')}" for m in inner]
        lines.append("")
    exports = _exports(module, modules)
    if exports:
        what = ("``from robostereo import ...``" if name == PACKAGE
                else f"``from {name} import ...``")
        head = "Names and where they are documented"
        lines += [head, "-" * len(head), "", f"The names {what} gives, by the page that "
                  "documents each:", "", *exports, ""]
    return "\n".join(lines)


def write_pages(out: Path) -> list[str]:
    """Write ``out/index.rst`` and one page per public module; returns the modules.
    Pages whose text is unchanged are left alone, and pages of modules that are gone are
    removed."""
    names = public_modules()
    modules = {n: importlib.import_module(n) for n in names}
    packages = {n for n, m in modules.items() if is_package(m)}
    groups: dict[str, list[str]] = {}
    for n in names[1:]:
        groups.setdefault(group_of(n, packages), []).append(n)
    out.mkdir(parents=True, exist_ok=True)
    pages = {f"{n}.rst": _page(n, modules) + "\n" for n in names}
    index = ["API reference", "=============", "",
             "Generated from the docstrings (numpydoc), one page per public module. The numba "
             "kernels (the ``*_kernels`` modules, called through the Python beside them) and "
             "private helpers are left out; the command line is described in the "
             ":doc:`user guide <../guide/index>`.", "", ".. toctree::", "   :maxdepth: 1", "",
             f"   {PACKAGE}", ""]
    for g in sorted(groups, key=_rank):
        members = groups[g]
        title, blurb = TITLES.get(g) or (g, summary(modules[g]))
        index += [title, "-" * len(title), "", blurb, ""]
        index += [".. toctree::", "   :maxdepth: 1", ""]
        index += [f"   {m}" for m in members]
        index.append("")
    pages["index.rst"] = "\n".join(index)
    for old in out.glob("*.rst"):
        if old.name not in pages:
            old.unlink()
    for fname, text in pages.items():
        path = out / fname
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    return names


def skip_numba(app, what, name, obj, skip, options):
    """``autodoc-skip-member``: leave numba's compiled kernels out wherever they are."""
    if type(obj).__module__.startswith("numba."):
        return True
    return None
