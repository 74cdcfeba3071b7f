"""The project's documentation on the web page: ``docs/<name>.md`` rendered as HTML.

markdown-it-py, CommonMark with
tables; in the page's layout, with its charts and figures served beside it.

Routes (pages, not in the OpenAPI document):

- ``GET /docs/{name}``: the document as HTML: its first heading the page's title, every heading an ``id`` as GitHub
  makes it (so ``accuracy.md#the-rotation-scale-terms`` works here as there), its links to other documents turned
  into this route's (``free_motion.md#x`` -> ``/docs/free_motion#x``), its images and data files into
  ``/docs/charts/…`` and ``/docs/figures/…``; a link to a file of the repository outside ``docs/`` is shown as its
  path (the service does not serve the repository); each table scrolls in its own box;
- ``GET /docs/{name}.md``: the Markdown source, as written;
- ``/docs/charts/…``, ``/docs/figures/…``: the documents' charts and their data (static files);
- ``GET /redoc/redoc.standalone.js``: the vendored ReDoc bundle (``service/static/redoc``, kept verbatim) with the one
  image it would fetch from the network, Redocly's logo on its CDN, replaced by an empty ``data:`` image (ReDoc
  then hides it): the API reference loads nothing from outside the service;
- ``GET /favicon.ico``: the page's icon (``service/static/page/favicon.svg``).

The documents are read from the repository's ``docs/`` (where ``make serve`` runs), or from ``EPHEM_DOCS_DIR`` (the
Docker image's copy of it); an installed package without either serves ``docs/accuracy.md`` from its copy (``service/static/accuracy.md``, kept identical by
tests/service/test_http.py) and answers 404 for the others and for the charts.
"""
from __future__ import annotations

import html
import os
import pathlib
import re
import unicodedata
from functools import lru_cache

from fastapi import FastAPI
from fastapi.responses import Response
from fastapi.staticfiles import StaticFiles
from markdown_it import MarkdownIt

SERVICE = pathlib.Path(__file__).resolve().parent
#: the documentation: EPHEM_DOCS_DIR where set (the Docker image copies the repository's docs/ there), else the
#: repository's docs/ beside the service (absent from an installed package)
DOCS_DIR = pathlib.Path(os.environ.get("EPHEM_DOCS_DIR") or SERVICE.parent / "docs")
#: the copies an installed package carries, by document name
PACKAGED = {"accuracy": SERVICE / "static" / "accuracy.md"}
#: the folders of ``docs/`` served as files (the documents' charts, figures and their data)
ASSET_DIRS = ("charts", "figures")
_NAME = re.compile(r"[a-z0-9_]+")
#: the vendored ReDoc bundle, and what it would fetch from the network -> what it gets instead
REDOC_JS = SERVICE / "static" / "redoc" / "redoc.standalone.js"
REDOC_OFFLINE = {b'src:"https://cdn.redoc.ly/redoc/logo-mini.svg"': b'src:"data:,"'}
FAVICON = SERVICE / "static" / "page" / "favicon.svg"


@lru_cache(maxsize=1)
def redoc_offline() -> bytes:
    """The ReDoc bundle with its network images replaced (each replacement must find its text: a new ReDoc
    release that moves it fails here, not in a browser)."""
    js = REDOC_JS.read_bytes()
    for online, offline in REDOC_OFFLINE.items():
        if online not in js:
            raise RuntimeError(f"the vendored ReDoc no longer holds {online!r}: update REDOC_OFFLINE")
        js = js.replace(online, offline)
    return js


def doc_path(name: str) -> pathlib.Path | None:
    """The Markdown file of document ``name`` (``accuracy``), None if there is none."""
    if not _NAME.fullmatch(name):
        return None
    path = DOCS_DIR / f"{name}.md"
    if path.is_file():
        return path
    packaged = PACKAGED.get(name)
    return packaged if packaged is not None and packaged.is_file() else None


def slug(text: str, seen: dict[str, int]) -> str:
    """A heading's anchor as GitHub writes it: lower case, punctuation dropped (letters, digits, '-' and '_' kept),
    spaces as '-'; a repeated one gets '-1', '-2', ..."""
    base = "".join(ch for ch in text.strip().lower()
                   if ch in " -_" or unicodedata.category(ch)[0] in "LN").replace(" ", "-")
    n = seen.get(base, 0)
    seen[base] = n + 1
    return base if n == 0 else f"{base}-{n}"


def _href(href: str) -> str | None:
    """A document's link as the web page serves it; None for a file of the repository outside ``docs/``."""
    if re.match(r"^[a-z][a-z0-9+.-]*:", href, re.I) or href.startswith("#") or href.startswith("/"):
        return href
    path, hash_, fragment = href.partition("#")
    if path.startswith("../"):
        return None
    if path.endswith(".md") and "/" not in path:
        return f"/docs/{path[:-3]}" + (f"#{fragment}" if hash_ else "")
    if path.split("/", 1)[0] in ASSET_DIRS:
        return f"/docs/{href}"
    return None


