"""Sphinx configuration of robostereo's documentation site.

Build it with ``python -m sphinx -W -b html docs docs/_build/html`` (``pip install -e
".[docs]"`` first).  The API pages are written at build time from the package's modules
(one page per subpackage, every public module on it), so a new module is documented
without anyone remembering to add it; the gallery's scripts in ``docs/examples`` run
during the build and their figures appear on the pages.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))
sys.path.insert(0, str(HERE / "_ext"))

import results_tables  # noqa: E402

import robostereo  # noqa: E402

project = "robostereo"
author = "robostereo developers"
copyright = "robostereo developers"
release = version = robostereo.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_copybutton",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# the generated fragments are included by the guide's pages, not pages of their own
exclude_patterns = ["_build", "_ext", "results", "examples/README.rst", "guide/_generated"]

autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"  # numpydoc's Parameters sections say the types
autosummary_generate = False
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]
# the guide includes README sections, whose in-page links point at README anchors
suppress_warnings = ["myst.xref_missing", "myst.header"]

html_theme = "pydata_sphinx_theme"
html_title = f"robostereo {release}"
html_theme_options = {"navigation_depth": 2, "show_toc_level": 2}

sphinx_gallery_conf = {
    "examples_dirs": str(HERE / "examples"),
    "gallery_dirs": str(HERE / "auto_examples"),
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
}

warnings.filterwarnings("ignore", category=UserWarning,
                        message="Matplotlib is currently using agg")

# -- API pages, written from the package ---------------------------------------------------

#: one page per subpackage (or group of top-level modules), in the order of the layers
API_PAGES: dict[str, tuple[str, str, tuple[str, ...]]] = {
    "top": ("robostereo", "The top-level names, the glossary and the layout.", ()),
    "geometry": ("robostereo.geometry", "Cameras, poses, rectifications, triangulation.",
                 ("robostereo.geometry",)),
    "io": ("robostereo.io", "Files in and out; scenes with ground truth.",
           ("robostereo.io", "robostereo.datasets")),
    "matcher": ("robostereo.matcher", "From a rectified pair to matched edge points.",
                ("robostereo.matcher",)),
    "simulation": ("robostereo.simulation", "The simulated camera.",
                   ("robostereo.simulation",)),
    "evaluation": ("Evaluation and rigs", "Scoring against ground truth; calibrated rigs.",
                   ("robostereo.evaluation", "robostereo.rig")),
    "robot": ("robostereo.robot", "Arms, captures, locating, hand-eye, planning.",
              ("robostereo.robot",)),
    "application": ("The application layer", "The thesis's experiments, figures, batches.",
                    ("robostereo.experiments", "robostereo.plots", "robostereo.batch",
                     "robostereo.batch_workers")),
    "errors": ("robostereo.errors", "The one error type and its checks.",
               ("robostereo.errors",)),
}


def _public_modules(prefix: str) -> list[str]:
    module = importlib.import_module(prefix)
    names = [prefix]
    if hasattr(module, "__path__"):
        for info in pkgutil.walk_packages(module.__path__, prefix + "."):
            if not any(part.startswith("_") for part in info.name.split(".")):
                names.append(info.name)
    return names


def _write_api_pages() -> None:
    listed = {n for _, _, prefixes in API_PAGES.values() for p in prefixes
              for n in _public_modules(p)}
    missing = sorted(set(_public_modules("robostereo")) - listed - {"robostereo"}
                     - set(_public_modules("robostereo.cli")))
    if missing:  # a new public module must find its page
        raise RuntimeError(f"docs/conf.py: API_PAGES does not list {missing}")
    out = HERE / "api"
    out.mkdir(exist_ok=True)
    index = ["API reference", "=============", "",
             "Generated from the docstrings (numpydoc); the command line is described in "
             "the :doc:`user guide <../guide/index>`.", "", ".. toctree::", "   :maxdepth: 1", ""]
    for page, (title, blurb, prefixes) in API_PAGES.items():
        index.append(f"   {page}")
        lines = [title, "=" * len(title), "", blurb, ""]
        if page == "top":
            lines += [".. automodule:: robostereo", "   :no-members:", "",
                      "The names ``from robostereo import ...`` gives, where each is "
                      "documented:", ""]
            for n in robostereo.__all__:
                obj = getattr(robostereo, n)
                if n != "__version__":
                    lines.append(f"* :py:obj:`{n} <{obj.__module__}.{n}>`")
            lines.append("")
        for prefix in prefixes:
            for name in _public_modules(prefix):
                is_package = hasattr(importlib.import_module(name), "__path__")
                lines += [name, "-" * len(name), "", f".. automodule:: {name}"]
                lines += ["   :no-members:", ""] if is_package else [""]
        text = "\n".join(lines) + "\n"
        path = out / f"{page}.rst"
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    (out / "index.rst").write_text("\n".join(index) + "\n")


_write_api_pages()
results_tables.write_all(HERE / "guide" / "_generated")
