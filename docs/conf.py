"""Sphinx configuration of the documentation site: the Markdown pages of docs/ (myst-parser), the API
reference from the docstrings (autodoc, autosummary, numpydoc) and the published report (copied as it
is).  Build: ``python -m sphinx -W -n -b html docs docs/_build/html`` (the ``docs`` extra)."""

from __future__ import annotations

import importlib
import inspect
import os
import shutil
import sys

os.environ.setdefault("MPLBACKEND", "Agg")

from docutils import nodes
from sphinx.domains.python import PythonDomain

import gear_rattle  # the installed package documented (importing it switches JAX to float64)

project = "gear-rattle"
author = "gear-rattle developers"
copyright = "gear-rattle developers; model: de Souza, Caldas, Viana, Balthazar (2004)"
release = version = gear_rattle.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
templates_path = ["_templates"]
# the published report and its data are copied as they are (below), not parsed
exclude_patterns = ["_build", "report", "Thumbs.db", ".DS_Store"]

# MyST: headings get anchors (pages link to sections, e.g. golden.md#cases); $...$ stays literal text
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

# autodoc / autosummary: one page per module (docs/_templates/autosummary/module.rst), generated at build
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "undoc-members": True, "member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_preserve_defaults = False
add_module_names = False

# numpydoc: the docstrings' Parameters/Returns/Examples sections; class members are listed by autodoc
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# -n (nitpicky): every cross-reference must resolve, except to the types of the dependencies, whose
# inventories are not fetched (the build runs offline)
nitpicky = True
_EXTERNAL = r"(numpy|np|jax|jnp|jaxlib|flint|arb|acb|fmpz|scipy|diffrax|optimistix|optx|equinox|eqx|matplotlib|dask|distributed|zarr|mpmath|decimal|fractions|numbers|collections|concurrent|threading|typing|pathlib|os|io|argparse|json|math|functools|warnings|subprocess|types|enum|dataclasses)"
nitpick_ignore_regex = [
    (r"py:.*", _EXTERNAL + r"(\..*)?"),
    (
        r"py:.*",
        r"(ndarray|Array|ArrayLike|PyTree|Figure|Figure\..*|Axes|Path|Callable|Iterable|Iterator|Sequence|Mapping)",
    ),
]

html_theme = "pydata_sphinx_theme"
html_title = "gear-rattle"
html_theme_options = {
    "navigation_with_keys": False,
    "header_links_before_dropdown": 6,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
}
html_static_path: list[str] = []
html_copy_source = False
html_show_sourcelink = False

# ---------------------------------------------------------------------------------------------------------
# Cross-references in the docstrings.  They name objects the way the code reads: by folder (``mapimpl.orbit``
# is the installed ``gear_rattle.mapimpl.orbit``), relative to the module they are in (``kernel.run_blocks``
# in the engine's driver), or through a package that re-exports a name (``mapimpl.certified.certify_orbit``,
# documented where it is defined, ``mapimpl.certified.orbit``).  A reference that Sphinx does not resolve as
# written is looked up once more: the object is imported under those names and referred to where it is
# defined.  What still does not resolve (a name that does not exist, a private or undocumented one) is an
# error under -n.
_FOLDERS = ("core.", "mapimpl.", "reference.", "validation.")


def _candidates(target: str, module: str | None) -> list[str]:
    t = target.lstrip(".~")
    names = (
        ["gear_rattle." + t] if t.startswith(_FOLDERS) or t in ("core", "mapimpl", "reference", "validation") else []
    )
    parts = (module or "").split(".")
    names += [".".join(parts[:i]) + "." + t for i in range(len(parts), 0, -1) if parts[0] == "gear_rattle"]
    return names + [t]