_md = MarkdownIt("commonmark", {"html": False}).enable("table")


def _table_open(self, tokens, idx, options, env):
    return '<div class="table-scroll" tabindex="0">' + self.renderToken(tokens, idx, options, env)


def _table_close(self, tokens, idx, options, env):
    return self.renderToken(tokens, idx, options, env) + "</div>"


#: a table cell holding a number and nothing else (as a document writes one: 1.5, -3, 2e-9, 0.25)
_NUMBER = re.compile(r"[-+\u2212]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _td_open(self, tokens, idx, options, env):
    """A cell holding only a number takes class num: the stylesheet right-aligns it in a monospace font."""
    inline = tokens[idx + 1] if idx + 1 < len(tokens) else None
    if inline is not None and inline.type == "inline" and _NUMBER.fullmatch(inline.content.strip()):
        tokens[idx].attrJoin("class", "num")
    return self.renderToken(tokens, idx, options, env)


def _repo_link_open(self, tokens, idx, options, env):
    return f'<span class="repo-path" title="a file of the repository: {html.escape(tokens[idx].meta["href"])}">'


def _repo_link_close(self, tokens, idx, options, env):
    return "</span>"


_md.add_render_rule("table_open", _table_open)
_md.add_render_rule("table_close", _table_close)
_md.add_render_rule("td_open", _td_open)
_md.add_render_rule("repo_link_open", _repo_link_open)
_md.add_render_rule("repo_link_close", _repo_link_close)


@lru_cache(maxsize=64)
def _render_cached(text: str) -> tuple[str, str]:
    tokens = _md.parse(text)
    seen: dict[str, int] = {}
    title = ""
    drop = None
    for i, tok in enumerate(tokens):
        if tok.type == "heading_open":
            words = "".join(c.content for c in tokens[i + 1].children or () if c.type in ("text", "code_inline"))
            tok.attrSet("id", slug(words, seen))
            if tok.tag == "h1" and not title:
                title, drop = words, i          # the page's own <h1>
        elif tok.type == "inline":
            stack = []
            for child in tok.children or ():
                if child.type == "link_open":
                    target = _href(child.attrGet("href") or "")
                    stack.append(target is None)
                    if target is None:
                        child.type, child.meta = "repo_link_open", {"href": child.attrGet("href")}
                    else:
                        child.attrSet("href", target)
                elif child.type == "link_close" and stack and stack.pop():
                    child.type = "repo_link_close"
                elif child.type == "image":
                    target = _href(child.attrGet("src") or "")
                    if target is not None:
                        child.attrSet("src", target)
    if drop is not None:
        del tokens[drop:drop + 3]
    # a code block scrolls sideways on a phone: focusable, so a keyboard scrolls it too (axe's rule)
    return title, _md.renderer.render(tokens, _md.options, {}).replace("<pre>", '<pre tabindex="0">')


def render(text: str) -> tuple[str, str]:
    """(title, HTML) of a Markdown document: its first level-1 heading, and the rest rendered."""
    return _render_cached(text)


def install(app: FastAPI, page) -> None:
    """The documentation routes on ``app``; ``page(template, status, **context)`` renders the page's layout."""

    @app.get("/docs/{name}.md", include_in_schema=False)
    def doc_source(name: str):
        path = doc_path(name)
        if path is None:
            return page("doc.html", 404, title="No such document", body_html="",
                        problem={"title": "Not found", "status": 404,
                                 "detail": f"there is no document {name!r} (the documents: /docs/accuracy, …)"})
        return Response(path.read_bytes(), media_type="text/markdown; charset=utf-8",
                        headers={"content-disposition": f'inline; filename="{name}.md"'})

    @app.get("/docs/{name}", include_in_schema=False)
    def doc_page(name: str):
        path = doc_path(name)
        if path is None:
            return page("doc.html", 404, title="No such document", body_html="",
                        problem={"title": "Not found", "status": 404,
                                 "detail": f"there is no document {name!r} here (the documents are docs/*.md of the "
                                           "repository; an installed package carries docs/accuracy.md only)"})
        title, body = render(path.read_text(encoding="utf-8"))
        return page("doc.html", 200, title=title or name, body_html=body, source=f"/docs/{name}.md")

    @app.get("/redoc/redoc.standalone.js", include_in_schema=False)
    def redoc_js():
        return Response(redoc_offline(), media_type="text/javascript; charset=utf-8")

    @app.get("/favicon.ico", include_in_schema=False)
    def favicon():
        return Response(FAVICON.read_bytes(), media_type="image/svg+xml")

    for folder in ASSET_DIRS:
        app.mount(f"/docs/{folder}", StaticFiles(directory=DOCS_DIR / folder, check_dir=False),
                  name=f"docs-{folder}")
