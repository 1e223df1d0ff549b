"""Sphinx configuration of robostereo's documentation site.

Build it with ``python -m sphinx -W -b html docs docs/_build/html`` (``pip install -e
".[docs]"`` first).  Two parts are written at build time, so neither can fall behind
what it describes: the API reference, one page per public module of the package
(``_ext/api_pages.py``), and the results' tables and figures, from the benchmarks' data
files in ``docs/results`` (``_ext/results_tables.py``).  The gallery's scripts in
``docs/examples`` run during the build and their figures appear on the pages.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))
sys.path.insert(0, str(HERE / "_ext"))

import api_pages  # noqa: E402
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

api_pages.write_pages(HERE / "api")
results_tables.write_all(HERE / "guide" / "_generated")


def setup(app):
    """Sphinx's hook: numba's compiled kernels stay out of every API page."""
    app.connect("autodoc-skip-member", api_pages.skip_numba)
