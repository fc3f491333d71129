"""Sphinx configuration of the fecontact documentation site.

Build: ``sphinx-build -W -b html docs docs/_build/html`` (``pip install -e ".[docs]"``).
Every Markdown page under docs/ (and one folder down) is picked up by glob toctrees; the
benchmark pages are generated from ``benchmarks/results/*.md`` at each build; the gallery runs
``docs/examples/plot_*.py`` and every notebook (``*.ipynb``) is executed at build time.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
# the notebooks' kernels import the tree being documented too
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]
)
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # the examples' small dense systems

import fecontact  # noqa: E402

project = "fecontact"
author = "the fecontact authors"
copyright = "the fecontact authors, BSD-3-Clause"
version = release = fecontact.__version__

extensions = [
    "myst_nb",  # Markdown pages (MyST) and notebooks executed at build time
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = [
    "_build",
    "examples",
    "gallery/*.ipynb",
    "gallery/*.py",
    "**/.ipynb_checkpoints",
]
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3
# pages moved from a single README cite source files (``benchmarks/…``) as links and skip
# heading levels in tables of results; neither is an error of the site
suppress_warnings = ["myst.header", "myst.xref_missing"]

nb_execution_mode = "force"
nb_execution_timeout = 300
nb_execution_raise_on_error = True

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": False}

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
}

html_theme = "alabaster"
html_title = f"fecontact {release}"
html_static_path: list[str] = []


def benchmark_pages() -> None:
    """One page per ``benchmarks/results/*.md`` (with its pictures), written by the
    benchmark scripts: the validation and speed tables as measured, never retyped."""
    results = ROOT / "benchmarks" / "results"
    out = HERE / "validation" / "benchmarks"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    for picture in results.glob("*.png"):
        shutil.copy(picture, out / picture.name)
    for md in sorted(results.glob("*.md")):
        lines = md.read_text(encoding="utf-8").splitlines()
        titled = bool(lines) and lines[0].startswith("# ")
        title = lines[0] if titled else f"# {md.stem}"
        source = f"*Measured by the scripts in `benchmarks/`: `benchmarks/results/{md.name}`.*"
        body = "\n".join(lines[1:] if titled else lines)
        (out / md.name).write_text(f"{title}\n\n{source}\n\n{body}\n", encoding="utf-8")


benchmark_pages()


# -- docstrings ---------------------------------------------------------------------------
# The package's docstrings are plain text with RST literals (``x``) and roles (:func:`f`):
# ``*`` and ``|`` are multiplication, shapes and norms there, never emphasis or
# substitutions, and "name : meaning" lines hang their continuation by an indent.

_LITERAL = re.compile(r"(``.*?``|:[a-z:]+:`[^`]*`)")
_MARKUP = re.compile(r"(?<![\\*])\*(?!\*)|\|")


def _escape(text: str) -> str:
    parts = _LITERAL.split(text)
    return "".join(p if i % 2 else _MARKUP.sub(lambda m: "\\" + m.group(0), p) for i, p in
                   enumerate(parts))  # fmt: skip


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip()) if line.strip() else -1


def _plain_docstring(app, what, name, obj, options, lines) -> None:
    """Hanging indents become definition list items; markup characters are escaped."""
    out: list[str] = []
    in_code, code_indent = False, 0
    for i, line in enumerate(lines):
        if in_code and line.strip() and _indent(line) <= code_indent:
            in_code = False
        prev = out[-1] if out else ""
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        if not in_code and line.strip() and prev.strip():
            hangs = _indent(nxt) > _indent(line) and not line.lstrip().startswith(("- ", "* "))
            if hangs or _indent(line) < _indent(prev):
                out.append("")
        out.append(line if in_code else _escape(line))
        if line.rstrip().endswith("::"):
            in_code, code_indent = True, _indent(line)
    lines[:] = out


def setup(app) -> None:
    app.connect("autodoc-process-docstring", _plain_docstring)