def _canonical(name: str) -> str | None:
    """Where the object ``name`` is defined (``module.qualname``, a module's own name), or None."""
    parts = name.split(".")
    if parts[0] != "gear_rattle":
        return None
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        try:
            for attr in parts[i:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        if inspect.ismodule(obj):
            return obj.__name__
        mod, qual = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
        return f"{mod}.{qual}" if isinstance(mod, str) and isinstance(qual, str) else name
    return None


def _resolve(app, env, node, contnode):
    if node.get("refdomain") != "py":
        return None
    domain = env.get_domain("py")
    for name in _candidates(node.get("reftarget", ""), node.get("py:module")):
        canonical = _canonical(name)
        for target in (name, canonical) if canonical not in (None, name) else (canonical,):
            if target is None:
                continue
            ref = node.deepcopy()
            ref["reftarget"] = target
            ref.attributes.pop("refspecific", None)
            found = domain.resolve_xref(
                env, node.get("refdoc"), app.builder, node.get("reftype"), target, ref, contnode
            )
            if found is not None:
                return found
    # a name written as it reads in its context (``Track`` in a summary line shown on the package's page):
    # the one documented object whose full name ends with it
    target = node.get("reftarget", "").lstrip(".~")
    objtypes = domain.objtypes_for_role(node.get("reftype")) or []
    matches = [
        name
        for name, obj in domain.objects.items()
        if (name == target or name.endswith("." + target)) and obj.objtype in objtypes
    ]
    if len(matches) == 1:
        ref = node.deepcopy()
        ref["reftarget"] = matches[0]
        ref.attributes.pop("refspecific", None)
        return domain.resolve_xref(env, node.get("refdoc"), app.builder, node.get("reftype"), matches[0], ref, contnode)
    return None


class _PythonDomain(PythonDomain):
    """Python's domain, where a relative name (``:mod:`.orbit``` in ``mapimpl.certified.release``) that
    several objects end with means the nearest one, as a relative import would: the one in the same
    package (``mapimpl.certified.orbit``, not ``mapimpl.orbit``), else in the package above."""

    def find_obj(self, env, modname, classname, name, type, searchmode=0):
        matches = super().find_obj(env, modname, classname, name, type, searchmode)
        if len(matches) > 1 and modname:
            parts = modname.split(".")
            for i in range(len(parts), 0, -1):
                near = [m for m in matches if m[0].startswith(".".join(parts[:i]) + ".")]
                if near:
                    return near
        return matches


def _summaries_in_their_context(app, doctree):
    """A summary line of an autosummary table is its object's docstring: its references are read in the
    context of that object's module (``:mod:`.transients``` in the summary of ``validation.io`` is
    ``validation.io.transients``), not of the page that lists it."""
    from sphinx.addnodes import pending_xref
    from sphinx.ext.autosummary import autosummary_table

    for table in doctree.findall(autosummary_table):
        for row in table.findall(nodes.row):
            refs = list(row.findall(pending_xref))
            if not refs:
                continue
            item = refs[0].get("reftarget", "")
            module = item if item in sys.modules else item.rpartition(".")[0]
            for ref in refs[1:]:
                ref["py:module"] = module
                ref.attributes.pop("py:class", None)


def _factory_defaults(app, what, name, obj, options, signature, return_annotation):
    """A dataclass field with a default factory shows ``= ...`` (Python writes ``<factory>``, which is
    no expression: the signature would not parse)."""
    if signature and "<factory>" in signature:
        return signature.replace("<factory>", "..."), return_annotation
    return None


#: The command-line reference generated from the parsers at every build (not committed: .gitignore)
COMMANDS_PAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "reference", "commands.md")


def command_reference() -> str:
    """The page of every command's ``--help``, as ``gear-rattle COMMAND --help`` prints it (at 100
    columns), from the command line's own parser (:func:`gear_rattle.validation.cli.build_parser`)."""
    import argparse

    from gear_rattle.validation.cli import build_parser

    columns = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "100"
    try:
        parser = build_parser()
        subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parts = [
            "# Every command's help\n",
            "Generated from the command line's parsers when this site is built: what `gear-rattle --help` and "
            "`gear-rattle COMMAND --help` print.  The conventions they share -- the options, the output streams, "
            "the exit status: [the command line](cli.md).\n",
            "## `gear-rattle`\n",
            "```text\n" + parser.format_help() + "```\n",
        ]
        for name, sub in subs.choices.items():
            parts += [f"## `gear-rattle {name}`\n", "```text\n" + sub.format_help() + "```\n"]
        return "\n".join(parts)
    finally:
        if columns is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = columns


def _write_command_reference(app):
    text = command_reference()
    old = open(COMMANDS_PAGE, encoding="utf-8").read() if os.path.exists(COMMANDS_PAGE) else None
    if text != old:  # unchanged: Sphinx keeps the page it has read
        with open(COMMANDS_PAGE, "w", encoding="utf-8") as f:
            f.write(text)


def _copy_report(app, exception):
    """The published report (docs/report/: report.html, its figures and data) as it is, under report/."""
    if exception is None and app.builder.format == "html":
        src = os.path.join(app.srcdir, "report")
        shutil.copytree(src, os.path.join(app.outdir, "report"), dirs_exist_ok=True)


def setup(app):
    app.add_domain(_PythonDomain, override=True)
    app.connect("doctree-read", _summaries_in_their_context)
    app.connect("autodoc-process-signature", _factory_defaults)
    app.connect("missing-reference", _resolve)
    app.connect("builder-inited", _write_command_reference)
    app.connect("build-finished", _copy_report)
