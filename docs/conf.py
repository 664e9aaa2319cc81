"""Sphinx configuration: the Markdown pages of docs/ and an API reference from the docstrings.

``make docs`` builds it with warnings as errors (``sphinx-build -W``) into ``build/docs``.
"""

from __future__ import annotations

import sys
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

project = "pivot_ompl"
author = "pivot_ompl contributors"
copyright = "pivot_ompl contributors"  # noqa: A001 (Sphinx's name)

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build"]
templates_path = ["_templates"]

# API reference: one page per module, generated at build time under docs/api/
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {
    "members": True,
    "show-inheritance": True,
    "ignore-module-all": True,  # a package page documents its own names, not re-exports
}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_format = "short"
napoleon_google_docstring = True
napoleon_numpy_docstring = False

# A short name (Motion, Plan, Scene) is defined in several modules: a type named in a docstring
# links to the first one rather than failing the build.
suppress_warnings = ["ref.python"]
# A page may link Markdown outside docs/ (README.md, benchmarks/README.md) for readers of the
# repository; Sphinx does not build those files. tests/test_docs_examples.py checks that every
# link of the pages reaches an existing file and heading.
suppress_warnings.append("myst.xref_missing")

# Markdown pages: heading anchors for links such as cli.md#exit-codes
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

html_theme = "alabaster"
html_title = "pivot_ompl"

# ``python -m pivot_ompl`` runs the command line on import: the API reference skips it (a
# module marked as mocked is left out by autosummary), so no verb runs during the build.
_main = types.ModuleType("pivot_ompl.__main__")
_main.__sphinx_mock__ = True  # type: ignore[attr-defined]
sys.modules.setdefault("pivot_ompl.__main__", _main)
sys.modules.setdefault("pivot_ompl.cli.__main__", _main)

# Google-style "Attributes:" sections as field lists, so a field documented there and by its
# own ``#:`` comment is one object, not two.
napoleon_use_ivar = True
